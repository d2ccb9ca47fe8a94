"""Checking the events of an MCAP file against the chain checkpoints exported with them.

An export in chain order carries the run's checkpoints (count, head) as metadata. Re-hashing the
events as they are read shows whether the file still holds exactly what the exporting store had
chained (an altered, dropped or reordered message changes every head after it), and comparing
the importing store's head shows whether its copy of the run is now the same chain. Files we
write put the metadata before the messages, so every checkpoint can be checked in one pass.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

from ..chain import GENESIS, link
from ..db import Store
from .rows import chain_head

RUN_METADATA = "gaps.run"
CHECKPOINT_METADATA = "gaps.checkpoint"


@dataclass
class _Chain:
    exported_events: int | None = None
    exported_head: str | None = None
    checkpoints: dict[int, str] = field(default_factory=dict)  # count -> head
    count: int = 0
    head: bytes = GENESIS
    matched: int = 0
    first_mismatch: dict[str, Any] | None = None
    malformed: int = 0
    order: str = "chain"  # a file written in time order does not rebuild the chain


class ChainCheck:
    def __init__(self) -> None:
        self._runs: dict[str, _Chain] = {}

    def metadata(self, name: str, data: Mapping[str, str]) -> None:
        """Take note of a gaps.run or gaps.checkpoint metadata record; others are not ours."""
        if name not in (RUN_METADATA, CHECKPOINT_METADATA) or not data.get("run"):
            return
        chain = self._runs.setdefault(data["run"], _Chain())
        try:
            count, head = int(data["count" if name == CHECKPOINT_METADATA else "events"]), data["head"]
        except (KeyError, ValueError):
            chain.malformed += 1
            return
        if name == RUN_METADATA:
            chain.exported_events, chain.exported_head = count, head
            chain.order = data.get("order") or "chain"
        else:
            chain.checkpoints[count] = head

    def observe(self, event: Mapping[str, Any], canonical: bytes) -> None:
        """Extend the file's own chain of the event's run, if the file declared that run."""
        chain = self._runs.get(event["run"])
        if chain is None or chain.order != "chain":
            return
        chain.head = link(chain.head, canonical)
        chain.count += 1
        expected = chain.checkpoints.get(chain.count)
        if expected is None:
            return
        if expected == chain.head.hex():
            chain.matched += 1
        elif chain.first_mismatch is None:
            chain.first_mismatch = {"count": chain.count, "exported_head": expected, "file_head": chain.head.hex()}

    def results(self, store: Store) -> list[dict[str, Any]]:
        """Per declared run: does the file, and does the store now, hold the exported chain?"""
        return [self._result(store, run, chain) for run, chain in sorted(self._runs.items())]

    @staticmethod
    def _result(store: Store, run: str, chain: _Chain) -> dict[str, Any]:
        store_head = chain_head(store, run)
        file_head = chain.head.hex() if chain.count else None
        whole = chain.count == chain.exported_events and file_head == chain.exported_head
        comparable = chain.order == "chain"
        return {
            "run": run,
            "order": chain.order,
            "exported_events": chain.exported_events,
            "exported_head": chain.exported_head,
            "file_events": chain.count if comparable else None,
            "file_head": file_head,
            "checkpoints": len(chain.checkpoints),
            "checkpoints_matched": chain.matched,
            "first_mismatch": chain.first_mismatch,
            "store_head": store_head,
            "malformed_metadata": chain.malformed,
            # None: not comparable, the file is in time order and rebuilds the events, not the chain
            "match": (whole and chain.first_mismatch is None and store_head == chain.exported_head)
            if comparable else None,
        }
