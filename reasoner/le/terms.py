"""The compiled form of LE sentences: plain data that crosses into Prolog as terms, never text."""
from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class Var:
    """An LE variable, named as the rule names it ("vehicle", "other vehicle")."""

    name: str


Arg = Var | str | int | float


@dataclass(frozen=True)
class Atom:
    """A sentence instance: the template's functor and one argument per slot."""

    functor: str
    args: tuple[Arg, ...]


@dataclass(frozen=True)
class Cond:
    """A condition: a positive sentence, or `it is not the case that` a block of conditions."""

    atom: Atom | None = None
    negated: tuple["Cond", ...] | None = None


@dataclass
class Rule:
    """A rule (or fact, with an empty body) with where it came from and what law it models."""

    head: Atom
    body: list[Cond]
    line: int
    label: str | None = None     # e.g. "HC 176", from a `% HC 176: ...` comment above the rule
    law: str | None = None       # e.g. "RTA 1988 s.36; TSRGD 2016 Sch 14 Pts 1 and 4"
    text: str = ""


@dataclass
class Document:
    """A parsed LE document: its templates by functor and its knowledge base."""

    file: str
    templates: dict = field(default_factory=dict)    # functor -> Template
    rules: list[Rule] = field(default_factory=list)
