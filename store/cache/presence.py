"""Where each road user was, coarsely: per source and BUCKET_S of time, the box its entity.state
positions fill. Derived data, kept in the cache file (store/cache.py).

The question it answers is the reasoner's "who came near this junction in this window?" at a
junction whose arms no camera watches: without it every road user's states of the window are
read and measured (a second of a 200-vehicle run is 2,000 events) to keep the few that came
near. With it, only the sources whose box meets the place are read, and the reader measures
them exactly as before: the index only ever says who *might* have been there, so it can make a
read cheaper but cannot change what the read finds, as long as every position a sample can
carry lies inside its box.

That holds by construction: a sample is placed only when its x and y are JSON numbers
(reasoner/junctions.finite), and the box takes every event whose x and y are JSON numbers
(booleans too, which SQLite reads as 0 and 1: a wider box, never a narrower one).

Staleness works as for the snapshots (store/snapshots.py): a watermark per run holds the chain
length and head hash up to which the boxes cover the events. A box only grows as events are
appended, so events appended since (late ones included) are merged in on the next read; a
watermark naming a chain this store does not hold drops the run's boxes, which are rebuilt.
`check_presence` (run by `gaps verify --snapshots`) recomputes them from the events.

Sealed (store/cache_seal.py): each box under its run, bucket and source; the watermark under its
run, with the chain length and head, the number of boxes and the XOR of their seals. A box
removed (a road user hidden), altered, added or put back from an older cache breaks the seal or
the XOR, and the run's boxes are then rebuilt from the events, never believed. The whole set is
checked once per process and chain head (a scan of the run's boxes), each box a read finds again.
"""

from __future__ import annotations

import sqlite3
import weakref

from dataclasses import dataclass
from typing import TYPE_CHECKING

from .file import writing as _writing
from .seal import NO_ENTRIES, xor
if TYPE_CHECKING:                       # annotations only: the store's faces load before db is done
    from ..db import Store
from .snapshots import chain_end, hash_at

BUCKET_S = 2
_BUCKET_NS = BUCKET_S * 1_000_000_000

Box = tuple[str, int, float, float, float, float]  # src, bucket, x0, x1, y0, y1

# Boxes a read had to keep in memory (the cache locked by another writer), per store: (run, chain
# length, head) -> boxes, so that the acts judged after it do not scan the run again.
_in_memory: weakref.WeakKeyDictionary[Store, dict[tuple[str, int, str], list[Box]]] = weakref.WeakKeyDictionary()

# One pass over the run's entity.state events from a chain position: json_extract once per
# value (a materialised CTE, else SQLite repeats it for every use of x and y), then the boxes.
# SQLite's integer division truncates toward zero; bucket() below does the same.
_BOXES = """
WITH p AS MATERIALIZED (
    SELECT src, t / ? AS b, json_extract(event, '$.body.x') AS x, json_extract(event, '$.body.y') AS y
    FROM events WHERE run = ? AND chain_pos >= ? AND chain_pos < ? AND kind = 'entity.state')
SELECT src, b, min(x), max(x), min(y), max(y) FROM p
WHERE typeof(x) IN ('integer', 'real') AND typeof(y) IN ('integer', 'real')
GROUP BY src, b"""

_PUT = "INSERT OR REPLACE INTO presence (run, bucket, src, x0, x1, y0, y1, mac) VALUES (?, ?, ?, ?, ?, ?, ?, ?)"
_HELD = "SELECT x0, x1, y0, y1, mac FROM presence WHERE run = ? AND bucket = ? AND src = ?"

_NEAR = """
SELECT src, bucket, x0, x1, y0, y1, mac FROM presence
WHERE run = ? AND bucket >= ? AND bucket <= ? AND x1 >= ? AND x0 <= ? AND y1 >= ? AND y0 <= ?
ORDER BY src"""

BOXES, MARKS = "presence", "presence_marks"

PAD_M = 1e-6   # the square is this much wider: a point at exactly radius_m (rounded) is never left out


@dataclass(frozen=True, slots=True)
class _Marks:
    """A run's watermark, its seal opened: the chain the boxes cover, how many, their seals' XOR."""

    chain_len: int
    head: str
    boxes: int
    digest: bytes


def bucket(t: int) -> int:
    """The bucket of a time, as _BOXES computes it (division truncated toward zero)."""
    return t // _BUCKET_NS if t >= 0 else -((-t) // _BUCKET_NS)


def sources_near(store: Store, run: str, x: float, y: float, radius_m: float, t_from: int,
                 t_to: int) -> list[str]:
    """The sources whose entity.state put them within the square of half-side radius_m around
    (x, y) at some time in the buckets that meet [t_from, t_to]: every source that can have a
    placed state within radius_m of the point in the window, and some that did not."""
    boxes = _current(store, run)
    reach = radius_m + PAD_M
    params = (bucket(t_from), bucket(t_to), x - reach, x + reach, y - reach, y + reach)
    if boxes is None:
        found = store.cache.connection.execute(_NEAR, (run, *params)).fetchall()
        sealer = store.cache.sealer
        if all(sealer.opens(BOXES, (run, b, src), (x0, x1, y0, y1), mac) for src, b, x0, x1, y0, y1, mac in found):
            return sorted({row[0] for row in found})
        store.cache.memo.pop(("presence", run), None)  # changed since it was checked: not believed
        boxes = _boxes(store, run, 0, chain_end(store.connection, run)[0])
    return sorted({src for src, b, x0, x1, y0, y1 in boxes if params[0] <= b <= params[1]
                   and x1 >= params[2] and x0 <= params[3] and y1 >= params[4] and y0 <= params[5]})


def _current(store: Store, run: str) -> list[Box] | None:
    """Bring the run's boxes in the cache up to the store's chain. None when they are there;
    the boxes themselves when the cache could not take them (locked by another writer, or read
    only): this read then uses them from memory."""
    length, head = chain_end(store.connection, run)
    held = _marks(store, run)
    if held is not None and (held.chain_len, held.head) == (length, head) and _sound(store, run, held):
        return None
    try:
        with _writing(store.cache.connection):
            _catch_up(store, run, length, head)
        return None
    except sqlite3.OperationalError as exc:    # locked, a full disk, a read-only folder: boxes in memory
        store.cache.failed_to_write(exc)
        kept = _in_memory.setdefault(store, {})
        if (run, length, head) not in kept:
            kept.clear()
            kept[(run, length, head)] = _boxes(store, run, 0, length)
        return kept[(run, length, head)]


def _marks(store: Store, run: str, *, count: bool = True) -> _Marks | None:
    """The run's watermark if there is one and it carries its seal."""
    row = store.cache.connection.execute(
        "SELECT chain_len, head, boxes, digest, mac FROM presence_marks WHERE run = ?", (run,)).fetchone()
    if row is None or not store.cache.sealer.opens(MARKS, (run,), tuple(row[:4]), row[4], count=count):
        return None
    return _Marks(*row[:4])


def _sound(store: Store, run: str, held: _Marks, *, count: bool = True) -> bool:
    """Are the run's boxes exactly those the watermark sealed (each box's seal opens, and their
    number and XOR are the watermark's)? Scanned once per process and watermark."""
    memo = ("presence", run)
    if store.cache.memo.get(memo) == held:
        return True
    sealer, number, digest = store.cache.sealer, 0, NO_ENTRIES
    for b, src, x0, x1, y0, y1, mac in store.cache.connection.execute(
            "SELECT bucket, src, x0, x1, y0, y1, mac FROM presence WHERE run = ?", (run,)):
        if not sealer.opens(BOXES, (run, b, src), (x0, x1, y0, y1), mac, count=count):
            return False
        number, digest = number + 1, xor(digest, mac)
    if (number, digest) != (held.boxes, held.digest):
        if count:
            sealer.dropped[MARKS] += 1
        return False
    store.cache.memo[memo] = held
    return True


def _catch_up(store: Store, run: str, length: int, head: str) -> None:
    """Inside the cache's write transaction: merge in what the watermark has not covered, each
    box merged in Python so that it is sealed as written."""
    cache, sealer = store.cache.connection, store.cache.sealer
    held = _marks(store, run, count=False)
    if (held is not None and 0 < held.chain_len <= length
            and hash_at(store.connection, run, held.chain_len - 1) == held.head
            and _sound(store, run, held, count=False)):  # a failure was counted by the read that came here
        covered, number, digest = held.chain_len, held.boxes, held.digest
    else:       # none yet, of another chain, or not as sealed
        cache.execute("DELETE FROM presence WHERE run = ?", (run,))
        covered, number, digest = 0, 0, NO_ENTRIES
    put = []        # written together: _boxes gives each (bucket, src) once, so no box read below is one put
    for src, b, x0, x1, y0, y1 in (_boxes(store, run, covered, length) if covered < length else ()):
        old = cache.execute(_HELD, (run, b, src)).fetchone() if covered else None
        if old is None:
            number += 1
        else:
            x0, x1, y0, y1 = min(x0, old[0]), max(x1, old[1]), min(y0, old[2]), max(y1, old[3])
            digest = xor(digest, old[4])
        x0, x1, y0, y1 = _stored(x0), _stored(x1), _stored(y0), _stored(y1)
        mac = sealer.seal(BOXES, (run, b, src), (x0, x1, y0, y1))
        digest = xor(digest, mac)
        put.append((run, b, src, x0, x1, y0, y1, mac))
    cache.executemany(_PUT, put)
    marks = (length, head, number, digest)
    cache.execute("INSERT OR REPLACE INTO presence_marks (run, chain_len, head, boxes, digest, mac) "
                  "VALUES (?, ?, ?, ?, ?, ?)", (run, *marks, sealer.seal(MARKS, (run,), marks)))
    store.cache.memo[("presence", run)] = _Marks(*marks)


def _stored(value: int | float) -> float:
    """A box's bound as its REAL column gives it back, which is what its seal must cover: a float
    (a JSON whole number, x 0, is an INTEGER min, read back as 0.0), and 0.0 for -0.0 (SQLite
    writes a whole REAL as an integer, and -0.0 comes back as 0.0). Sealed otherwise, the box's
    seal never opened: verify called the cache tampered, and every read meeting the box rebuilt
    the run's boxes from all its events (the hour: 3 boxes of 470,438, half its first judgement)."""
    return float(value) + 0.0       # -0.0 + 0.0 is 0.0; every other value is left as it is


def _boxes(store: Store, run: str, start: int, end: int) -> list[Box]:
    return store.connection.execute(_BOXES, (_BUCKET_NS, run, start, end)).fetchall()


def check_presence(store: Store, run: str) -> list[tuple[str, int]]:
    """(src, bucket) of every box the cache holds for the part of the chain its watermark
    covers that differs from the events (a box missing, added or changed). A cache whose
    watermark is of another chain is not used, so it has nothing wrong to report; a store
    without a cache is left without one."""
    if not store.cache.exists():
        return []
    cache = store.cache.connection
    held = _marks(store, run, count=False)
    if held is None or not (held.chain_len > 0 and hash_at(store.connection, run, held.chain_len - 1) == held.head):
        return []
    if not _sound(store, run, held, count=False):
        return []  # never used: reported by tampered_presence, rebuilt by the next read
    fresh = {(src, b): box for src, b, *box in _boxes(store, run, 0, held.chain_len)}
    cached = {(src, b): [x0, x1, y0, y1] for src, b, x0, x1, y0, y1 in cache.execute(
        "SELECT src, bucket, x0, x1, y0, y1 FROM presence WHERE run = ?", (run,))}
    return sorted(key for key in fresh.keys() | cached.keys() if fresh.get(key) != cached.get(key))


def tampered_presence(store: Store, run: str) -> list[str]:
    """What of the run's cached boxes does not carry its seal ([] if nothing, or no cache): such
    entries are never used, but someone wrote them (for `gaps verify`)."""
    if not store.cache.exists():
        return []
    row = store.cache.connection.execute("SELECT 1 FROM presence_marks WHERE run = ?", (run,)).fetchone()
    held = _marks(store, run, count=False)
    if held is None:
        boxes = store.cache.connection.execute("SELECT count(*) FROM presence WHERE run = ?", (run,)).fetchone()[0]
        return ["the watermark of the boxes does not carry its seal"] if row is not None or boxes else []
    if not _sound(store, run, held, count=False):
        return ["the boxes of where road users were are not those sealed (one altered, added or removed)"]
    return []
