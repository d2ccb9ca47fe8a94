"""Why a verdict or a decision changed: the changed rules that the two proofs went through.

A proof tree (DESIGN "Proof trees") names at each node the rule it tried (`rule`: the rule's index
in the rulebook whose sha256 the stage's proof carries), whether it held (`proved`) or not
(`failed`), and it keeps the attempts under a negation ("it is not the case that ..."), so a
removed exception shows in the old proof as a rule that held. A change is attributed to the
changed rules that appear in either proof, those that held in one of them first: a rule that was
only tried and failed in both is named only when no changed rule held in either.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterable, Mapping

from .diff import RuleChange, RulebookDiff

Used = dict[tuple[str, int], bool]          # (rulebook sha256, rule index) -> held in some node


@dataclass(frozen=True)
class Trees:
    """The proof trees of one stage, with the sha256 of the rulebook whose rules they index."""

    rulebook: str | None
    trees: tuple[Mapping[str, Any], ...]


def used_rules(proofs: Iterable[Trees]) -> Used:
    """Every rule a proof went through, and whether it held there."""
    used: Used = {}
    for proof in proofs:
        if proof.rulebook is None:
            continue
        for tree in proof.trees:
            _walk(tree, proof.rulebook, used)
    return used


def _walk(node: Mapping[str, Any], sha: str, used: Used) -> None:
    stack = [node]
    while stack:
        item = stack.pop()
        rule = item.get("rule")
        if isinstance(rule, int) and not isinstance(rule, bool):
            key = (sha, rule)
            used[key] = used.get(key, False) or item.get("status") == "proved"
        stack.extend(item.get("children") or ())


def attribute(diffs: Iterable[RulebookDiff], used: Used) -> tuple[RuleChange, ...]:
    """The changed rules the proofs used: those that held somewhere, else those only tried."""
    held: list[RuleChange] = []
    tried: list[RuleChange] = []
    for diff in diffs:
        for change in diff.changes:
            marks = [used[k] for k in _keys(change) if k in used]
            if not marks:
                continue
            (held if any(marks) else tried).append(change)
    return tuple(dict.fromkeys(held or tried))


def _keys(change: RuleChange) -> list[tuple[str, int]]:
    return [(v.sha256, v.index) for v in (change.old, change.new) if v is not None]


def reasons(changes: tuple[RuleChange, ...], diffs: Iterable[RulebookDiff]) -> tuple[str, ...]:
    """The reasons in words; when no changed rule is in either proof, say which rulebooks differ."""
    if changes:
        return tuple(dict.fromkeys(c.sentence() for c in changes))
    differing = [d for d in diffs if d.changes]
    if not differing:
        return ("the rules are the same; the judgement differs in what the rulebooks were given",)
    books = "; ".join(f"{d.old_name} -> {d.new_name} ({len(d.changes)} rule(s) differ)" for d in differing)
    return (f"no changed rule appears in either proof; the rulebooks differ: {books}",)
