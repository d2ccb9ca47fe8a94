"""The compiled form of LE sentences: plain data that crosses into Prolog as terms, never text.

A sentence is an `Atom` (a template's functor and one argument per slot).  Arguments are
constants (str, int, float), variables (`Var`), lists (`ListTerm`), arithmetic (`Expr`) or, for a
`that` slot, a whole sentence (`Atom`).  A rule's body is a list of `Cond`s joined by `and`;
a `Cond` is a sentence, a negation, a disjunction, `for all cases in which`, or an aggregate.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

if TYPE_CHECKING:   # for the annotations only: both import this module
    from .sentences import Vocabulary
    from .templates import Template


@dataclass(frozen=True)
class Var:
    """An LE variable, named as the rule names it ("vehicle", "other vehicle", "X")."""

    name: str
    label: str = field(default="", compare=False)     # as introduced: "number X", "other vehicle"


@dataclass(frozen=True)
class ListTerm:
    items: tuple = ()


@dataclass(frozen=True)
class Expr:
    """Arithmetic: `op` is one of + - * / (binary) or `neg` (unary minus)."""

    op: str
    args: tuple = ()


Arg = object          # Var | str | int | float | ListTerm | Expr | Atom


@dataclass(frozen=True)
class Atom:
    """A sentence instance: the template's functor and one argument per slot."""

    functor: str
    args: tuple = ()


@dataclass(frozen=True)
class Aggregate:
    """`R is the sum of each E such that C` (kind sum/max/min), `R is a collection of E where C`
    (kind bag), `R is a set of E where C` (kind set)."""

    kind: str
    result: Arg
    each: Arg
    body: tuple


@dataclass(frozen=True)
class Cond:
    """One condition.  Exactly one field is set: a sentence (`atom`), `it is not the case that`
    a block (`negated`), a disjunction of blocks (`any_of`), `for all cases in which` a block
    `it is the case that` a block (`forall`), or an aggregate."""

    atom: Atom | None = None
    negated: tuple | None = None
    any_of: tuple | None = None          # tuple of blocks (each a tuple of Cond)
    forall: tuple | None = None          # (cases block, then block)
    aggregate: Aggregate | None = None
    line: int = field(default=0, compare=False)

    @property
    def kind(self) -> str:
        for k in ("atom", "negated", "any_of", "forall", "aggregate"):
            if getattr(self, k) is not None:
                return k
        return "true"


@dataclass
class Rule:
    """A rule (or fact, with an empty body) with where it came from and what law it models."""

    head: Atom
    body: list
    line: int
    label: str | None = None     # e.g. "HC 176", from a `% HC 176: ...` comment above the rule
    law: str | None = None       # e.g. "RTA 1988 s.36; TSRGD 2016 Sch 14 Pts 1 and 4"
    text: str = ""
    section: str = "kb"          # kb (a knowledge base), ontology, or scenario:<name>


@dataclass
class Query:
    name: str
    body: list
    line: int
    text: str = ""


@dataclass
class Scenario:
    name: str
    rules: list
    line: int


class TemplateTable(dict[str, "Template"]):
    """Templates by functor (a second template with the same functor and another arity is
    filed under `functor/arity`); it also caches the matcher built from it."""

    _vocabulary: Vocabulary | None = None


@dataclass
class Document:
    """A parsed LE document: templates by functor, the knowledge base, scenarios and queries."""

    file: str
    templates: TemplateTable = field(default_factory=TemplateTable)    # functor (or functor/arity) -> Template
    rules: list = field(default_factory=list)
    scenarios: dict = field(default_factory=dict)    # name -> Scenario
    queries: dict = field(default_factory=dict)      # name -> Query
    target: str | None = None
    kb_names: list = field(default_factory=list)
    warnings: list = field(default_factory=list)     # LEWarning
    unreadable_queries: dict = field(default_factory=dict)   # name -> LEError (asking it raises that)

    def template_for(self, functor: str, arity: int):
        """The declared (or built-in) template that compiles to functor/arity, if any."""
        t = self.templates.get(functor)
        if t is not None and t.arity == arity:
            return t
        t = self.templates.get(f"{functor}/{arity}")
        if t is not None:
            return t
        return _builtin(functor, arity)


_BUILTINS: dict | None = None


def _builtin(functor: str, arity: int):
    """The built-in template of functor/arity (builtins.py imports templates, loaded on first use)."""
    global _BUILTINS
    if _BUILTINS is None:
        from .builtins import BUILTIN_BY_KEY
        _BUILTINS = BUILTIN_BY_KEY
    return _BUILTINS.get((functor, arity))
