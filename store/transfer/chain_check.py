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

@dataclass(frozen=True)
class Mismatch:
    """The first checkpoint the file's own events do not reach: after `count` events the export
    recorded `exported_head`, the file's events give `file_head`."""

    count: int
    exported_head: str
    file_head: str

    def to_json(self) -> dict[str, Any]:
        return {"count": self.count, "exported_head": self.exported_head, "file_head": self.file_head}


@dataclass(frozen=True)
class ChainResult:
    """One run the file declared: does the file, and does the store now, hold the exported chain?
    `match` is None when the file is in time order (it rebuilds the events, not the chain);
    `chain_order` says why the file's chain order was not followed to the end, if it was not."""

    run: str
    order: str                      # "chain" or "time" as the file says: read from it, it may be any word
    exported_events: int | None
    exported_head: str | None
    file_events: int | None
    file_head: str | None
    checkpoints: int
    checkpoints_matched: int
    first_mismatch: Mismatch | None
    store_head: str | None
    malformed_metadata: int
    match: bool | None
    chain_order: str | None = None

    def to_json(self) -> dict[str, Any]:
        out = {"run": self.run, "order": self.order, "exported_events": self.exported_events,
               "exported_head": self.exported_head, "file_events": self.file_events, "file_head": self.file_head,
               "checkpoints": self.checkpoints, "checkpoints_matched": self.checkpoints_matched,
               "first_mismatch": None if self.first_mismatch is None else self.first_mismatch.to_json(),
               "store_head": self.store_head, "malformed_metadata": self.malformed_metadata, "match": self.match}
        return out if self.chain_order is None else {**out, "chain_order": self.chain_order}


@dataclass
class _Chain:
    exported_events: int | None = None
    exported_head: str | None = None
    checkpoints: dict[int, str] = field(default_factory=dict)  # count -> head
    count: int = 0
    head: bytes = GENESIS
    matched: int = 0
    first_mismatch: Mismatch | None = None
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
            chain.first_mismatch = Mismatch(chain.count, expected, chain.head.hex())

    def results(self, store: Store) -> list[ChainResult]:
        """Per declared run: does the file, and does the store now, hold the exported chain?"""
        return [self._result(store, run, chain) for run, chain in sorted(self._runs.items())]

    @staticmethod
    def _result(store: Store, run: str, chain: _Chain) -> ChainResult:
        store_head = chain_head(store, run)
        file_head = chain.head.hex() if chain.count else None
        whole = chain.count == chain.exported_events and file_head == chain.exported_head
        comparable = chain.order == "chain"
        # None: not comparable, the file is in time order and rebuilds the events, not the chain
        match = (whole and chain.first_mismatch is None and store_head == chain.exported_head) if comparable else None
        return ChainResult(run, chain.order, chain.exported_events, chain.exported_head,
                           chain.count if comparable else None, file_head, len(chain.checkpoints), chain.matched,
                           chain.first_mismatch, store_head, chain.malformed, match)
