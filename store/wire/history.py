"""A run's stored events in chain order, read a chunk at a time: what a history query over the wire
(ingest/history_queryable.py) answers from, without holding the store.

An answer may cover millions of events and take minutes to send to a slow querier. Reading it in
one statement would keep one read transaction open all that time, and a WAL store cannot fold its
log back while a reader holds an old snapshot (the ingest's WAL would grow for as long as the
answer lasts). So each chunk is read in its own short transaction, resuming after the last chain
position sent: the store is append-only, so positions never move, and the window is fixed at the
start, so events appended during the answer are not half-included.

Chain order, not time order: a copy that appends the events as they arrive then rebuilds the
source's very chain, and its heads can be compared with the source's (`gaps fetch`).
"""
from __future__ import annotations

import sqlite3
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from typing import TypeVar

from .. import queries

R = TypeVar("R")
CHUNK = 1000  # rows per read transaction: one chunk of events is all an answer holds in memory


@dataclass(frozen=True, slots=True)
class HistoryRow:
    """One stored event as the store has it: its canonical JSON text and its link of the chain."""

    run: str
    chain_pos: int
    t: int
    src: str
    kind: str
    event: str   # the canonical JSON, as hashed
    hash: str    # hex sha256 of the chain up to and including this event


@dataclass(frozen=True, slots=True)
class HistoryFilter:
    """Which of a run's events: t in [t_from, t_to] (inclusive, None: open), one source, one kind."""

    t_from: int | None = None
    t_to: int | None = None
    src: str | None = None
    kind: str | None = None


def history_rows(conn: sqlite3.Connection, run: str, wanted: HistoryFilter, after: int = -1,
                 chunk: int = CHUNK) -> Iterator[HistoryRow]:
    """The run's events that pass `wanted`, at chain positions above `after`, in chain order."""
    if chunk < 1:
        raise ValueError(f"chunk must be >= 1, got {chunk}")
    window = _read(conn, lambda: queries.history_window(conn, run, wanted))
    if window is None:
        return
    lo, hi = window
    last = max(after, lo - 1)
    while last < hi:
        rows = _read(conn, lambda: queries.history_chunk(conn, run, wanted, last, hi, chunk))
        for row in rows:
            yield HistoryRow(run, *row)
        if len(rows) < chunk:
            return
        last = rows[-1][0]


def _read(conn: sqlite3.Connection, read: Callable[[], R]) -> R:
    """One short read transaction (or the caller's, if one is open)."""
    if conn.in_transaction:
        return read()
    conn.execute("BEGIN")
    try:
        return read()
    finally:
        conn.execute("COMMIT")
