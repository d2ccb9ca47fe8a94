"""Telling a store that cannot write now from a sample it cannot take, and how long to wait.

A commit can fail for two kinds of reasons. The store's condition (a full disk, an I/O error, a
write lock held elsewhere, a file made read-only) fails every commit alike until it changes: the
writer must hold what it accepted and wait, which makes Zenoh's channel fill and publishers block
(BLOCK congestion control), instead of giving the samples up. Anything else is taken to be the
sample's own fault, and quarantining that sample lets the others through (ingest/writer.py).
"""
from __future__ import annotations

import sqlite3

# SQLite's primary result codes (the low byte of an extended code) that describe the file or the
# disk rather than what was being written: https://sqlite.org/rescode.html
_CONDITIONS = {5: "the store is busy", 6: "the store is locked", 7: "out of memory",
               8: "the store is read-only", 10: "disk I/O error", 13: "the disk is full",
               14: "the store file cannot be opened", 15: "the store's lock protocol failed"}
_MESSAGES = {"database or disk is full": "the disk is full", "disk i/o error": "disk I/O error",
             "database is locked": "the store is locked", "readonly database": "the store is read-only",
             "unable to open database": "the store file cannot be opened"}

FIRST_PAUSE_S = 0.1
LONGEST_PAUSE_S = 2.0
"""Waits between tries while the store cannot write: doubling from the first to the longest, so a
disk freed again is written to within about two seconds, and a dead one costs a try every two."""


def store_condition(exc: BaseException) -> str | None:
    """What about the store made ``exc`` happen ("the disk is full"), or None if it is not the
    store's condition (then it is taken to be the sample's). Read from SQLite's result code where
    the error carries one, else from SQLite's message; an OSError is the disk's."""
    if isinstance(exc, OSError):
        return f"the disk failed ({exc.strerror or exc})"
    if not isinstance(exc, sqlite3.OperationalError):
        return None
    code = getattr(exc, "sqlite_errorcode", None)
    if code is not None:
        return _CONDITIONS.get(code & 0xFF)
    text = str(exc).lower()
    return next((why for words, why in _MESSAGES.items() if words in text), None)


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
