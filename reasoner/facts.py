"""Recorded fact sentences read with a rulebook's templates: data in, terms out, never code.

A recorded sentence becomes an `Atom` (functor and constants) that crosses into Prolog as a term
(DESIGN "Facts are data"). A sentence no template fits is an "unknown fact" finding, never fatal:
a hostile string ("X :- shell(...)") is just a sentence no template fits. Parsing is the costly
part of re-deriving a run's observations, so results are cached per rulebook.
"""
from __future__ import annotations

import re
from typing import Any

from store import EventRef

from .engine import Rulebook
from .le.sentences import parse_fact
from .le.terms import Atom
from .model import Finding

_CACHE_LIMIT = 200_000


class FactReader:
    """Parses sentences for any number of rulebooks, remembering what it parsed.

    Sentences that differ only in their whole numbers ("173 has speed of 23", "174 has speed of
    31") are parsed once, as their *skeleton* (each such number replaced by a placeholder number),
    and the numbers put back in the atom's places. A skeleton is used only where that gives what
    parsing the sentence gives: each placeholder lands whole in one argument, and a number that
    is among the own words of one of the rulebook's templates stays as it is (where "section 87"
    is a template's words, "87" is no placeholder: the template still fits the skeleton, and
    only its arguments are placeholders)."""

    def __init__(self) -> None:
        self._cache: dict[tuple[str, str], Atom | None] = {}
        self._skeletons: dict[tuple[str, str], Atom | None] = {}
        self._numbered: dict[str, frozenset[str]] = {}     # rulebook sha256 -> its templates' number words

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
        found = self._from_skeleton(rb, sentence)
        if found is None:
            found = parse_fact(sentence, rb.document.templates)
        self._cache[key] = found
        return found

    def _from_skeleton(self, rb: Rulebook, sentence: str) -> Atom | None:
        """The sentence's atom made from its skeleton's, or None (then it is parsed as it is)."""
        skeleton, numbers = _skeleton(sentence, self._number_words(rb))
        if not numbers:
            return None
        key = (rb.sha256, skeleton)
        try:
            shaped = self._skeletons[key]
        except KeyError:
            if len(self._skeletons) >= _CACHE_LIMIT:
                self._skeletons.clear()
            shaped = self._skeletons[key] = parse_fact(skeleton, rb.document.templates)
        return _filled(shaped, numbers) if shaped is not None else None

    def _number_words(self, rb: Rulebook) -> frozenset[str]:
        """Every run of digits in the templates' own words ("5", "6" of "paragraph 5(6)"), as
        written and as its number reads."""
        found = self._numbered.get(rb.sha256)
        if found is None:
            runs = {run for template in rb.document.templates.values() for part in template.parts
                    if isinstance(part, str) for run in re.findall(r"[0-9]+", part)}
            found = self._numbered[rb.sha256] = frozenset(runs | {str(int(run)) for run in runs})
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


_PLACEHOLDER = 7_306_000_000_000_000   # the first placeholder number; a sentence holding one is parsed as it is
_PLACEHOLDER_TEXT = str(_PLACEHOLDER)[:6]   # a text argument holding it may hold a placeholder
_MAX_DIGITS = 15


def _skeleton(sentence: str, kept: frozenset[str] = frozenset()) -> tuple[str, list[int]]:
    """The sentence with each whole number word (no sign, no leading zero, at most _MAX_DIGITS
    digits, not in `kept`: a template's own words) replaced by a placeholder number, and the
    numbers in order; no numbers where the sentence has none, or holds a word that could be a
    placeholder."""
    words = sentence.split(" ")
    numbers: list[int] = []
    for i, word in enumerate(words):
        if word.isdigit() and word.isascii():
            if len(word) > _MAX_DIGITS:          # as long as a placeholder: parsed as it is
                return sentence, []
            if (word[0] == "0" and len(word) > 1) or word in kept:
                continue
            words[i] = str(_PLACEHOLDER + len(numbers))
            numbers.append(int(word))
    return (" ".join(words), numbers) if numbers else (sentence, [])


def _filled(atom: Atom, numbers: list[int]) -> Atom | None:
    """The skeleton's atom with its numbers put back: None unless every argument is a plain
    constant and each placeholder is one whole argument, once."""
    top = _PLACEHOLDER + len(numbers)
    args, placed = [], []
    for arg in atom.args:
        kind = type(arg)
        if kind is int and _PLACEHOLDER <= arg < top:
            args.append(numbers[arg - _PLACEHOLDER])
            placed.append(arg)
        elif kind is int or kind is float or (kind is str and _PLACEHOLDER_TEXT not in arg):
            args.append(arg)
        else:
            return None
    return Atom(atom.functor, tuple(args)) if sorted(placed) == list(range(_PLACEHOLDER, top)) else None


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
