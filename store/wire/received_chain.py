"""Checking a run received from another store, event by event, against that store's own chain.

A history answer (ingest/history_queryable.py) carries, beside each event, its chain position and
chain hash in the store that sent it. Where the copy receives consecutive positions, each event's
hash must be sha256(previous hash || its canonical bytes): a changed, dropped or reordered event
breaks that link, whoever changed it. Where the copy received the run from its first event on
without a hole, it appended the very same sequence, so its own chain head must equal the sender's
hash at that length: the copy is then provably the sender's chain (or the first N events of it).
A time window that starts after the run's first event cannot be compared that way: its links are
checked, and the report says that the heads are not comparable rather than that they differ.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..chain import GENESIS, link
if TYPE_CHECKING:                       # annotations only: the store's faces load before db is done
    from ..db import Store


@dataclass
class _Received:
    events: int = 0
    first_pos: int | None = None
    last_pos: int = -1
    last_hash: str = ""
    from_start: bool = True      # positions 0, 1, 2, ... with no hole so far
    links_checked: int = 0
    first_mismatch: dict[str, Any] | None = None


class ReceivedChains:
    """The chains of the runs a copy receives, as the sender stated them."""

    def __init__(self) -> None:
        self._runs: dict[str, _Received] = {}

    def observe(self, run: str, pos: int, hash_hex: str, canonical: bytes) -> None:
        """One received event at the sender's chain position `pos` with the sender's hash. A
        position at or below the last one seen (a repeat) changes nothing."""
        got = self._runs.setdefault(run, _Received())
        if pos <= got.last_pos:
            return
        if pos == got.last_pos + 1:
            prev = GENESIS if pos == 0 else bytes.fromhex(got.last_hash)
            got.links_checked += 1
            if link(prev, canonical).hex() != hash_hex and got.first_mismatch is None:
                got.first_mismatch = {"chain_pos": pos, "stated_hash": hash_hex,
                                      "recomputed": link(prev, canonical).hex()}
        else:
            got.from_start = False
        if got.first_pos is None:
            got.first_pos = pos
            got.from_start = pos == 0
        got.events += 1
        got.last_pos, got.last_hash = pos, hash_hex

    def results(self, store: Store) -> list[dict[str, Any]]:
        """Per run received: what was received, whether every link held, and whether this store's
        chain of the run is now the sender's (None: not comparable, a window past the start)."""
        return [self._result(store, run, got) for run, got in sorted(self._runs.items())]

    @staticmethod
    def _result(store: Store, run: str, got: _Received) -> dict[str, Any]:
        count, head = store.chain_head(run)
        comparable = got.from_start
        return {
            "run": run,
            "received": got.events,
            "first_chain_pos": got.first_pos,
            "last_chain_pos": got.last_pos,
            "source_head": got.last_hash,
            "links_checked": got.links_checked,
            "first_mismatch": got.first_mismatch,
            "store_events": count,
            "store_head": head or None,
            "match": (got.first_mismatch is None and (count, head) == (got.last_pos + 1, got.last_hash))
            if comparable else None,
        }
