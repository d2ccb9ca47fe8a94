"""Checking a run received from another store, event by event, against that store's own chain.

A history answer (ingest/history_queryable.py) carries, beside each event, its chain position and
chain hash in the store that sent it. Where the copy receives consecutive positions, each event's
hash must be sha256(previous hash || its canonical bytes): a changed, dropped or reordered event
breaks that link, whoever changed it. Where the copy received the run from its first event on
without a hole, it appended the very same sequence, so its own chain head must equal the sender's
hash at that length: the copy is then provably the sender's chain (or the first N events of it).
A time window that starts after the run's first event cannot be compared that way: its links are
checked, and the report says that the heads are not comparable rather than that they differ.
What a run's check found is a frozen value (`ReceivedChain`, its first broken link a `BrokenLink`)
with the `to_json` that `gaps fetch --json` prints.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

from ..chain import GENESIS, link
if TYPE_CHECKING:                       # annotations only: the store's faces load before db is done
    from ..db import Store


@dataclass(frozen=True)
class BrokenLink:
    """The first received event that does not hash, on the previous one, to the hash the sender
    stated for it: at the sender's chain position `chain_pos`."""

    chain_pos: int
    stated_hash: str
    recomputed: str

    def to_json(self) -> dict[str, Any]:
        return {"chain_pos": self.chain_pos, "stated_hash": self.stated_hash, "recomputed": self.recomputed}


@dataclass(frozen=True)
class ReceivedChain:
    """One run received: the sender's chain positions it came from, the links checked, and whether
    this store's chain of the run is now the sender's (`match` None: not comparable, a window past
    the run's start)."""

    run: str
    received: int
    first_chain_pos: int | None
    last_chain_pos: int
    source_head: str
    links_checked: int
    first_mismatch: BrokenLink | None
    store_events: int
    store_head: str | None
    match: bool | None

    @property
    def broken(self) -> bool:
        """A link did not hold, or the chains were comparable and differ."""
        return self.first_mismatch is not None or self.match is False

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "received": self.received, "first_chain_pos": self.first_chain_pos,
                "last_chain_pos": self.last_chain_pos, "source_head": self.source_head,
                "links_checked": self.links_checked,
                "first_mismatch": None if self.first_mismatch is None else self.first_mismatch.to_json(),
                "store_events": self.store_events, "store_head": self.store_head, "match": self.match}


@dataclass
class _Received:
    events: int = 0
    first_pos: int | None = None
    last_pos: int = -1
    last_hash: str = ""
    from_start: bool = True      # positions 0, 1, 2, ... with no hole so far
    links_checked: int = 0
    first_mismatch: BrokenLink | None = None


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
                got.first_mismatch = BrokenLink(pos, hash_hex, link(prev, canonical).hex())
        else:
            got.from_start = False
        if got.first_pos is None:
            got.first_pos = pos
            got.from_start = pos == 0
        got.events += 1
        got.last_pos, got.last_hash = pos, hash_hex

    def results(self, store: Store) -> list[ReceivedChain]:
        """Per run received: what was received, whether every link held, and whether this store's
        chain of the run is now the sender's (None: not comparable, a window past the start)."""
        return [self._result(store, run, got) for run, got in sorted(self._runs.items())]

    @staticmethod
    def _result(store: Store, run: str, got: _Received) -> ReceivedChain:
        count, head = store.chain_head(run)
        match = (got.first_mismatch is None and (count, head) == (got.last_pos + 1, got.last_hash)) \
            if got.from_start else None
        return ReceivedChain(run=run, received=got.events, first_chain_pos=got.first_pos,
                             last_chain_pos=got.last_pos, source_head=got.last_hash,
                             links_checked=got.links_checked, first_mismatch=got.first_mismatch,
                             store_events=count, store_head=head or None, match=match)
