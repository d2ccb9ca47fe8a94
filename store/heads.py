"""Where each run's chain and each source's seq stand, cached for the append path.

Every event appended needs its run's chain head and Merkle frontier, and whether its
(run, src, seq) is new. Asking the file each time would double the cost of an append, so the
answers are kept in memory. The cache is only ever a shortcut: it is filled from the file on
demand (the latest checkpoint holds the frontier, so a reopened store does not reread the run)
and thrown away whenever another connection may have written to the file.
"""

from __future__ import annotations

import sqlite3

from .chain import RunChain
from .tail_check import anchored_chain
from .keys.tree_heads import CheckpointKey
from .keys.trust_root import SignedRuns


class Heads:
    """The cache, for one connection."""

    def __init__(self, conn: sqlite3.Connection, key: CheckpointKey | None = None,
                 trust: SignedRuns | None = None) -> None:
        self._conn = conn
        self.key = key  # the checkpoint key, whose last signed checkpoint a run's tail is checked against
        self.trust = trust  # each run's signed heads known outside the file (store/trust_root.py)
        self.chains: dict[str, RunChain] = {}
        self.max_seq: dict[tuple[str, str], int] = {}  # (run, src) -> highest stored seq, -1 if none
        self.sources: dict[str, list[str]] = {}  # run -> the srcs it has in max_seq, so that letting a
        # run go costs its own sources, not a walk over every source of every run held
        self.empty: set[str] = set()  # runs whose chain was empty when loaded: every source they
        # stored since is in max_seq, so a source not there has stored nothing (no query: a
        # fleet's new run brings dozens of new sources, and each was a look-up in the index)

    def forget(self) -> None:
        self.chains.clear()
        self.max_seq.clear()
        self.sources.clear()
        self.empty.clear()

    def release(self, run: str) -> None:
        """Forget what is kept of a run that ended (its run.end stored and committed) or went
        quiet: a fleet's ended runs must cost nothing for ever. A later event of it loads its
        chain again from its last checkpoint (its tail checked), and each source's highest seq
        from the file, as a reopened store does."""
        self.chains.pop(run, None)
        self.empty.discard(run)
        max_seq = self.max_seq
        for src in self.sources.pop(run, ()):
            max_seq.pop((run, src), None)

    def chain(self, run: str) -> RunChain:
        found = self.chains.get(run)
        if found is None:
            found = self.chains[run] = self._load_chain(run)
            if found.count == 0:
                self.empty.add(run)
        return found

    def highest_seq(self, run: str, src: str) -> int:
        """The highest seq stored for the source, -1 if none."""
        key = (run, src)
        highest = self.max_seq.get(key)
        if highest is None:
            if run in self.empty or (run not in self.chains and self._holds_nothing(run)):
                highest = -1
            else:
                (found,) = self._conn.execute(
                    "SELECT max(seq) FROM events WHERE run = ? AND src = ?", key
                ).fetchone()
                highest = -1 if found is None else found
            self.max_seq[key] = highest   # every key enters max_seq here (Batch._place asks first)
            self.sources.setdefault(run, []).append(src)
        return highest

    def _holds_nothing(self, run: str) -> bool:
        """Does the store hold no event of the run? (One probe a run, not one a source.)"""
        if self._conn.execute("SELECT 1 FROM events WHERE run = ? LIMIT 1", (run,)).fetchone() is None:
            self.empty.add(run)
            return True
        return False

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
        """The run's chain as stored, its tail checked against its last (signed) checkpoint
        first (store/tail_check.py): an append never seals events no append wrote. A run that
        `_holds_nothing` found empty is not looked for again (`empty` is only ever of this
        connection's view of the file: forgotten whenever another connection writes, and a run
        whose chain is loaded is in `chains`, which is asked first)."""
        return anchored_chain(self._conn, run, self.key, self.trust, empty=run in self.empty)

