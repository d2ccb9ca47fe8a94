"""LE templates: declaring sentence shapes, matching sentences to them, rendering them back.

A template such as `*a vehicle* has *a colour* light` gives the Prolog functor `has_light`
(the words outside the slots joined by `_`, as the reference implementation names them) and
an argument per slot.  Matching is how both rules and scenario facts become terms, and
rendering is how terms become English again, so both directions live here.
"""
from __future__ import annotations

import re
from dataclasses import dataclass

SLOT = re.compile(r"\*\s*(an?|the)\s+([^*]+?)\s*\*")


@dataclass(frozen=True)
class Slot:
    """A place in a template, named by its type (`vehicle`, `colour`)."""

    type: str


@dataclass(frozen=True)
class Template:
    """One declared sentence shape: literal words and slots, in order."""

    parts: tuple[str | Slot, ...]

    @property
    def functor(self) -> str:
        return "_".join(p for p in self.parts if isinstance(p, str))

    @property
    def arity(self) -> int:
        return sum(isinstance(p, Slot) for p in self.parts)

    def literal_count(self) -> int:
        return sum(isinstance(p, str) for p in self.parts)


def parse_template(text: str) -> Template:
    """Parse `*a vehicle* has *a colour* light.` into its words and slots."""
    text = text.strip().rstrip(".").strip()
    parts: list[str | Slot] = []
    pos = 0
    for m in SLOT.finditer(text):
        parts.extend(text[pos:m.start()].split())
        parts.append(Slot(m.group(2).strip()))
        pos = m.end()
    parts.extend(text[pos:].split())
    return Template(tuple(parts))


def match(template: Template, words: list[str]) -> list[list[str]] | None:
    """Split `words` into slot fillers (each one or more words), or None if it does not fit."""
    return _match(template.parts, 0, words, 0, [])


def _match(parts, i, words, j, fillers):
    if i == len(parts):
        return fillers if j == len(words) else None
    part = parts[i]
    if isinstance(part, str):
        if j < len(words) and words[j].lower() == part.lower():
            return _match(parts, i + 1, words, j + 1, fillers)
        return None
    for end in range(j + 1, len(words) + 1):   # shortest filler first
        found = _match(parts, i + 1, words, end, fillers + [words[j:end]])
        if found is not None:
            return found
    return None


def render(template: Template, args: list[str]) -> str:
    """Fill the template's slots with already-rendered arguments."""
    it = iter(args)
    return " ".join(next(it) if isinstance(p, Slot) else p for p in template.parts)
