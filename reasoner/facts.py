"""Recorded fact sentences read with a rulebook's templates: data in, terms out, never code.

A recorded sentence becomes an `Atom` (functor and constants) that crosses into Prolog as a term
(DESIGN "Facts are data"). A sentence no template fits is an "unknown fact" finding, never fatal:
a hostile string ("X :- shell(...)") is just a sentence no template fits. Parsing is the costly
part of re-deriving a run's observations, so results are cached per rulebook.
"""
from __future__ import annotations

from typing import Any

from store import EventRef

from .engine import Rulebook
from .le.sentences import parse_fact
from .le.terms import Atom
from .model import Finding

_CACHE_LIMIT = 200_000


class FactReader:
    """Parses sentences for any number of rulebooks, remembering what it parsed."""

    def __init__(self) -> None:
        self._cache: dict[tuple[str, str], Atom | None] = {}

    def atom(self, rb: Rulebook, sentence: Any) -> Atom | None:
        if not isinstance(sentence, str):
            return None
        key = (rb.sha256, sentence)
        try:
            return self._cache[key]
        except KeyError:
            pass
        if len(self._cache) >= _CACHE_LIMIT:
            self._cache.clear()
        found = self._cache[key] = parse_fact(sentence, rb.document.templates)
        return found

    def pairs(self, rb: Rulebook, facts: list[tuple[Any, EventRef]],
              unknown: list[Finding] | None = None) -> list[tuple[Atom, EventRef]]:
        """The parsed facts, each with its evidence; each one that no template fits is appended
        to `unknown` as a finding."""
        out = []
        for sentence, evidence in facts:
            atom = self.atom(rb, sentence)
            if atom is not None:
                out.append((atom, evidence))
            elif unknown is not None:
                unknown.append(unknown_fact(sentence, evidence, rb))
        return out

    def atoms(self, rb: Rulebook, facts: list[tuple[Any, EventRef]],
              unknown: list[Finding] | None = None) -> list[Atom]:
        """The parsed facts alone (see pairs)."""
        return [atom for atom, _ in self.pairs(rb, facts, unknown)]

    def known(self, rb: Rulebook, sentences: list[str]) -> list[Atom]:
        """The sentences the rulebook can read, parsed; for sentences the reasoner wrote itself."""
        return [a for a in (self.atom(rb, s) for s in sentences) if a is not None]


def unknown_fact(sentence: Any, evidence: EventRef, rb: Rulebook) -> Finding:
    """The finding for a recorded sentence no template fits, cut to 200 characters: a hostile
    producer may write megabytes."""
    shown = sentence if isinstance(sentence, str) else repr(sentence)
    if len(shown) > 200:
        shown = shown[:200] + f"… ({len(shown)} characters)"
    return Finding("unknown fact", f"no template of {rb.name} fits the recorded sentence {shown!r}; it was not used",
                   (evidence,), fact=shown)


def walk_atoms(value: Any):
    """Every Atom inside a rule part (heads, bodies, negations, disjunctions, aggregates)."""
    if isinstance(value, Atom):
        yield value
        for arg in value.args:
            yield from walk_atoms(arg)
    elif isinstance(value, (list, tuple)):
        for item in value:
            yield from walk_atoms(item)
    elif hasattr(value, "__dataclass_fields__"):
        for name in value.__dataclass_fields__:
            yield from walk_atoms(getattr(value, name))


def plain_constants(values: Any) -> set:
    """The constants (str, int, float) among the arguments of atoms, and inside arithmetic."""
    out: set = set()
    stack = list(values)
    while stack:
        value = stack.pop()
        if isinstance(value, (str, int, float)) and not isinstance(value, bool):
            out.add(value)
        elif isinstance(value, (list, tuple)):
            stack.extend(value)
        elif hasattr(value, "args") and not isinstance(value, Atom):      # Expr
            stack.extend(value.args)
        elif hasattr(value, "items") and not isinstance(value, dict):     # ListTerm
            stack.extend(value.items)
    return out
