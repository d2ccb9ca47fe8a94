"""Opening a store file: to append to it, or to read it without changing a byte.

An investigator reads evidence; reading must not alter it. A writer takes the write lock,
migrates the schema and switches the file to WAL, so that an ingest can append while others
read. A reader opens the file with SQLite's read-only mode and touches nothing: no lock taken
for writing, no migration, no schema created, no journal mode switched. A writer leaves the
file in rollback-journal mode when it is the last to close it, so that a later reader does
not need the -wal and -shm files a WAL file requires, and does not create them.

On read-only media (or a file or folder without write permission) SQLite cannot even take its
read locks, so the file is opened immutable: nothing then guards against a concurrent writer,
which on such media there cannot be.
"""

from __future__ import annotations

import os
import sqlite3
import stat
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator
from urllib.parse import quote

from . import ddl
from .errors import StoreError

CACHE_KIB = 64 * 1024  # page cache per connection: the indexes of a busy run stay in memory
PAGE_SIZE = 16384
MIGRATE_HINT = "run `gaps migrate SRC DST` to write a migrated copy"
CURSOR_SWEEP = 200
"""How often Python's sqlite3 (3.11) drops the dead weak references a connection keeps to its
cursors: at every CURSOR_SWEEP-th cursor made (each `execute` makes one). See `drop_dead_cursors`."""


def connect_writable(path: str, *, durable: bool, check_same_thread: bool) -> sqlite3.Connection:
    """A connection that may append: the schema created or migrated, WAL switched on. A file that
    is not an event store is a StoreError; one that cannot be opened or locked, sqlite3's error."""
    conn = sqlite3.connect(path, isolation_level=None, check_same_thread=check_same_thread)
    with _closed_on_error(conn, path, locked_as_is=True):
        _refuse_newer(conn, path)  # before anything is switched: a refused file is left as it was
        # A new file gets 16 KiB pages (before WAL fixes the size): the append inserts each
        # event into a table and four indexes, and larger pages split less often (bench/
        # append.py: +10-20% events/s against 4 KiB). An existing file keeps its size.
        conn.execute(f"PRAGMA page_size={PAGE_SIZE}")
        conn.execute("PRAGMA journal_mode=WAL")
        conn.execute(f"PRAGMA synchronous={'FULL' if durable else 'NORMAL'}")
        conn.execute(f"PRAGMA cache_size=-{CACHE_KIB}")
        ddl.migrate(conn)
    return conn


def connect_read_only(path: str, *, check_same_thread: bool = True, oldest: int = ddl.SCHEMA_VERSION) -> sqlite3.Connection:
    """A connection that cannot write, to a file that must be an event store of a schema
    version from `oldest` to the current one (older ones need `gaps migrate`)."""
    _check_file(path)
    flags = "mode=ro&immutable=1" if read_only_place(path) else "mode=ro"
    uri = f"file:{quote(os.path.abspath(path))}?{flags}"
    try:
        conn = sqlite3.connect(uri, uri=True, isolation_level=None, check_same_thread=check_same_thread)
    except sqlite3.Error as exc:
        raise StoreError(f"cannot open the event store {path}: {exc}") from None
    with _closed_on_error(conn, path, locked_as_is=False):
        conn.execute(f"PRAGMA cache_size=-{CACHE_KIB}")
        check_schema(conn, path, oldest)
    return conn


def _refuse_newer(conn: sqlite3.Connection, path: str) -> None:
    """StoreError for a store of a newer schema, read before the writer changes a byte of it (the
    switch to WAL rewrites the file's header)."""
    tables = {name for (name,) in conn.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
    if "schema_version" in tables and ddl.current_version(conn) > ddl.SCHEMA_VERSION:
        raise StoreError(f"cannot open the event store {path}: its store schema version "
                         f"{ddl.current_version(conn)} is newer than this gaps understands "
                         f"({ddl.SCHEMA_VERSION}): use a newer gaps")


def leave_rollback_journal(conn: sqlite3.Connection) -> None:
    """Switch the file back from WAL if no one else has it open (else leave it: they need WAL),
    so that readers of a closed store need no -wal or -shm file."""
    try:
        conn.execute("PRAGMA busy_timeout = 0")
        conn.execute("PRAGMA journal_mode=DELETE")
    except sqlite3.OperationalError:
        pass  # another connection has the file open: it stays in WAL mode


def read_only_place(path: str) -> bool:
    """Is the file or its folder not writable (read-only media, or permissions say so)? The
    permission bits are looked at as well as access(2), which says yes to root for anything."""
    folder = os.path.dirname(os.path.abspath(path))
    for place in (path, folder):
        if not os.access(place, os.W_OK) or not os.stat(place).st_mode & (stat.S_IWUSR | stat.S_IWGRP | stat.S_IWOTH):
            return True
    return False


def check_schema(conn: sqlite3.Connection, path: str, oldest: int = ddl.SCHEMA_VERSION) -> int:
    """The file's schema version, if it is an event store this code may read as it is."""
    tables = {name for (name,) in conn.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
    if not {"schema_version", "events"} <= tables:
        empty = os.path.getsize(path) == 0 if os.path.isfile(path) else False
        why = "the file is empty" if empty else "it holds no event log"
        raise StoreError(f"cannot open the event store {path}: not an event store ({why})")
    version = ddl.current_version(conn)
    if version > ddl.SCHEMA_VERSION:
        raise StoreError(f"cannot open the event store {path}: its store schema version {version} is newer "
                         f"than this gaps understands ({ddl.SCHEMA_VERSION}): use a newer gaps")
    if version < oldest:
        raise StoreError(f"cannot read the event store {path} as it is: its store schema version {version} "
                         f"is older than this gaps reads ({ddl.SCHEMA_VERSION}); {MIGRATE_HINT}")
    return version


def _check_file(path: str) -> None:
    place = Path(path)
    if not place.exists():
        raise StoreError(f"no event store at {path}: the file does not exist")
    if not place.is_file():
        raise StoreError(f"no event store at {path}: it is not a file")
    if not os.access(path, os.R_OK):
        raise StoreError(f"cannot read the event store {path}: permission denied")


@contextmanager
def _closed_on_error(conn: sqlite3.Connection, path: str, *, locked_as_is: bool) -> Iterator[None]:
    """Close the connection if setting it up fails; a file that is not a usable event store is a
    StoreError. With locked_as_is, SQLite's own error for a locked or unwritable file passes as
    it is (the writer's caller, the ingest, tells those apart)."""
    try:
        yield
    except sqlite3.DatabaseError as exc:
        conn.close()
        if locked_as_is and isinstance(exc, sqlite3.OperationalError):
            raise
        raise _unusable(path, exc) from None
    except UnicodeDecodeError:  # a damaged schema: SQLite hands Python text that is not UTF-8
        conn.close()
        raise StoreError(f"cannot open the event store {path}: its schema holds text that is not UTF-8 "
                         "(the file is damaged or was altered)") from None
    except BaseException:
        conn.close()
        raise


def _unusable(path: str, exc: sqlite3.DatabaseError) -> StoreError:
    """SQLite's words for a file that is not a database, said plainly."""
    if "not a database" in str(exc):
        return StoreError(f"cannot open the event store {path}: not an event store (file is not a database)")
    return StoreError(f"cannot open the event store {path}: {exc}")


def drop_dead_cursors(conn: sqlite3.Connection) -> None:
    """Have the connection let go of the weak references to its dead cursors now.

    sqlite3 keeps a weak reference to every cursor a connection made (each `execute` makes one) and
    drops the dead ones only at every CURSOR_SWEEP-th new cursor. A busy writer's last few hundred
    are made mid-batch, so they sit among the batch's own objects in the interpreter's memory arenas,
    and an arena goes back to the system only once nothing in it is alive: a quiet serve kept some
    eight arenas of 1 MB each for as few as one such dead reference (ingest/idle_memory.py). Making
    CURSOR_SWEEP cursors sweeps the list once, whatever the count stood at; the references made
    after the sweep are made now, when the batch is gone."""
    for _ in range(CURSOR_SWEEP):
        conn.cursor()
