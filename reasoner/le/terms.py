"""The compiled form of LE sentences: plain data that crosses into Prolog as terms, never text.

A sentence is an `Atom` (a template's functor and one argument per slot).  Arguments are
constants (str, int, float), variables (`Var`), lists (`ListTerm`), arithmetic (`Expr`) or, for a
`that` slot, a whole sentence (`Atom`).  A rule's body is a list of `Cond`s joined by `and`;
a `Cond` is a sentence, a negation, a disjunction, `for all cases in which`, or an aggregate.
The document these make up, with its templates, is parsed.py's `Document`: this module imports
nothing of the LE reader, so that every part of it can import it.
"""
from __future__ import annotations

from dataclasses import dataclass, field


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
