"""Reads through the covering index by kind, checked against the chained table row by row.

`events_by_kind` holds, beside run, kind, t, seq and src, each sparse event's text a second time,
so that the reasoner reads a run's observations, spawns and decisions from the index alone. The
hash chains cover the table's rows, not the index's copies: someone holding the file can rewrite
an index entry (a forged rulebook in `run.start`) and every read through it believes the forgery
while the chains still verify. So each such read also fetches the entry's row from the table by
rowid, inside SQLite, and compares every column the index repeats: a row read is then exactly a
row the chain covers, or the read stops with IndexDisagrees naming the event.

Measured (docs/guarantees.md): the row lookup roughly doubles the cost of the raw index read
(a run's 39,715 observations: 0.30 s to 0.56-0.75 s, on a loaded machine), while all incidents of
bench/incidents.py's quick run took no measurably longer (CPU median 7.52 s before, 6.75 s after,
six interleaved runs each, spread 6.3-8.6 s: the some 0.3 s the run's observations should cost
is below the noise). An entry removed from the index (an observation hidden) cannot be seen this
way, since no row is read for it: SQLite's integrity check in `gaps verify` finds that
(store/integrity.py).
"""
from __future__ import annotations

import sqlite3
from typing import Any, Iterable, Iterator

from .errors import EvidenceError, IndexDisagrees

# 1 when the index entry being read agrees with the table row it points at, 0 when a column
# differs, NULL when it points at no row. Written for a query `FROM events` (not aliased).
AGREES = ("(SELECT x.run = events.run AND x.kind = events.kind AND x.t = events.t AND x.seq = events.seq "
          "AND x.src = events.src AND x.event = events.event FROM events AS x WHERE x.rowid = events.rowid)")


def checked(rows: Iterable[tuple], run: str, src_at: int = 2, seq_at: int = 1) -> Iterator[tuple]:
    """The rows without their last column (AGREES), each one checked; IndexDisagrees at the first
    entry that is not its table row, EvidenceError at text that is not UTF-8 (sqlite3 cannot
    return it)."""
    try:
        for row in rows:
            if row[-1] != 1:
                raise disagreement(run, row[src_at], row[seq_at])
            yield row[:-1]
    except sqlite3.OperationalError as exc:
        if "decode" not in str(exc):
            raise
        raise EvidenceError(f"run {run}: a stored event's text is not valid UTF-8, which no append writes: "
                            "the file was altered behind the store's back; `gaps verify` names the event") from None


def disagreement(run: str, src: Any, seq: Any) -> IndexDisagrees:
    return IndexDisagrees(
        f"event run={run} src={src} seq={seq}: the store's index by kind (events_by_kind) does not hold what "
        "the chained table holds for this event: the file was altered behind the store's back, so nothing is "
        "read through that index; `gaps verify` names what the integrity check finds")
