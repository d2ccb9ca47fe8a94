"""A regression in words, as `gaps regress` prints it: the rule change report first, then per run
what changed and why, then the tally. Lines only; the command escapes them for the terminal."""
from __future__ import annotations

from pathlib import Path
from typing import Iterator

from .regression import CaseResult, Change, Regression
from .diff import RuleChange, RulebookDiff

WHAT = {"new": "new incident", "gone": "incident gone", "verdict": "verdict flipped", "rule": "rule changed",
        "penalty": "penalty changed", "liability": "liability changed", "decision": "decision changed"}
PLURAL = {"new": "new incidents", "gone": "incidents gone", "verdict": "verdicts flipped", "rule": "rules changed",
          "penalty": "penalties changed", "liability": "liabilities changed", "decision": "decisions changed"}


def lines(result: Regression) -> Iterator[str]:
    """The whole report."""
    yield from rule_change_report(result)
    for unused in result.unused:
        yield f"Not used: {unused} (no stage takes it: the stages it defines are answered by a rulebook before it)"
    for run in result.runs:
        changed = run.changed()
        yield (f"Run {run.run}: {len(run.incidents)} incident(s) and {len(run.decisions)} recorded decision(s) "
               f"judged; {len(changed)} changed")
        for problem in run.problems:
            yield f"  note: {problem}"
        for case in changed:
            yield from _case(case)
    yield tally(result)


def rule_change_report(result: Regression) -> Iterator[str]:
    """Per pair of rulebooks compared: each added, removed or changed rule with the changes it caused."""
    for diff in result.diffs:
        if not diff.changes:
            continue
        yield (f"Rule changes, {diff.old_name} -> {diff.new_name} (stage {', '.join(diff.stages)}): "
               f"{len(diff.changes)} rule(s)")
        shown = diff.changes
        if Path(diff.old_name).name != Path(diff.new_name).name:
            # another rulebook answers the stage now (stages.py): every rule one has and the other
            # lacks differs; only those that changed something are worth reading here (--json has all)
            shown = tuple(c for c in diff.changes if result.flipped_by(c))
        if len(shown) < len(diff.changes):
            yield (f"  the stage is now answered by another rulebook; {len(diff.changes) - len(shown)} differing "
                   "rule(s) that changed nothing are left out (--json lists them)")
        for change in shown:
            yield from _rule(change, result)
    if result.diffs and not any(d.changes for d in result.diffs):
        yield "Rule changes: none (the rulebooks differ only outside their rules: templates, scenarios, queries)"


def _rule(change: RuleChange, result: Regression) -> Iterator[str]:
    where = " -> ".join(v.where for v in (change.old, change.new) if v is not None)
    yield f"  {change.kind} {change.label or '(no label)'} {where}"
    old, new = change.old, change.new
    if old is not None and new is not None and change.kind == "changed":
        yield from _text("was: ", old.text)
        yield from _text("now: ", new.text)
    else:
        yield from _text("", change.latest.text)
    flipped = result.flipped_by(change)
    for case, ch in flipped:
        yield f"      -> {case.run} {case.id}: {WHAT[ch.kind]}, {from_to(ch)}"
    if not flipped:
        yield "      -> changed no verdict or decision of these runs"


def _text(prefix: str, text: str) -> Iterator[str]:
    for n, line in enumerate(text.splitlines()):
        yield f"      {prefix if n == 0 else ' ' * len(prefix)}{line}"


def _case(case: CaseResult) -> Iterator[str]:
    subject = f'"{case.action}"' if case.case == "decision" else case.action
    yield f"  {case.id}  vehicle {case.vehicle}  {subject}"
    for change in case.changes:
        yield f"    {WHAT[change.kind]}: {from_to(change)}"
        for reason in change.reasons:
            yield f"      because {reason}"


def from_to(change: Change) -> str:
    return f"{change.before or '(none)'} -> {change.after or '(none)'}"


def tally(result: Regression) -> str:
    counts = result.counts()
    said = [f"{counts[k]} {WHAT[k] if counts[k] == 1 else PLURAL[k]}" for k in WHAT if counts.get(k)]
    if not said:
        return (f"Nothing changed: {counts['incidents']} incident(s) and {counts['decisions']} decision(s) "
                f"of {counts['runs']} run(s) judged alike.")
    return "Changed: " + ", ".join(said) + "."
