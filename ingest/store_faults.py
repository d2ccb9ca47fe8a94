"""Telling a store that cannot write now from a sample it cannot take, and how long to wait.

A commit can fail for two kinds of reasons. The store's condition (a full disk, an I/O error, a
write lock held elsewhere, a file made read-only) fails every commit alike until it changes: the
writer must hold what it accepted and wait, which makes Zenoh's channel fill and publishers block
(BLOCK congestion control), instead of giving the samples up. Anything else is taken to be the
sample's own fault, and quarantining that sample lets the others through (ingest/writer.py).
Which of the store's errors are its condition the store says (store/sqlite_errors.py): no room
but the store knows SQLite.
"""
from __future__ import annotations

from store import store_fault

FIRST_PAUSE_S = 0.1
LONGEST_PAUSE_S = 2.0
"""Waits between tries while the store cannot write: doubling from the first to the longest, so a
disk freed again is written to within about two seconds, and a dead one costs a try every two."""


def store_condition(exc: BaseException) -> str | None:
    """What about the store made ``exc`` happen ("the disk is full"), or None if it is not the
    store's condition (then it is taken to be the sample's). The store says which of its errors
    (store/errors.py: StoreFault) are its condition, from SQLite's result code or message; an
    OSError is the disk's."""
    if isinstance(exc, OSError):
        return f"the disk failed ({exc.strerror or exc})"
    fault = store_fault(exc)
    return None if fault is None else fault.condition


class Backoff:
    """The pauses between tries at a store that cannot write: FIRST_PAUSE_S, doubling, at most
    LONGEST_PAUSE_S."""

    def __init__(self, first_s: float | None = None, longest_s: float | None = None) -> None:
        self._first = FIRST_PAUSE_S if first_s is None else first_s
        self._longest = LONGEST_PAUSE_S if longest_s is None else longest_s
        self._next = self._first

    def pause(self) -> float:
        """The next pause, in seconds (each twice the last, up to the longest)."""
        pause, self._next = self._next, min(self._next * 2, self._longest)
        return pause
