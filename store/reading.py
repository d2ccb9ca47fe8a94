"""One read transaction: what is read together comes from one snapshot of the file.

A store may be appended to while it is read (an ingest writing, an investigator verifying). In
WAL mode each statement outside a transaction sees the file as it is when the statement starts,
so two statements may see two different files: the checkpoints read before a writer's commit and
the events read after it, which looks exactly like events added behind the store's back. Inside
one read transaction every statement sees the same snapshot, and the writer is not held up.
"""
from __future__ import annotations

import sqlite3
from contextlib import contextmanager
from typing import Iterator


@contextmanager
def one_snapshot(conn: sqlite3.Connection) -> Iterator[None]:
    """A read transaction around the block, or the caller's if one is already open."""
    if conn.in_transaction:
        yield
        return
    conn.execute("BEGIN")
    try:
        yield
    finally:
        _end(conn)


def _end(conn: sqlite3.Connection) -> None:
    """End the read transaction. Nothing was written in it, so a COMMIT that fails (SQLite
    reporting a damaged page once more, on a damaged file) is a ROLLBACK, not a new error that
    would hide what the block found or raised."""
    if not conn.in_transaction:
        return
    try:
        conn.execute("COMMIT")
    except sqlite3.DatabaseError:
        if conn.in_transaction:
            conn.execute("ROLLBACK")
