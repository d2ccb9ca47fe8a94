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
`check_presence` (run by `gaps verify --snapshots`) recomputes them from the events, because
whoever can write the cache file could otherwise hide a road user from the reasoner.
"""

from __future__ import annotations

import sqlite3
import weakref

from .cache import writing as _writing
from .db import Store
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

_MERGE = """
INSERT INTO presence (run, bucket, src, x0, x1, y0, y1) VALUES (?, ?, ?, ?, ?, ?, ?)
ON CONFLICT (run, bucket, src) DO UPDATE SET
    x0 = min(x0, excluded.x0), x1 = max(x1, excluded.x1),
    y0 = min(y0, excluded.y0), y1 = max(y1, excluded.y1)"""

_NEAR = """
SELECT DISTINCT src FROM presence
WHERE run = ? AND bucket >= ? AND bucket <= ? AND x1 >= ? AND x0 <= ? AND y1 >= ? AND y0 <= ?
ORDER BY src"""


def bucket(t: int) -> int:
    """The bucket of a time, as _BOXES computes it (division truncated toward zero)."""
    return t // _BUCKET_NS if t >= 0 else -((-t) // _BUCKET_NS)


def sources_near(store: Store, run: str, x: float, y: float, radius_m: float, t_from: int,
                 t_to: int) -> list[str]:
    """The sources whose entity.state put them within the square of half-side radius_m around
    (x, y) at some time in the buckets that meet [t_from, t_to]: every source that can have a
    placed state within radius_m of the point in the window, and some that did not."""
    boxes = _current(store, run)
    params = (bucket(t_from), bucket(t_to), x - radius_m, x + radius_m, y - radius_m, y + radius_m)
    if boxes is not None:
        return sorted({src for src, b, x0, x1, y0, y1 in boxes if params[0] <= b <= params[1]
                       and x1 >= params[2] and x0 <= params[3] and y1 >= params[4] and y0 <= params[5]})
    return [src for (src,) in store.cache.connection.execute(_NEAR, (run, *params))]


def _current(store: Store, run: str) -> list[Box] | None:
    """Bring the run's boxes in the cache up to the store's chain. None when they are there;
    the boxes themselves when the cache could not take them (locked by another writer, or read
    only): this read then uses them from memory."""
    length, head = chain_end(store.connection, run)
    cache = store.cache.connection
    row = cache.execute("SELECT chain_len, head FROM presence_marks WHERE run = ?", (run,)).fetchone()
    if row is not None and row[0] == length and row[1] == head:
        return None
    try:
        with _writing(cache):
            _catch_up(store, run, length, head)
        return None
    except sqlite3.OperationalError:
        kept = _in_memory.setdefault(store, {})
        if (run, length, head) not in kept:
            kept.clear()
            kept[(run, length, head)] = _boxes(store, run, 0, length)
        return kept[(run, length, head)]


def _catch_up(store: Store, run: str, length: int, head: str) -> None:
    """Inside the cache's write transaction: merge in what the watermark has not covered."""
    cache = store.cache.connection
    row = cache.execute("SELECT chain_len, head FROM presence_marks WHERE run = ?", (run,)).fetchone()
    covered = 0
    if row is not None and 0 < row[0] <= length and hash_at(store.connection, run, row[0] - 1) == row[1]:
        covered = row[0]
    else:       # none yet, or of another chain
        cache.execute("DELETE FROM presence WHERE run = ?", (run,))
    if covered < length:
        cache.executemany(_MERGE, ((run, b, src, x0, x1, y0, y1)
                                   for src, b, x0, x1, y0, y1 in _boxes(store, run, covered, length)))
    cache.execute("INSERT INTO presence_marks (run, chain_len, head) VALUES (?, ?, ?) "
                  "ON CONFLICT (run) DO UPDATE SET chain_len = excluded.chain_len, head = excluded.head",
                  (run, length, head))


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
    row = cache.execute("SELECT chain_len, head FROM presence_marks WHERE run = ?", (run,)).fetchone()
    if row is None or not (row[0] > 0 and hash_at(store.connection, run, row[0] - 1) == row[1]):
        return []
    fresh = {(src, b): box for src, b, *box in _boxes(store, run, 0, row[0])}
    held = {(src, b): [x0, x1, y0, y1] for src, b, x0, x1, y0, y1 in cache.execute(
        "SELECT src, bucket, x0, x1, y0, y1 FROM presence WHERE run = ?", (run,))}
    return sorted(key for key in fresh.keys() | held.keys() if fresh.get(key) != held.get(key))
