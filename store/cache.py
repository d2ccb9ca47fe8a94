"""The cache file: derived data (state snapshots, where road users were, verification results) kept
out of the evidence.

The store file is evidence, and reading it must not change it; what reads derive from it to go
faster lives in a separate SQLite file, `<store>.cache` beside it, or under
`$XDG_CACHE_HOME/mind-the-gaps/` (default `~/.cache/mind-the-gaps/`) when the store's folder
cannot be written (read-only media), or in memory when neither can. Everything in it is keyed
by the chain it was derived from (run, chain length, head hash) and checked against the store
when read, so a cache from another chain head, another store or another version of this code is
never used: deleting the file at any time changes no result, only how long the next read takes.
"""

from __future__ import annotations

import hashlib
import os
import sqlite3
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from .opening import read_only_place

CACHE_VERSION = 2  # raise when a table below changes: a file of another version is emptied
SUFFIX = ".cache"
MEMORY = ":memory:"
_TIMEOUT_S = 2.0  # a cache write waits this long for another process's, then goes without

_DDL = (
    """CREATE TABLE IF NOT EXISTS state_snapshots (
        run TEXT NOT NULL,
        fold INTEGER NOT NULL,
        t INTEGER NOT NULL,
        seq INTEGER NOT NULL,
        src TEXT NOT NULL,
        chain_len INTEGER NOT NULL,
        head TEXT NOT NULL,
        state BLOB NOT NULL,
        PRIMARY KEY (run, fold, t, seq, src)
    )""",
    """CREATE TABLE IF NOT EXISTS state_watermarks (
        run TEXT PRIMARY KEY,
        chain_len INTEGER NOT NULL,
        head TEXT NOT NULL
    )""",
    # store/presence.py: where each road user was, per source and bucket of time
    """CREATE TABLE IF NOT EXISTS presence (
        run TEXT NOT NULL,
        bucket INTEGER NOT NULL,
        src TEXT NOT NULL,
        x0 REAL NOT NULL,
        x1 REAL NOT NULL,
        y0 REAL NOT NULL,
        y1 REAL NOT NULL,
        PRIMARY KEY (run, bucket, src)
    ) WITHOUT ROWID""",
    """CREATE TABLE IF NOT EXISTS presence_marks (
        run TEXT PRIMARY KEY,
        chain_len INTEGER NOT NULL,
        head TEXT NOT NULL
    )""",
    """CREATE TABLE IF NOT EXISTS verifications (
        run TEXT NOT NULL,
        chain_len INTEGER NOT NULL,
        head TEXT NOT NULL,
        report TEXT NOT NULL,
        PRIMARY KEY (run, chain_len, head)
    )""",
)
_TABLES = ("state_snapshots", "state_watermarks", "presence", "presence_marks", "verifications")


def cache_path(store_path: str) -> str:
    """Where the cache of this store lives (MEMORY for a store that has no file)."""
    if store_path in ("", MEMORY) or store_path.startswith("file:"):
        return MEMORY
    beside = store_path + SUFFIX
    if not read_only_place(store_path) and (not os.path.exists(beside) or os.access(beside, os.W_OK)):
        return beside
    home = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
    absolute = os.path.abspath(store_path)
    name = f"{hashlib.sha256(absolute.encode('utf-8', 'surrogatepass')).hexdigest()[:24]}-{os.path.basename(absolute)}"
    return os.path.join(home, "mind-the-gaps", name + SUFFIX)


class Cache:
    """The cache of one store, opened on first use (a command that derives nothing creates no
    file). Falls back to memory when the file cannot be made or read."""

    def __init__(self, store_path: str) -> None:
        self.path = cache_path(store_path)
        self._conn: sqlite3.Connection | None = None

    @property
    def connection(self) -> sqlite3.Connection:
        if self._conn is None:
            self._conn = _open(self.path)
            if self._conn is None:
                self.path = MEMORY
                self._conn = _open(MEMORY)
        assert self._conn is not None
        return self._conn

    def exists(self) -> bool:
        """Is there a cache yet? (Asked without creating one.)"""
        return self._conn is not None or (self.path != MEMORY and os.path.isfile(self.path))

    def close(self) -> None:
        if self._conn is not None:
            self._conn.close()
            self._conn = None


@contextmanager
def writing(cache: sqlite3.Connection) -> Iterator[sqlite3.Connection]:
    """A write transaction on the cache, the lock taken first (BEGIN IMMEDIATE)."""
    cache.execute("BEGIN IMMEDIATE")
    try:
        yield cache
        cache.execute("COMMIT")
    except BaseException:
        cache.execute("ROLLBACK")
        raise


def _open(path: str) -> sqlite3.Connection | None:
    """The cache connection with its tables, or None if this path cannot hold a cache."""
    try:
        if path != MEMORY:
            os.makedirs(os.path.dirname(path), exist_ok=True)
        conn = sqlite3.connect(path, isolation_level=None, timeout=_TIMEOUT_S, check_same_thread=False)
    except (OSError, sqlite3.Error):
        return None
    try:
        conn.execute("PRAGMA synchronous=NORMAL")
        _prepare(conn)
    except sqlite3.Error:  # not a database, another version being written, read-only
        conn.close()
        return None
    return conn


def _prepare(conn: sqlite3.Connection) -> None:
    """Create the tables; empty a file written for another CACHE_VERSION."""
    (version,) = conn.execute("PRAGMA user_version").fetchone()
    if version == CACHE_VERSION:
        return
    conn.execute("BEGIN IMMEDIATE")
    try:
        if conn.execute("PRAGMA user_version").fetchone()[0] == CACHE_VERSION:  # another process did it
            conn.execute("COMMIT")
            return
        for table in _TABLES:
            conn.execute(f"DROP TABLE IF EXISTS {table}")
        for statement in _DDL:
            conn.execute(statement)
        conn.execute(f"PRAGMA user_version = {CACHE_VERSION}")
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise
