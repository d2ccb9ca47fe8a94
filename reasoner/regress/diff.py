"""What changed between two versions of a rulebook, rule by rule (the rule change report).

A rule is the same in both when its compiled head and body (so its LE wording and nesting), its
label ("HC 175") and its law are; it may have moved to another line. The rules left over are
paired into *changed* ones when they conclude the same sentence under the same label and their
wording is alike (difflib ratio at least SIMILAR), the closest pairs first; the rest are *added*
or *removed*. Scenarios and queries are not rules and are not compared: they do not decide a
verdict. Each change keeps the rule's index in its rulebook, so a proof that used it (a node's
`rule`) can be traced back to it.
"""
from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from difflib import SequenceMatcher
from typing import Any

from ..engine import Rulebook
from ..le.compile import atom_data, body_data
from ..le.terms import Rule

SIMILAR = 0.6


@dataclass(frozen=True)
class RuleVersion:
    """One rule as one rulebook states it: where (file, line, index) and its LE text."""

    book: str
    sha256: str
    index: int
    line: int
    text: str

    @property
    def where(self) -> str:
        return f"{self.book}:{self.line}"

    def to_json(self) -> dict[str, Any]:
        return {"file": self.book, "line": self.line, "text": self.text}


@dataclass(frozen=True)
class RuleChange:
    """A rule added, removed or changed between the old and the new rulebook."""

    kind: str                          # added, removed, changed
    label: str | None                  # "HC 175": the Highway Code rule it models, if labelled
    head: str                          # the sentence it concludes, as a template's functor
    old: RuleVersion | None
    new: RuleVersion | None

    @property
    def latest(self) -> RuleVersion:
        """The rule as the new rulebook states it, or as the old one did if it was removed."""
        version = self.new or self.old
        if version is None:
            raise ValueError(f"a {self.kind} rule change with neither version")
        return version

    @property
    def key(self) -> str:
        """A stable name for the change: what a flipped verdict is attributed to in JSON."""
        old = f"{self.old.sha256[:12]}#{self.old.index}" if self.old else "-"
        new = f"{self.new.sha256[:12]}#{self.new.index}" if self.new else "-"
        return f"{old}>{new}"

    def sentence(self) -> str:
        """The change as a reason: "HC 175 no longer has the rule ...", "HC 176 now reads ..."."""
        who = self.label or "the rulebook"
        old, new = self.old, self.new
        if self.kind == "added" and new is not None:
            return f'{who} now has the rule "{_one_line(new.text)}" ({new.where})'
        if self.kind == "removed" and old is not None:
            return f'{who} no longer has the rule "{_one_line(old.text)}" ({old.where})'
        if old is None or new is None:
            raise ValueError(f"a {self.kind} rule change without its rule's versions")
        return (f'{who} now reads "{_one_line(new.text)}" ({new.where}), '
                f'was "{_one_line(old.text)}" ({old.where})')

    def to_json(self) -> dict[str, Any]:
        return {"key": self.key, "kind": self.kind, "label": self.label, "concludes": self.head,
                "old": self.old.to_json() if self.old else None, "new": self.new.to_json() if self.new else None}


@dataclass(frozen=True)
class RulebookDiff:
    """Two rulebooks that answered the same stages, and the rules that differ between them."""

    stages: tuple[str, ...]
    old_name: str
    old_sha256: str
    new_name: str
    new_sha256: str
    changes: tuple[RuleChange, ...]

    def to_json(self) -> dict[str, Any]:
        return {"stages": list(self.stages),
                "old": {"name": self.old_name, "sha256": self.old_sha256},
                "new": {"name": self.new_name, "sha256": self.new_sha256},
                "changes": [c.to_json() for c in self.changes]}


def diff_rulebooks(old: Rulebook, new: Rulebook, stages: tuple[str, ...] = (),
                   names: dict[str, str] | None = None) -> RulebookDiff:
    """The rules added, removed and changed from `old` to `new`, in the order of their lines.
    `names`: sha256 -> the file to call a rulebook by (the engine keeps the name it was first
    loaded under, which may be another copy of the same text)."""
    names = names or {}
    left = _unmatched(old, new)
    right = _unmatched(new, old)
    pairs = _pairs(old, new, left, right)
    paired_old = {i for i, _ in pairs}
    paired_new = {j for _, j in pairs}
    changes = [_change("changed", old, i, new, j, names) for i, j in pairs]
    changes += [_change("removed", old, i, None, None, names) for i in left if i not in paired_old]
    changes += [_change("added", None, None, new, j, names) for j in right if j not in paired_new]
    changes.sort(key=lambda c: (c.latest.line, c.kind))
    return RulebookDiff(stages, names.get(old.sha256, old.name), old.sha256, names.get(new.sha256, new.name),
                        new.sha256, tuple(changes))


def _key(rule: Rule) -> tuple:
    """What makes two rules the same rule: wording and nesting (as compiled, so not the line),
    label and law."""
    return repr(atom_data(rule.head)), repr(body_data(rule.body)), rule.label, rule.law


def _unmatched(mine: Rulebook, theirs: Rulebook) -> list[int]:
    """Indexes of `mine`'s rules with no identical rule left in `theirs` (duplicates counted)."""
    left: dict[tuple, int] = defaultdict(int)
    for rule in theirs.document.rules:
        left[_key(rule)] += 1
    out = []
    for i, rule in enumerate(mine.document.rules):
        key = _key(rule)
        if left[key]:
            left[key] -= 1
        else:
            out.append(i)
    return out


def _pairs(old: Rulebook, new: Rulebook, left: list[int], right: list[int]) -> list[tuple[int, int]]:
    """Removed and added rules that are one rule changed: same conclusion, same label, alike."""
    scored = []
    for i in left:
        a = old.document.rules[i]
        for j in right:
            b = new.document.rules[j]
            if a.head.functor == b.head.functor and a.label == b.label:
                ratio = SequenceMatcher(None, _one_line(a.text), _one_line(b.text)).ratio()
                if ratio >= SIMILAR:
                    scored.append((-ratio, abs(a.line - b.line), i, j))
    taken_old, taken_new, out = set(), set(), []
    for _, _, i, j in sorted(scored):
        if i not in taken_old and j not in taken_new:
            taken_old.add(i)
            taken_new.add(j)
            out.append((i, j))
    return out


def _version(rb: Rulebook | None, index: int | None, names: dict[str, str]) -> RuleVersion | None:
    if rb is None or index is None:
        return None
    rule = rb.document.rules[index]
    return RuleVersion(names.get(rb.sha256, rb.name), rb.sha256, index, rule.line, rule.text)


def _change(kind: str, old: Rulebook | None, i: int | None, new: Rulebook | None, j: int | None,
            names: dict[str, str]) -> RuleChange:
    book, index = (old, i) if old is not None else (new, j)
    if book is None or index is None:
        raise ValueError(f"a {kind} rule with no rulebook to read it from")
    rule = book.document.rules[index]
    return RuleChange(kind, rule.label, rule.head.functor, _version(old, i, names), _version(new, j, names))


def _one_line(text: str) -> str:
    return " ".join(text.split())
