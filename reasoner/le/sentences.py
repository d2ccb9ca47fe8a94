"""Turning one LE sentence into an Atom with the document's templates.

Shared by rules (where `a X` introduces and `the X` refers to a variable) and by scenario
facts from events (where every filler is a constant): facts are parsed as data, so a hostile
fact can at worst fail to match a template.
"""
from __future__ import annotations

import re

from .errors import LEError
from .templates import Template, match
from .terms import Arg, Atom, Var

NUMBER = re.compile(r"-?\d+(\.\d+)?$")


def words_of(sentence: str) -> list[str]:
    return sentence.strip().rstrip(".").split()


def best_match(templates: dict[str, Template], words: list[str]):
    """The template that fits with the most literal words; ties between templates are ambiguous."""
    fits = [(t.literal_count(), t, f) for t in templates.values() if (f := match(t, words))]
    if not fits:
        return None
    fits.sort(key=lambda x: -x[0])
    if len(fits) > 1 and fits[0][0] == fits[1][0]:
        names = ", ".join(x[1].functor for x in fits[:2])
        raise ValueError(f"ambiguous sentence: it fits the templates {names}")
    return fits[0][1], fits[0][2]


def constant(words: list[str]) -> Arg:
    text = " ".join(words)
    if NUMBER.match(text):
        return float(text) if "." in text else int(text)
    return text


def rule_arg(words: list[str], scope: set[str]) -> Arg:
    """`a vehicle` introduces a variable, `the vehicle` refers to one; anything else is a constant."""
    first = words[0].lower()
    if first in ("a", "an") and len(words) > 1:
        name = " ".join(words[1:])
        scope.add(name)
        return Var(name)
    if first == "the" and " ".join(words[1:]) in scope:
        return Var(" ".join(words[1:]))
    return constant(words)


def parse_rule_sentence(text: str, templates, scope: set[str], file: str, line: int, col: int) -> Atom:
    words = words_of(text)
    try:
        found = best_match(templates, words)
    except ValueError as exc:
        raise LEError(str(exc), file, line, col, "reword it or make the templates distinct") from None
    if not found:
        raise LEError(f"no template fits: {text.strip()!r}", file, line, col,
                      "declare it under `the templates are:`")
    template, fillers = found
    return Atom(template.functor, tuple(rule_arg(f, scope) for f in fillers))


def parse_fact(text: str, templates) -> Atom | None:
    """A scenario fact as a ground Atom, or None when no template fits (an unknown fact)."""
    words = words_of(text)
    if not words:
        return None
    try:
        found = best_match(templates, words)
    except ValueError:
        return None
    if not found:
        return None
    template, fillers = found
    return Atom(template.functor, tuple(constant(f) for f in fillers))
