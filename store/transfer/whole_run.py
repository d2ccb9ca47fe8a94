"""An export writes the whole run the chain holds, or no file at all.

An export reads a run through an index (time order: `events_by_time`; chain order: the (run,
chain_pos) index) and writes what it finds. An index that lost entries (one flipped bit in the
time index: 4,382 of 79,576 events written, exit 0; issue 15, finding 3) would give a short
file that looks whole. So the export counts what it wrote and compares it with the run's figure
from the chain: the count of its latest checkpoint, which verify checks the chain against, and
the chain's length by position; and, in chain order, it re-hashes the text it wrote and compares
the head with that checkpoint's. A difference raises ExportIncomplete before the file is put in
place. The export reads in one snapshot (store/reading.py), so a writer appending meanwhile
cannot make a whole export look short.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from ..chain import GENESIS, link
from ..db import Store
from ..queries import chain_length
from .errors import ExportIncomplete
from .rows import chain_head


@dataclass
class WholeRun:
    """What the chain says the run holds, and what the export has written so far."""

    run: str
    events: int            # the count of the run's latest checkpoint (its chain length without one)
    head: str | None       # that checkpoint's head
    positions: int         # the chain's length by position (highest chain_pos + 1)
    chained: bool          # rows come in chain order, so the head can be recomputed
    written: int = 0
    _head: bytes = field(default=GENESIS, repr=False)

    @classmethod
    def of(cls, store: Store, run: str, order: str) -> WholeRun:
        checkpoints = store.checkpoints(run)
        positions = chain_length(store.connection, run)
        if checkpoints:
            latest = checkpoints[-1]
            return cls(run, int(latest["count"]), str(latest["head"]), positions, order == "chain")
        return cls(run, positions, chain_head(store, run), positions, order == "chain")

    def see(self, text: str) -> None:
        """One event written, as its stored text."""
        self.written += 1
        if self.chained:
            self._head = link(self._head, text.encode("utf-8", "surrogatepass"))

    def check(self) -> None:
        """ExportIncomplete unless the export wrote exactly the run the chain holds."""
        if self.written != self.events or self.positions != self.events:
            raise ExportIncomplete(
                f"export of run {self.run} stopped: it read {self.written} events, but the run's chain holds "
                f"{self.events} (its latest checkpoint; {self.positions} by chain position): an index of the "
                "store disagrees with the chain, so no file was written; `gaps verify` says what is wrong")
        if self.chained and self.head is not None and self._head.hex() != self.head:
            raise ExportIncomplete(
                f"export of run {self.run} stopped: the {self.written} events read hash to head "
                f"{self._head.hex()[:16]}…, but the run's latest checkpoint records {self.head[:16]}…: the store "
                "does not hold the chain it recorded, so no file was written; `gaps verify` says where")

