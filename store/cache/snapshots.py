"""Snapshots of folded state: a cache that makes state at any t cost one snapshot load plus a
short fold, however long the run.

The snapshots are derived data, not evidence: they live in the cache file (store/cache.py), not
in the store, are neither hash-chained nor append-only, and may be deleted at any time: they are
rebuilt from the events on the next read. A snapshot is keyed by the position (t, seq, src) of
the last event folded into it, and records the chain it was folded from (the run's chain length
and head hash when it was read), which is checked against the store before it is used, so a
snapshot of another chain (another store, a store replaced, a forged entry) is never used. It
holds the fold state as zlib-compressed JSON (compressed about eightfold, so
fewer pages to read; inflating costs a fraction of parsing). The JSON is written by orjson when
it can be, and the blob says so: orjson refuses to write an integer beyond 64 bits, so such a
snapshot can be parsed by orjson without the search for long digit runs that store.fastjson
needs to parse arbitrary JSON exactly (a third of the parsing time of a snapshot).

Staleness. A late event (one whose position is at or before a snapshot's) makes that snapshot
wrong. Rather than trust every writer to say so, the cache keeps a watermark per run: the chain
length (and the head hash there) up to which the snapshots have been checked against the events.
Appends lengthen the chain, so the events a snapshot may not have seen are exactly those at
chain positions at or above the watermark; every read ignores snapshots at or after the earliest
t among them, and every snapshot write first deletes those snapshots and raises the watermark. A
watermark whose head is not the store's hash at that length belongs to another chain: then every
snapshot of the run is ignored, and dropped on the next write. This is correct whoever appended.
`enable_snapshots(store)` adds an append hook that does the same after each append, so that a
reader of a live run never has to look at unchecked events.

Sealed (store/cache_seal.py): a snapshot under its run, fold version, position and the chain it
was folded from; a watermark under its run, with its chain length and head. A snapshot that does
not carry its seal is passed over (and deleted when the cache can be written), a watermark that
does not counts as none (every snapshot of the run is then unchecked): forged entries are never
believed. A genuine snapshot put back after a late event made it stale is passed over too: each
time late events make snapshots stale, the run's watermark starts a new epoch, the snapshots kept
are sealed again under it, and a read uses only snapshots of the watermark's epoch.
"""

from __future__ import annotations

import json
import sqlite3
import struct
import weakref
import zlib
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Iterable, Iterator

import orjson

from .. import fastjson
from .file import rollback, writing as _writing
if TYPE_CHECKING:                       # annotations only: the store's faces load before db is done
    from ..db import Store

FOLD_VERSION = 4  # raise when the fold or the encoding changes: other versions are ignored

Position = tuple[int, int, str]  # (t, seq, src) of an event, the order of the fold
Fresh = tuple[Position, bytes]  # a snapshot folded but not yet written: position, encoded state

SNAPSHOTS, WATERMARKS = "state_snapshots", "state_watermarks"
_NEAREST = (
    "SELECT t, seq, src, chain_len, head, state, mac, epoch FROM state_snapshots "
    "WHERE run = ? AND fold = ? AND t <= ? AND t < ? ORDER BY t DESC, seq DESC, src DESC LIMIT 1"
)
_INSERT = (
    "INSERT OR REPLACE INTO state_snapshots (run, fold, t, seq, src, chain_len, head, state, epoch, mac) "
    "VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"
)
_HASH_AT = "SELECT hash FROM events WHERE run = ? AND chain_pos = ?"
_T_MAX = (1 << 63) - 1
_T_MIN = -_T_MAX - 1
_HEADER = struct.Struct("<IB")  # size of the JSON, how it was written (below)
_BY_JSON, _BY_ORJSON = 0, 1  # by json: may hold any integer; by orjson: none beyond 64 bits
_LEVEL = 6  # zlib: a quarter smaller than level 1, so fewer pages to read, and as fast to inflate

# The last snapshot inflated, kept until the next replaces it. Freeing it at once let glibc hand
# the top of the heap back to the kernel after every read, and faulting those pages in again
# cost more than parsing the JSON on the virtual machine measured (bench/scene_at_t.py).
_last_inflated = b""

_hooked: weakref.WeakSet[Store] = weakref.WeakSet()


@dataclass(frozen=True, slots=True)
class Snapshot:
    """A fold state as of `position`, ready to be folded further."""

    position: Position
    state: dict[str, Any]


# --- the cache ---------------------------------------------------------------------------------


def ensure_tables(store: Store) -> None:
    """Open the store's cache (creating its file and tables if need be)."""
    store.cache.connection


def has_tables(store: Store) -> bool:
    """Does the store have a cache yet? (Asked without creating one.)"""
    return store.cache.exists()


def enable_snapshots(store: Store) -> None:
    """Keep this store's snapshots checked after every append.

    Optional for correctness (reads check what no hook has seen), but a process that appends to
    a run while others read it should call this once after opening the store: the check then
    costs the appender a short scan of its own batch instead of costing every reader a scan of
    everything appended since the last snapshot was written."""
    ensure_tables(store)
    if store not in _hooked:
        store.add_append_hook(_on_append)
        _hooked.add(store)


def _on_append(store: Store, earliest: dict[str, int]) -> None:
    """Append hook: every run the append stored events of caught up, in one cache transaction (a
    commit of the cache per run was most of a fleet's ingest). The batch's min_t covers only this
    batch, while writers without the hook may have left earlier events unchecked, so each check
    starts from its run's watermark instead. A failure here (the cache is locked or gone) must not
    cost the append: the watermarks then stay behind and the next reader does the check."""
    try:
        with _writing(store.cache.connection):
            for run in earliest:
                catch_up(store, run)
    except sqlite3.OperationalError as exc:
        store.cache.failed_to_write(exc)


def clear(store: Store, run: str | None = None) -> None:
    """Delete the snapshots (of one run, or all): they are rebuilt as reads need them."""
    where, params = ("", ()) if run is None else (" WHERE run = ?", (run,))
    with _writing(store.cache.connection) as cache:
        cache.execute(f"DELETE FROM state_snapshots{where}", params)
        cache.execute(f"DELETE FROM state_watermarks{where}", params)


def count(store: Store, run: str) -> int:
    sql = "SELECT count(*) FROM state_snapshots WHERE run = ? AND fold = ?"
    return store.cache.connection.execute(sql, (run, FOLD_VERSION)).fetchone()[0]


def disk_bytes(store: Store, run: str) -> int:
    """Bytes of compressed state held for a run (the blobs, not SQLite's page overhead)."""
    sql = "SELECT coalesce(sum(length(state)), 0) FROM state_snapshots WHERE run = ?"
    return store.cache.connection.execute(sql, (run,)).fetchone()[0]


# --- staleness --------------------------------------------------------------------------------


@dataclass(frozen=True, slots=True)
class Marks:
    """How long the run's chain is and its head hash (read in the reader's transaction), and how
    much of it the snapshots have been checked against (0 if the cache's watermark names a
    chain this store does not hold: then nothing in the cache is trusted)."""

    length: int
    head: str
    checked: int
    agrees: bool = True
    epoch: int = -1
    """The watermark's epoch (-1 without a sealed watermark: no snapshot is of it)."""

    @property
    def unchecked(self) -> bool:
        return not self.agrees or self.checked != self.length


def hash_at(conn: sqlite3.Connection, run: str, chain_pos: int) -> str | None:
    """The stored hash of the run's event at this chain position (None before the first)."""
    if chain_pos < 0:
        return None
    row = conn.execute(_HASH_AT, (run, chain_pos)).fetchone()
    return None if row is None else row[0]


def chain_end(conn: sqlite3.Connection, run: str) -> tuple[int, str]:
    """The run's chain length and head hash ("" for none): two index probes, what a cache of
    derived data is keyed by."""
    (last,) = conn.execute("SELECT max(chain_pos) FROM events WHERE run = ?", (run,)).fetchone()
    length = 0 if last is None else last + 1
    return length, hash_at(conn, run, length - 1) or ""


def marks(store: Store, run: str, end: tuple[int, str] | None = None) -> Marks:
    """A few index probes (this runs on every read). `end`: the chain's (length, head) as the
    append whose hook asks committed it (Store.appended_end), instead of read back."""
    conn = store.connection
    length, head = chain_end(conn, run) if end is None else end
    row = _watermark(store, run)
    if row is None:
        return Marks(length, head, 0)
    checked, checked_head, epoch = row
    agrees = checked <= length and (checked == 0 or hash_at(conn, run, checked - 1) == checked_head)
    return Marks(length, head, checked if agrees else 0, agrees, epoch if agrees else -1)


def _watermark(store: Store, run: str, *, count: bool = True) -> tuple[int, str, int] | None:
    """The run's watermark (chain length, head, epoch) if it carries its seal."""
    row = store.cache.connection.execute(
        "SELECT chain_len, head, epoch, mac FROM state_watermarks WHERE run = ?", (run,)).fetchone()
    if row is None or not store.cache.sealer.opens(WATERMARKS, (run,), tuple(row[:3]), row[3], count=count):
        return None
    return row[0], row[1], row[2]


def _earliest_since(conn: sqlite3.Connection, run: str, chain_pos: int) -> int | None:
    """The earliest t among the events appended at or after chain_pos."""
    sql = "SELECT min(t) FROM events WHERE run = ? AND chain_pos >= ?"
    return conn.execute(sql, (run, chain_pos)).fetchone()[0]


def _latest_t(cache: sqlite3.Connection, run: str) -> int | None:
    sql = "SELECT max(t) FROM state_snapshots WHERE run = ? AND fold = ?"
    return cache.execute(sql, (run, FOLD_VERSION)).fetchone()[0]


def stale_from(store: Store, run: str, seen: Marks) -> int:
    """Snapshots at or after this t may have missed an event; _T_MAX if none may have."""
    if not seen.agrees:
        return _T_MIN
    if not seen.unchecked or _latest_t(store.cache.connection, run) is None:
        return _T_MAX
    earliest = _earliest_since(store.connection, run, seen.checked)
    return _T_MAX if earliest is None else earliest


def catch_up(store: Store, run: str) -> None:
    """Delete the snapshots unchecked events make stale and raise the watermark to the chain's
    length. Runs inside the caller's write transaction on the cache."""
    seen = marks(store, run, store.appended_end(run))
    stale = stale_from(store, run, seen)
    cache = store.cache.connection
    epoch = max(seen.epoch, 0)
    if stale != _T_MAX:
        sql = "DELETE FROM state_snapshots WHERE run = ? AND t >= ?"
        if cache.execute(sql, (run, stale)).rowcount or seen.epoch < 0:
            epoch = _new_epoch(store, run, seen.epoch)
    values = (seen.length, seen.head, epoch)
    cache.execute("INSERT OR REPLACE INTO state_watermarks (run, chain_len, head, epoch, mac) VALUES (?, ?, ?, ?, ?)",
                  (run, *values, store.cache.sealer.seal(WATERMARKS, (run,), values)))


def _new_epoch(store: Store, run: str, epoch: int) -> int:
    """Snapshots were dropped as stale: seal the run's remaining ones under a new epoch, so that a
    dropped one put back (by whoever kept a copy) is not of the watermark's epoch. The new epoch is
    above any the file holds, so an old watermark put back cannot name it either."""
    cache, sealer = store.cache.connection, store.cache.sealer
    (top,) = cache.execute("SELECT max(epoch) FROM state_snapshots WHERE run = ?", (run,)).fetchone()
    fresh = max(epoch, top if isinstance(top, int) else 0) + 1
    rows = cache.execute("SELECT t, seq, src, chain_len, head, state, mac, epoch FROM state_snapshots "
                         "WHERE run = ? AND fold = ? AND epoch = ?", (run, FOLD_VERSION, epoch)).fetchall()
    cache.execute("DELETE FROM state_snapshots WHERE run = ? AND epoch <> ?", (run, epoch))  # of no epoch in use
    for row in rows:
        if sealer.opens(SNAPSHOTS, _seal_key(run, row), (row[5], epoch), row[6]):
            cache.execute("UPDATE state_snapshots SET epoch = ?, mac = ? WHERE run = ? AND fold = ? AND t = ? "
                          "AND seq = ? AND src = ?", (fresh, sealer.seal(SNAPSHOTS, _seal_key(run, row), (row[5], fresh)),
                                                      run, FOLD_VERSION, row[0], row[1], row[2]))
        else:
            cache.execute("DELETE FROM state_snapshots WHERE run = ? AND fold = ? AND t = ? AND seq = ? AND src = ?",
                          (run, FOLD_VERSION, row[0], row[1], row[2]))
    return fresh


# --- reading and writing ----------------------------------------------------------------------


def _of_this_chain(store: Store, run: str, chain_len: Any, head: Any, seen: Marks) -> bool:
    """Was a snapshot folded from a prefix of the chain the store holds now?"""
    return (isinstance(chain_len, int) and 0 < chain_len <= seen.length
            and hash_at(store.connection, run, chain_len - 1) == head)


def _seal_key(run: str, row: tuple) -> tuple:
    """What names a snapshot row (t, seq, src, chain_len, head, ...): its seal covers these."""
    return (run, FOLD_VERSION, row[0], row[1], row[2], row[3], row[4])


def _usable(store: Store, run: str, row: tuple, seen: Marks, *, count: bool = True) -> bool:
    """May a read use this snapshot row (t, seq, src, chain_len, head, state, mac, epoch)? Of this
    chain and of the watermark's epoch, and sealed by this code."""
    return (_of_this_chain(store, run, row[3], row[4], seen) and row[7] == seen.epoch
            and store.cache.sealer.opens(SNAPSHOTS, _seal_key(run, row), (row[5], row[7]), row[6], count=count))


def _drop(store: Store, run: str, row: tuple) -> None:
    """Delete a snapshot that is not to be believed, if the cache can be written now."""
    try:
        store.cache.connection.execute(
            "DELETE FROM state_snapshots WHERE run = ? AND fold = ? AND t = ? AND seq = ? AND src = ?",
            (run, FOLD_VERSION, row[0], row[1], row[2]))
    except sqlite3.DatabaseError as exc:
        store.cache.failed_to_write(exc)


def nearest(store: Store, run: str, t: int, seen: Marks) -> Snapshot | None:
    """The latest usable snapshot at or before t, given the marks read in the same transaction.
    A snapshot that cannot be decoded, or that names a chain the store does not hold, is passed
    over (the cache was damaged, or belongs elsewhere)."""
    before = stale_from(store, run, seen)
    cache = store.cache.connection
    row = cache.execute(_NEAREST, (run, FOLD_VERSION, t, before)).fetchone()
    while row is not None:
        if _of_this_chain(store, run, row[3], row[4], seen) and row[7] == seen.epoch:
            if not store.cache.sealer.opens(SNAPSHOTS, _seal_key(run, row), (row[5], row[7]), row[6]):
                _drop(store, run, row)  # written behind gaps' back (of another epoch: perhaps a race, kept)
            elif (state := decode(row[5])) is not None:
                return Snapshot((row[0], row[1], row[2]), state)
        row = cache.execute(_NEAREST, (run, FOLD_VERSION, row[0] - 1, before)).fetchone()
    return None


def listed(store: Store, run: str, seen: Marks) -> Iterator[Snapshot]:
    """The run's usable snapshots (those a read may use), oldest first, one at a time; an
    undecodable one comes with an empty state (it can never equal a fold)."""
    sql = (
        "SELECT t, seq, src, chain_len, head, state, mac, epoch FROM state_snapshots "
        "WHERE run = ? AND fold = ? AND t < ? ORDER BY t, seq, src"
    )
    rows = store.cache.connection.execute(sql, (run, FOLD_VERSION, stale_from(store, run, seen))).fetchall()
    for row in rows:
        if _usable(store, run, row, seen, count=False):
            yield Snapshot((row[0], row[1], row[2]), decode(row[5], exact=True) or {})


def tampered_snapshots(store: Store, run: str) -> list[Position]:
    """Positions of the run's snapshots (of this fold version) and its watermark that do not carry
    their seals: never used by a read, but written by someone else (for `gaps verify`)."""
    if not has_tables(store):
        return []
    cache, sealer = store.cache.connection, store.cache.sealer
    rows = cache.execute("SELECT t, seq, src, chain_len, head, state, mac, epoch FROM state_snapshots "
                         "WHERE run = ? AND fold = ? ORDER BY t, seq, src", (run, FOLD_VERSION)).fetchall()
    wrong = [tuple(row[:3]) for row in rows
             if not sealer.opens(SNAPSHOTS, _seal_key(run, row), (row[5], row[7]), row[6], count=False)]
    has_mark = cache.execute("SELECT 1 FROM state_watermarks WHERE run = ?", (run,)).fetchone() is not None
    if has_mark and _watermark(store, run, count=False) is None:
        wrong.append((-1, -1, "(watermark)"))
    return wrong


def save(store: Store, run: str, fresh: Iterable[Fresh], seen: Marks) -> bool:
    """Store snapshots folded from a read that saw the chain as `seen` says.

    In one write transaction on the cache: check the events no snapshot has been checked
    against, then keep only the fresh snapshots that no event appended since the read precedes
    (none, if the chain read is no longer the store's). Returns False, having written nothing,
    when the cache cannot be written now (locked, read-only): it is an optimisation, so the
    caller carries on without it."""
    cache = store.cache.connection
    try:
        cache.execute("BEGIN IMMEDIATE")
    except sqlite3.DatabaseError as exc:
        store.cache.failed_to_write(exc)
        return False
    try:
        late = _earliest_since(store.connection, run, seen.length)
        if hash_at(store.connection, run, seen.length - 1) != (seen.head or None):
            late = _T_MIN
        catch_up(store, run)
        kept = [(position, blob) for position, blob in fresh if late is None or position[0] < late]
        sealer, epoch = store.cache.sealer, marks(store, run).epoch  # the watermark catch_up just wrote
        cache.executemany(_INSERT, [
            (run, FOLD_VERSION, *position, seen.length, seen.head, blob, epoch,
             sealer.seal(SNAPSHOTS, (run, FOLD_VERSION, *position, seen.length, seen.head), (blob, epoch)))
            for position, blob in kept])
        cache.execute("DELETE FROM state_snapshots WHERE run = ? AND fold < ?", (run, FOLD_VERSION))
        cache.execute("COMMIT")
    except sqlite3.OperationalError as exc:    # a full disk, a read-only folder: the snapshots go unkept
        rollback(cache)
        store.cache.failed_to_write(exc)
        return False
    except BaseException:
        rollback(cache)
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
