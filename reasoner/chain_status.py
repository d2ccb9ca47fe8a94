"""Whether a run's record is as it was written: its hash chain recomputed, for the explanations.

An explanation is only as good as the record it rests on, so each states whether the run's chain
verified and, if not, the first link that failed (events from there on are not vouched for).
Recomputing a chain reads the whole run (seconds for a long one): an Investigation asks once
per run and keeps the answer.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from store import Problem, Store


@dataclass(frozen=True)
class ChainStatus:
    """checked: a store was read; verified: the chain matched (None if not checked); events: how
    many the run holds; problem: the store's account of the first link that failed (store.Problem),
    None when it verified, was not checked, or failed without naming a link."""

    checked: bool
    verified: bool | None
    events: int | None
    problem: Problem | None

    @property
    def failed(self) -> bool:
        """Whether the chain was recomputed and did not match."""
        return self.verified is False

    def to_json(self) -> dict[str, Any]:
        """The problem as the store states it; {} for a failure that names no link."""
        problem = self.problem.to_json() if self.problem is not None else {} if self.failed else None
        return {"checked": self.checked, "verified": self.verified, "events": self.events, "problem": problem}


def chain_status(store: Store, run: str) -> ChainStatus:
    report = store.verify(run)
    events = next((r.events for r in report.runs if r.run == run), None)
    if report.ok:
        return ChainStatus(True, True, events, None)
    return ChainStatus(True, False, events, report.problem)
