"""The cache file: derived data (state snapshots, where road users were, verification results) kept
out of the evidence.

The store file is evidence, and reading it must not change it; what reads derive from it to go
faster lives in a separate SQLite file, `<store>.cache` beside it, or under
`$XDG_CACHE_HOME/mind-the-gaps/` (default `~/.cache/mind-the-gaps/`) when the store's folder
cannot be written (read-only media), or in memory when neither can. Everything in it is keyed
by the chain it was derived from (run, chain length, head hash) and checked against the store
when read, so a cache from another chain head, another store or another version of this code is
never used: deleting the file at any time changes no result, only how long the next read takes.

Every entry is sealed (store/cache_seal.py) under a key kept outside the store's folder: an entry
that does not carry its seal is dropped and rebuilt, never believed, and counted (`Cache.sealer`),
so that whoever can write the folder can make reads slower, never different (issue 15, finding 2).
A file sealed under another key (the key file was replaced) is emptied when opened.
"""

from __future__ import annotations

import hashlib
import os
import sqlite3
from collections import Counter
from contextlib import contextmanager
from pathlib import Path
from typing import Any, Iterator, cast
from urllib.parse import quote

from .seal import Sealer, load_or_create_key, memory_key
from ..opening import drop_dead_cursors, read_only_place
from ..output_files import note_evidence

CACHE_VERSION = 5  # raise when a table below changes: a file of another version is emptied
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
        epoch INTEGER NOT NULL,
        mac BLOB NOT NULL,
        PRIMARY KEY (run, fold, t, seq, src)
    )""",
    """CREATE TABLE IF NOT EXISTS state_watermarks (
        run TEXT PRIMARY KEY,
        chain_len INTEGER NOT NULL,
        head TEXT NOT NULL,
        epoch INTEGER NOT NULL,
        mac BLOB NOT NULL
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
        mac BLOB NOT NULL,
        PRIMARY KEY (run, bucket, src)
    ) WITHOUT ROWID""",
    # boxes: how many the run has, digest: the XOR of their seals (a box removed shows)
    """CREATE TABLE IF NOT EXISTS presence_marks (
        run TEXT PRIMARY KEY,
        chain_len INTEGER NOT NULL,
        head TEXT NOT NULL,
        boxes INTEGER NOT NULL,
        digest BLOB NOT NULL,
        mac BLOB NOT NULL
    )""",
    """CREATE TABLE IF NOT EXISTS verifications (
        run TEXT NOT NULL,
        chain_len INTEGER NOT NULL,
        head TEXT NOT NULL,
        report TEXT NOT NULL,
        mac BLOB NOT NULL,
        PRIMARY KEY (run, chain_len, head)
    )""",
    # store/derived_cache.py: what a reader derived from one run's chain (measurements, states)
    """CREATE TABLE IF NOT EXISTS derived (
        run TEXT NOT NULL,
        kind TEXT NOT NULL,
        version TEXT NOT NULL,
        chain_len INTEGER NOT NULL,
        head TEXT NOT NULL,
        key TEXT NOT NULL,
        payload TEXT NOT NULL,
        mac BLOB NOT NULL,
        PRIMARY KEY (run, kind, version, key)
    ) WITHOUT ROWID""",
    "CREATE TABLE IF NOT EXISTS cache_key (id BLOB NOT NULL)",  # which key sealed this file
)
_TABLES = ("state_snapshots", "state_watermarks", "presence", "presence_marks", "verifications", "derived", "cache_key")


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

    def __init__(self, store_path: str, *, at: str | None = None) -> None:
        """`at`: the cache file to use in place of the one beside the store (a recording's
        temporary store keeps its cache under the recording's digest: store/kept_recording.py)."""
        self.path = at or cache_path(store_path)
        self._conn: sqlite3.Connection | None = None
        self._sealer: Sealer | None = None
        self.unwritten: str | None = None
        """Why the cache could not be written, if it could not (a full disk, a read-only folder):
        reads then compute without it, and the command line says so (never as damage)."""
        self.memo: dict[tuple, Any] = {}
        """What this process has found about the cache (a run's whole set of boxes sound at one
        chain head, the earliest event appended after a chain length), so that it is worked out
        once, not on every read."""

    def shrink_memory(self) -> None:
        """Give back the page cache of the open connection, if one is open (an idle ingest), and
        its dead cursors' weak references (store.opening.drop_dead_cursors)."""
        if self._conn is not None:
            self._conn.execute("PRAGMA shrink_memory")
            drop_dead_cursors(self._conn)

    @property
    def connection(self) -> sqlite3.Connection:
        if self._conn is None:
            if self.path in _unread:    # it could not be read earlier in this process: go without it
                _went_without.append((self.path, _unread[self.path]))
                self.path = MEMORY
            key = None if self.path == MEMORY else load_or_create_key()
            if key is not None:
                note_evidence(self.path, "cache file")
                self._conn = _open(self.path, key)
                if self._conn is not None:
                    _files_opened.append(self.path)
            if self._conn is None:  # no key to keep, or no file to keep it in: memory only
                if self.path != MEMORY and os.path.lexists(self.path):     # there, but not a cache SQLite can use
                    _went_without.append((self.path, "SQLite could not open it as a cache"))
                elif self.path != MEMORY:
                    self.failed_to_write(f"{self.path} could not be opened or made")
                self.path, key = MEMORY, memory_key()
                self._conn = _open(MEMORY, key)
            if self._sealer is None or self._sealer.key != key:
                path = self.path
                self._sealer = Sealer(cast(bytes, key), self._sealer.dropped if self._sealer else Counter(),
                                      None if path == MEMORY else lambda: _altered.update((path,)))
        assert self._conn is not None
        return self._conn

    @property
    def sealer(self) -> Sealer:
        """Seals and opens this cache's entries (store/cache_seal.py); counts what was dropped."""
        self.connection
        assert self._sealer is not None
        return self._sealer

    def failed_to_write(self, why: sqlite3.Error | str) -> None:
        """Note that a write to the cache failed for want of room or permission (SQLITE_FULL,
        IOERR, READONLY, CANTOPEN) - not when another process held its lock, which is ordinary."""
        if isinstance(why, sqlite3.Error):
            if (getattr(why, "sqlite_errorcode", None) or 0) & 0xFF not in _CANNOT_WRITE:
                return      # locked by another process (ordinary), or not a failure to write
            why = f"{self.path}: {why}"
        if self.unwritten is None:
            self.unwritten = why
            _unwritten.append(why)

    def exists(self) -> bool:
        """Is there a cache yet? (Asked without creating one.)"""
        return self._conn is not None or (self.path != MEMORY and os.path.isfile(self.path))

    def close(self) -> None:
        if self._conn is not None:
            self._conn.close()
            self._conn = None
            self.memo.clear()


_CANNOT_WRITE = (sqlite3.SQLITE_FULL, sqlite3.SQLITE_IOERR, sqlite3.SQLITE_READONLY, sqlite3.SQLITE_CANTOPEN,
                 sqlite3.SQLITE_PERM)
_unwritten: list[str] = []


_files_opened: list[str] = []


def caches_opened() -> int:
    """How many times this process has opened a cache file (damaged_caches(since=) counts from it)."""
    return len(_files_opened)


def caches_opened_since(since: int) -> list[str]:
    """The cache files this process opened after its first `since` openings, each once."""
    return list(dict.fromkeys(_files_opened[since:]))


_unread: dict[str, str] = {}


def go_without_caches(paths: list[str], why: str) -> None:
    """Never open these cache files again in this process (an SQLite error while reading one:
    damaged pages, an I/O error): every Cache made for them from now on lives in memory, so that
    a read run again computes from the events alone (cli/app.py)."""
    for path in paths:
        _unread.setdefault(path, why)


_went_without: list[tuple[str, str]] = []


_altered: Counter[str] = Counter()


def altered_caches() -> dict[str, int]:
    """Per cache file this process opened, how many entries it found whose seal did not open
    (altered since gaps wrote them, or damaged where SQLite could not tell): they were dropped and
    computed again from the store, and the command line names the file, as it does a cache it could
    not read, so that damage to derived data is said whichever check caught it. One count per file,
    however many times a long-running process opens it."""
    return dict(_altered)


def unread_caches() -> list[tuple[str, str]]:
    """(cache file, why) each time this process went without a cache file it had failed to read
    (the command line warns with these, as with unwritten_caches)."""
    return list(_went_without)


def damaged_caches(since: int = 0) -> list[str]:
    """The cache files this process opened (after its first `since` openings) that SQLite's quick
    check finds damaged: asked only after an SQLite error, to tell a damaged cache (derived data:
    delete it) from a damaged store."""
    found: list[str] = []
    for path in dict.fromkeys(_files_opened[since:]):
        try:
            conn = sqlite3.connect(f"file:{quote(os.path.abspath(path))}?mode=ro", uri=True)
        except sqlite3.Error:
            continue
        try:
            sound = conn.execute("PRAGMA quick_check(1)").fetchall() == [("ok",)]
        except sqlite3.DatabaseError:
            sound = False
        finally:
            conn.close()
        if not sound:
            found.append(path)
    return found


def unwritten_caches() -> list[str]:
    """Why each cache this process could not write failed (the command line warns with these)."""
    return list(_unwritten)


@contextmanager
def writing(cache: sqlite3.Connection) -> Iterator[sqlite3.Connection]:
    """A write transaction on the cache, the lock taken first (BEGIN IMMEDIATE)."""
    cache.execute("BEGIN IMMEDIATE")
    try:
        yield cache
        cache.execute("COMMIT")
    except BaseException:
        rollback(cache)
        raise


def rollback(cache: sqlite3.Connection) -> None:
    """Roll back the cache's transaction if it is still open: SQLite ends one itself on a full
    disk or an I/O error, and a ROLLBACK then would fail and hide why."""
    if cache.in_transaction:
        try:
            cache.execute("ROLLBACK")
        except sqlite3.Error:
            pass


def _open(path: str, key: bytes) -> sqlite3.Connection | None:
    """The cache connection with its tables, or None if this path cannot hold a cache."""
    try:
        if path != MEMORY:      # a store named relative to here ("gaps.db", the default) has "" as its folder
            os.makedirs(os.path.dirname(os.path.abspath(path)), exist_ok=True)
        conn = sqlite3.connect(path, isolation_level=None, timeout=_TIMEOUT_S, check_same_thread=False)
    except (OSError, sqlite3.Error):
        return None
    try:
        conn.execute("PRAGMA synchronous=NORMAL")
        _prepare(conn, _key_id(key))
    except sqlite3.Error:  # not a database, another version being written, read-only
        conn.close()
        return None
    return conn


def _key_id(key: bytes) -> bytes:
    """Names the key without revealing it."""
    return hashlib.sha256(b"mind-the-gaps cache key id" + key).digest()[:16]


def _current(conn: sqlite3.Connection, key_id: bytes) -> bool:
    """Is the file of this CACHE_VERSION and sealed under this key?"""
    if conn.execute("PRAGMA user_version").fetchone()[0] != CACHE_VERSION:
        return False
    try:
        row = conn.execute("SELECT id FROM cache_key LIMIT 1").fetchone()
    except sqlite3.OperationalError:  # no such table: the file was altered
        return False
    return row is not None and row[0] == key_id


def _prepare(conn: sqlite3.Connection, key_id: bytes) -> None:
    """Create the tables; empty a file written for another CACHE_VERSION or under another key
    (its seals could never open: not tampering, a new key)."""
    if _current(conn, key_id):
        return
    conn.execute("BEGIN IMMEDIATE")
    try:
        if _current(conn, key_id):  # another process did it
            conn.execute("COMMIT")
            return
        for table in _TABLES:
            conn.execute(f"DROP TABLE IF EXISTS {table}")
        for statement in _DDL:
            conn.execute(statement)
        conn.execute("INSERT INTO cache_key (id) VALUES (?)", (key_id,))
        conn.execute(f"PRAGMA user_version = {CACHE_VERSION}")
        conn.execute("COMMIT")
    except BaseException:
        rollback(conn)
        raise
