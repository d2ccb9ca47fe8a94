"""Snapshots of folded state: a cache that makes state at any t cost one snapshot load plus a
short fold, however long the run.

The snapshots are derived data, not evidence. Their tables are created here (IF NOT EXISTS), are
neither hash-chained nor append-only, and may be deleted at any time: they are rebuilt from the
events on the next read. A snapshot is keyed by the position (t, seq, src) of the last event
folded into it and holds the fold state as zlib-compressed JSON (compressed about eightfold, so
fewer pages to read; inflating costs a fraction of parsing). The JSON is written by orjson when
it can be, and the blob says so: orjson refuses to write an integer beyond 64 bits, so such a
snapshot can be parsed by orjson without the search for long digit runs that store.fastjson
needs to parse arbitrary JSON exactly (a third of the parsing time of a snapshot).

Staleness. A late event (one whose position is at or before a snapshot's) makes that snapshot
wrong. Rather than trust every writer to say so, the store keeps a watermark per run: the chain
length up to which the snapshots have been checked against the events. Appends lengthen the
chain, so the events a snapshot may not have seen are exactly those at chain positions at or
above the watermark; every read ignores snapshots at or after the earliest t among them, and
every snapshot write first deletes those snapshots and raises the watermark. This is correct
whoever appended. `enable_snapshots(store)` adds an append hook that does the same inside each
append transaction, so that a reader of a live run never has to look at unchecked events.
"""

from __future__ import annotations

import json
import sqlite3
import struct
import weakref
import zlib
from dataclasses import dataclass
from typing import Any, Iterable, Iterator

import orjson

from . import fastjson
from .db import Store

FOLD_VERSION = 4  # raise when the fold or the encoding changes: other versions are ignored

Position = tuple[int, int, str]  # (t, seq, src) of an event, the order of the fold
Fresh = tuple[Position, bytes]  # a snapshot folded but not yet written: position, encoded state

_DDL = (
    """CREATE TABLE IF NOT EXISTS state_snapshots (
        run TEXT NOT NULL,
        fold INTEGER NOT NULL,
        t INTEGER NOT NULL,
        seq INTEGER NOT NULL,
        src TEXT NOT NULL,
        state BLOB NOT NULL,
        PRIMARY KEY (run, fold, t, seq, src)
    )""",
    "CREATE TABLE IF NOT EXISTS state_watermarks (run TEXT PRIMARY KEY, chain_len INTEGER NOT NULL)",
)

_EXISTING = (
    "SELECT count(*) FROM sqlite_master "
    "WHERE type = 'table' AND name IN ('state_snapshots', 'state_watermarks')"
)
_NEAREST = (
    "SELECT t, seq, src, state FROM state_snapshots WHERE run = ? AND fold = ? AND t <= ? AND t < ? "
    "ORDER BY t DESC, seq DESC, src DESC LIMIT 1"
)
_INSERT = "INSERT OR REPLACE INTO state_snapshots (run, fold, t, seq, src, state) VALUES (?, ?, ?, ?, ?, ?)"
_T_MAX = (1 << 63) - 1
_HEADER = struct.Struct("<IB")  # size of the JSON, how it was written (below)
_BY_JSON, _BY_ORJSON = 0, 1  # by json: may hold any integer; by orjson: none beyond 64 bits
_LEVEL = 6  # zlib: a quarter smaller than level 1, so fewer pages to read, and as fast to inflate

# The last snapshot inflated, kept until the next replaces it. Freeing it at once let glibc hand
# the top of the heap back to the kernel after every read, and faulting those pages in again
# cost more than parsing the JSON on the virtual machine measured (bench/scene_at_t.py).
_last_inflated = b""

_ready: weakref.WeakSet[Store] = weakref.WeakSet()
_hooked: weakref.WeakSet[Store] = weakref.WeakSet()


@dataclass(frozen=True, slots=True)
class Snapshot:
    """A fold state as of `position`, ready to be folded further."""

    position: Position
    state: dict[str, Any]


# --- tables ----------------------------------------------------------------------------------


def ensure_tables(store: Store) -> None:
    """Create the cache tables if this file has none yet (looked at once per Store object, and
    without taking the write lock when they exist)."""
    if store in _ready:
        return
    conn = store.connection
    if conn.execute(_EXISTING).fetchone()[0] < len(_DDL):
        _create_tables(conn)
    _ready.add(store)


def has_tables(store: Store) -> bool:
    """Does the file hold the cache tables? (Asked without creating them.)"""
    return store in _ready or store.connection.execute(_EXISTING).fetchone()[0] == len(_DDL)


def _create_tables(conn: sqlite3.Connection) -> None:
    if conn.in_transaction:
        for statement in _DDL:
            conn.execute(statement)
        return
    conn.execute("BEGIN IMMEDIATE")
    try:
        for statement in _DDL:
            conn.execute(statement)
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise


def enable_snapshots(store: Store) -> None:
    """Keep this store's snapshots checked inside every append transaction.

    Optional for correctness (reads check what no hook has seen), but a process that appends to
    a run while others read it should call this once after opening the store: the check then
    costs the appender a short scan of its own batch instead of costing every reader a scan of
    everything appended since the last snapshot was written."""
    ensure_tables(store)
    if store not in _hooked:
        store.add_append_hook(_on_append)
        _hooked.add(store)


def _on_append(conn: sqlite3.Connection, run: str, min_t: int) -> None:
    """Append hook. min_t covers only this batch, while writers without the hook may have left
    earlier events unchecked, so the check starts from the watermark instead. A failure here
    (the cache tables were dropped) must not cost the append: the watermark then stays behind
    and the next reader does the check."""
    try:
        catch_up(conn, run)
    except sqlite3.OperationalError:
        pass


def clear(store: Store, run: str | None = None) -> None:
    """Delete the snapshots (of one run, or all): they are rebuilt as reads need them."""
    ensure_tables(store)
    where, params = ("", ()) if run is None else (" WHERE run = ?", (run,))
    conn = store.connection
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute(f"DELETE FROM state_snapshots{where}", params)
        conn.execute(f"DELETE FROM state_watermarks{where}", params)
        conn.execute("COMMIT")
    except BaseException:
        conn.execute("ROLLBACK")
        raise


def count(store: Store, run: str) -> int:
    ensure_tables(store)
    sql = "SELECT count(*) FROM state_snapshots WHERE run = ? AND fold = ?"
    return store.connection.execute(sql, (run, FOLD_VERSION)).fetchone()[0]


def disk_bytes(store: Store, run: str) -> int:
    """Bytes of compressed state held for a run (the blobs, not SQLite's page overhead)."""
    ensure_tables(store)
    sql = "SELECT coalesce(sum(length(state)), 0) FROM state_snapshots WHERE run = ?"
    return store.connection.execute(sql, (run,)).fetchone()[0]


# --- staleness --------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Marks:
    """Read together, in the reader's transaction: how long the run's chain is, and how much of
    it the snapshots have been checked against."""

    length: int
    checked: int

    @property
    def unchecked(self) -> bool:
        return self.checked != self.length


_MARKS = (
    "SELECT (SELECT max(chain_pos) FROM events WHERE run = ?1), "
    "(SELECT chain_len FROM state_watermarks WHERE run = ?1)"
)


def marks(conn: sqlite3.Connection, run: str) -> Marks:
    """Two index probes in one statement (this runs on every read)."""
    last, checked = conn.execute(_MARKS, (run,)).fetchone()
    return Marks(0 if last is None else last + 1, checked or 0)


def _earliest_since(conn: sqlite3.Connection, run: str, chain_pos: int) -> int | None:
    """The earliest t among the events appended at or after chain_pos."""
    sql = "SELECT min(t) FROM events WHERE run = ? AND chain_pos >= ?"
    return conn.execute(sql, (run, chain_pos)).fetchone()[0]


def _latest_t(conn: sqlite3.Connection, run: str) -> int | None:
    sql = "SELECT max(t) FROM state_snapshots WHERE run = ? AND fold = ?"
    return conn.execute(sql, (run, FOLD_VERSION)).fetchone()[0]


def stale_from(conn: sqlite3.Connection, run: str, seen: Marks) -> int:
    """Snapshots at or after this t may have missed an event; _T_MAX if none may have."""
    if not seen.unchecked or _latest_t(conn, run) is None:
        return _T_MAX
    if seen.checked > seen.length:  # the chain shrank: events were deleted behind the store's back
        return -_T_MAX - 1
    earliest = _earliest_since(conn, run, seen.checked)
    return _T_MAX if earliest is None else earliest


def catch_up(conn: sqlite3.Connection, run: str) -> None:
    """Delete the snapshots unchecked events make stale and raise the watermark to the chain's
    length. Runs inside the caller's write transaction."""
    seen = marks(conn, run)
    stale = stale_from(conn, run, seen)
    if stale != _T_MAX:
        sql = "DELETE FROM state_snapshots WHERE run = ? AND fold = ? AND t >= ?"
        conn.execute(sql, (run, FOLD_VERSION, stale))
    conn.execute(
        "INSERT INTO state_watermarks (run, chain_len) VALUES (?, ?) "
        "ON CONFLICT (run) DO UPDATE SET chain_len = excluded.chain_len",
        (run, seen.length),
    )


# --- reading and writing ----------------------------------------------------------------------


def nearest(conn: sqlite3.Connection, run: str, t: int, seen: Marks) -> Snapshot | None:
    """The latest usable snapshot at or before t, given the marks read in the same transaction.
    A snapshot that cannot be decoded is passed over (the cache was damaged)."""
    before = stale_from(conn, run, seen)
    row = conn.execute(_NEAREST, (run, FOLD_VERSION, t, before)).fetchone()
    while row is not None:
        state = decode(row[3])
        if state is not None:
            return Snapshot((row[0], row[1], row[2]), state)
        row = conn.execute(_NEAREST, (run, FOLD_VERSION, row[0] - 1, before)).fetchone()
    return None


def listed(conn: sqlite3.Connection, run: str, before: int = _T_MAX) -> Iterator[Snapshot]:
    """The run's snapshots before t `before`, oldest first, one at a time; an undecodable one
    comes with an empty state (it can never equal a fold)."""
    sql = (
        "SELECT t, seq, src, state FROM state_snapshots WHERE run = ? AND fold = ? AND t < ? "
        "ORDER BY t, seq, src"
    )
    for t, seq, src, blob in conn.execute(sql, (run, FOLD_VERSION, before)):
        yield Snapshot((t, seq, src), decode(blob, exact=True) or {})


def save(conn: sqlite3.Connection, run: str, fresh: Iterable[Fresh], read_length: int) -> bool:
    """Store snapshots folded from a read that saw the first read_length events of the chain.

    In one write transaction: check the events no snapshot has been checked against, then keep
    only the fresh snapshots that no event appended since the read precedes. Returns False,
    having written nothing, when the file cannot be written now (locked, read-only): the cache
    is an optimisation, so the caller carries on without it."""
    try:
        conn.execute("BEGIN IMMEDIATE")
    except sqlite3.OperationalError:
        return False
    try:
        late = _earliest_since(conn, run, read_length)
        catch_up(conn, run)
        kept = [(position, blob) for position, blob in fresh if late is None or position[0] < late]
        conn.executemany(_INSERT, [(run, FOLD_VERSION, *position, blob) for position, blob in kept])
        conn.execute("DELETE FROM state_snapshots WHERE run = ? AND fold < ?", (run, FOLD_VERSION))
        conn.execute("COMMIT")
    except sqlite3.OperationalError:
        conn.execute("ROLLBACK")
        return False
    except BaseException:
        conn.execute("ROLLBACK")
        raise
    return True


def encode(state: dict[str, Any]) -> bytes:
    """The JSON's length and writer, then the JSON deflated: knowing the length up front lets
    zlib inflate into one buffer instead of growing one (a third of the inflating time)."""
    try:
        text, writer = orjson.dumps(state), _BY_ORJSON
    except TypeError:  # an integer beyond 64 bits (or anything else orjson will not write)
        text = json.dumps(state, separators=(",", ":"), ensure_ascii=False, allow_nan=False).encode("utf-8")
        writer = _BY_JSON
    return _HEADER.pack(len(text), writer) + zlib.compress(text, _LEVEL)


def decode(blob: bytes, *, exact: bool = False) -> dict[str, Any] | None:
    """The state in a snapshot, or None if the blob is not one (damaged or foreign).

    A snapshot written by orjson is parsed by orjson alone, unless `exact`: then it is parsed
    like any JSON, so that a blob altered to hold a longer integer than orjson can read is read
    as written (check_snapshots compares what the file says, not what orjson makes of it)."""
    global _last_inflated
    try:
        size, writer = _HEADER.unpack_from(blob)
        _last_inflated = zlib.decompress(blob[_HEADER.size:], bufsize=max(size, 1))
        if writer == _BY_ORJSON and not exact:
            state = orjson.loads(_last_inflated)
        elif writer in (_BY_JSON, _BY_ORJSON):
            state = fastjson.loads(_last_inflated)
        else:
            return None
    except (struct.error, zlib.error, ValueError, TypeError):
        return None
    return state if isinstance(state, dict) else None
