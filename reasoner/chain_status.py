"""Whether a run's record is as it was written: its hash chain recomputed, for the explanations.

An explanation is only as good as the record it rests on, so each states whether the run's chain
verified and, if not, the first link that failed (events from there on are not vouched for).
Recomputing a chain reads the whole run (seconds for a long one): an Investigation asks once
per run and keeps the answer.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

from store import Store


@dataclass(frozen=True)
class ChainStatus:
    """checked: a store was read; verified: the chain matched (None if not checked); events: how
    many the run holds; problem: the store's account of the first link that failed."""

    checked: bool
    verified: bool | None
    events: int | None
    problem: Mapping[str, Any] | None

    def to_json(self) -> dict[str, Any]:
        return {"checked": self.checked, "verified": self.verified, "events": self.events,
                "problem": dict(self.problem) if self.problem is not None else None}


def chain_status(store: Store, run: str) -> ChainStatus:
    report = store.verify(run)
    summary = next((r for r in report.runs if r.get("run") == run), {})
    if report.ok:
        return ChainStatus(True, True, summary.get("events"), None)
    return ChainStatus(True, False, summary.get("events"), report.problem or {})
