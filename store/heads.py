"""Where each run's chain and each source's seq stand, cached for the append path.

Every event appended needs its run's chain head and Merkle frontier, and whether its
(run, src, seq) is new. Asking the file each time would double the cost of an append, so the
answers are kept in memory. The cache is only ever a shortcut: it is filled from the file on
demand (the latest checkpoint holds the frontier, so a reopened store does not reread the run)
and thrown away whenever another connection may have written to the file.
"""

from __future__ import annotations

import sqlite3

from . import merkle
from .chain import RunChain


class Heads:
    """The cache, for one connection."""

    def __init__(self, conn: sqlite3.Connection) -> None:
        self._conn = conn
        self.chains: dict[str, RunChain] = {}
        self.max_seq: dict[tuple[str, str], int] = {}  # (run, src) -> highest stored seq, -1 if none

    def forget(self) -> None:
        self.chains.clear()
        self.max_seq.clear()

    def chain(self, run: str) -> RunChain:
        found = self.chains.get(run)
        if found is None:
            found = self.chains[run] = self._load_chain(run)
        return found

    def highest_seq(self, run: str, src: str) -> int:
        """The highest seq stored for the source, -1 if none."""
        key = (run, src)
        highest = self.max_seq.get(key)
        if highest is None:
            (found,) = self._conn.execute(
                "SELECT max(seq) FROM events WHERE run = ? AND src = ?", key
            ).fetchone()
            highest = self.max_seq[key] = -1 if found is None else found
        return highest

    def stored_event(self, run: str, src: str, seq: int) -> bytes | None:
        """Canonical bytes of the stored event with this identity, if any. Sources send seq in
        rising order, so knowing each source's highest seq answers "new" without a query."""
        if seq > self.highest_seq(run, src):
            return None
        row = self._conn.execute(
            "SELECT event FROM events WHERE run = ? AND src = ? AND seq = ?", (run, src, seq)
        ).fetchone()
        return None if row is None else row[0].encode("utf-8")

    def _load_chain(self, run: str) -> RunChain:
        """The run's chain as stored: head from its last event; frontier from its latest
        checkpoint when that checkpoint is at the head, else rebuilt from the event hashes."""
        last = self._conn.execute(
            "SELECT chain_pos, hash FROM events WHERE run = ? ORDER BY chain_pos DESC LIMIT 1", (run,)
        ).fetchone()
        latest = self._conn.execute(
            "SELECT count, head, frontier FROM checkpoints WHERE run = ? ORDER BY id DESC LIMIT 1", (run,)
        ).fetchone()
        checkpointed = 0 if latest is None else latest[0]
        if last is None:
            return RunChain(checkpointed=checkpointed)
        count, head = last[0] + 1, _digest(run, last[1])
        frontier = None
        if latest is not None and latest[0] == count and latest[1] == last[1]:
            frontier = merkle.unpack(latest[2], count)
        if frontier is None:
            frontier = self._rebuild_frontier(run)
        return RunChain(count, head, frontier, checkpointed)

    def _rebuild_frontier(self, run: str) -> list[bytes]:
        """Read every event hash of the run: a file from v1, or one whose last checkpoint does
        not match its events (verify will say why)."""
        rows = self._conn.execute("SELECT hash FROM events WHERE run = ? ORDER BY chain_pos", (run,))
        return merkle.frontier_of(_digest(run, stored) for (stored,) in rows)


def _digest(run: str, stored: str) -> bytes:
    """A stored hash as bytes; a non-hex value means the file was altered."""
    try:
        return bytes.fromhex(stored)
    except (TypeError, ValueError):
        raise ValueError(
            f"an event hash of run {run} is not a sha256 hex digest: the store was altered; run verify"
        ) from None
