"""The state of a few sources at t, read from their own events: what judging one act needs.

`state_at` folds every event of the run up to t (from the nearest snapshot). Judging an act
needs two parts of that state: the record of the vehicle (its spawn, latest state, perception
and decision, its ADS status, its despawn) and what its monitor last observed of it. Each part
depends only on its own source's events, so it can be folded from those alone: the vehicle's
events since its last spawn before t, and the monitor's observations of the vehicle in the
OBSERVATION_WINDOW_S before t. Their cost follows the act, not the run: no fold of the other
road users' millions of events, and no snapshots to build first (a one-hour run's snapshots
took over an hour to build; see docs/history.md "Cost").

Every part `state_of` holds is the same part `state_at` gives (the same fold handlers fold the
same events; tests/store/test_partial_state.py compares them on generated runs); the parts it
was not asked for are empty. One assumption, the one `Store.source_events` makes too: a
source's t rises with its seq, give or take SEQ_SLACK places.
"""
from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Any, Iterable

from . import fastjson
from .db import Store
from .ddl import DENSE_KINDS, SPARSE_ONLY
from .kinds import SRC_ROLES
from .index_guard import AGREES, checked
from .queries import SEQ_SLACK, _first_seq_past, highest_seq
from .cache.snapshots import chain_end
from .state import _HANDLERS, _LATEST, _TOUCH, OBSERVATION_WINDOW_S, _key, empty_state, fold_rows
from .state_value import State

_SECOND = 1_000_000_000
ENTITY_KINDS = frozenset(("entity.spawn", "entity.despawn", "ads.event", *_LATEST, *_TOUCH))
_DENSE_LATEST = tuple(k for k in _LATEST if k in DENSE_KINDS)      # entity.state, vehicle.perception
_SPARSE_KINDS = tuple(sorted(k for k in ENTITY_KINDS if k not in DENSE_KINDS))
_ENTITY_KIND_LIST = tuple(sorted(ENTITY_KINDS))
_WINDOW = "FROM events WHERE run = ? AND src = ? AND seq >= ? AND seq <= ? AND t <= ?"
# through the covering kind index: the few sparse events of all sources in the window, no row read
_SPARSE_ROWS = (f"SELECT seq, t, kind, src, {AGREES} FROM events WHERE run = ? "
                f"AND kind IN ({', '.join(repr(k) for k in _SPARSE_KINDS)})"
                f" AND {SPARSE_ONLY} AND src = ? AND t >= ? AND t <= ?")
_LATEST_ROWS = f"SELECT seq, t, kind {_WINDOW} AND kind = ? ORDER BY seq DESC LIMIT ?"
_T_MIN = -(1 << 63)
_SEQ_MIN, _SEQ_MAX = -(1 << 63), (1 << 63) - 1
_LAST_SPAWN = (f"SELECT seq, t, src, {AGREES} FROM events WHERE run = ? AND kind = 'entity.spawn' AND "
               f"{SPARSE_ONLY} AND src = ? AND t <= ? ORDER BY t DESC, seq DESC LIMIT 1")
_TEXT = "SELECT seq, event FROM events WHERE run = ? AND src = ? AND seq IN ({})"
# the source's first entity events by seq: SQLite skips its other kinds (a camera's observations)
_ENTITY_IN_ORDER = "SELECT seq, t FROM events WHERE run = ? AND src = ? AND kind IN ({}) ORDER BY seq LIMIT ?"
_SPARSE_FIRST = f"SELECT min(t) FROM events WHERE run = ? AND kind IN ({{}}) AND {SPARSE_ONLY} AND src = ?"
# body.vehicle is a string (the schema refuses any other), compared in SQLite
_OBSERVED = (f"SELECT t, seq, src, event, {AGREES} FROM events WHERE run = ? AND kind = 'monitor.observation' AND "
             f"{SPARSE_ONLY} AND src = ? AND t >= ? AND t <= ? AND json_extract(event, '$.body.vehicle') = ? "
             "ORDER BY t DESC, seq DESC")


def state_of(store: Store, run: str, t: int, *, entities: Iterable[str] = (),
             observed: Iterable[tuple[str, str]] = ()) -> State:
    """The state of `run` at t restricted to these entity srcs ("vehicle/173") and these
    (monitor src, vehicle) observations: each present part equal to state_at's. Nothing of the
    run as a whole is read: `events` is 0, and `last`, `start` and `end` are None."""
    folded = empty_state()
    with store._reading():
        for src in entities:
            record = entity_at(store, run, src, t)
            if record is not None:
                folded["entities"][src] = record
        for monitor, vehicle in observed:
            piece = observation_at(store, run, monitor, vehicle, t)
            if piece is not None:
                held = folded["monitors"].setdefault(monitor, {"observations": {}, "potential_violations": {}})
                held["observations"][vehicle] = piece
    return State.of(run, t, folded)


def entity_at(store: Store, run: str, src: str, t: int) -> dict[str, Any] | None:
    """The fold's record of the entity `src` at t (state_at(...).entities[src]), or None.

    Only the events after its last entity.spawn at or before t count (a spawn starts a fresh
    record), and of those only the latest of each kind the fold keeps the latest of. The spawn
    and the other sparse kinds are found in the kind index (no row read), the latest state and
    perception by kind within the source's seq range from the spawn, SQLite doing the filtering:
    a vehicle's thousands of states are neither returned nor parsed."""
    conn = store.connection
    highest = highest_seq(conn, run, src)
    if highest is None:
        return None
    top = _first_seq_past(conn, run, src, highest, t, True) - 1 + SEQ_SLACK
    spawn = next(checked(conn.execute(_LAST_SPAWN, (run, src, t)), run, 2, 0), None)
    low = max(0, spawn[0] - SEQ_SLACK) if spawn else 0
    window = (run, src, low, top, t)
    rows = [row[:3] for row in checked(conn.execute(_SPARSE_ROWS, (run, src, spawn[1] if spawn else _T_MIN, t)),
                                       run, 3, 0)]
    for kind in (*_DENSE_LATEST, *(() if spawn else _TOUCH)):
        if kind == "entity.state":      # a few rows back from the top: the source's own series
            rows += _last_of(conn.execute(_LATEST_ROWS, (*window, kind, SEQ_SLACK + 1)).fetchall())
        else:
            rows += _last_of(_kind_rows(store, run, src, kind, low, top, t))
    rows = sorted({r for r in rows if spawn is None or (r[1], r[0]) >= (spawn[1], spawn[0])},
                  key=lambda row: (row[1], row[0]))
    if not rows:
        return None
    wanted = _needed(rows)
    texts = dict(conn.execute(_TEXT.format(",".join("?" * len(wanted))), (run, src, *wanted)))
    state = empty_state()
    fold_rows(state, [(src, seq, at, kind, texts.get(seq, "null")) for seq, at, kind in rows])
    return state["entities"].get(src)


# One source's rows of a dense kind other than entity.state (vehicle.perception, vehicle.trace),
# in the store's memo (store.cache.memo[_KIND_MEMO], a _Kept). Such a kind has no index by kind, and a
# vehicle that perceives only when it decides has a few dozen among thousands of states: _LATEST_ROWS
# then walks back through every one of them, one table row each, to its spawn, for every act judged.
# Read once per source and chain instead, and answered from memory. And once the sources' reads
# would have walked 1/WHOLE_RUN_SHARE of the run's chain, all the run's rows of these kinds are read
# in one walk of its chain instead, a tenth of the cost a row: one source at a time, the hour's cold
# judgement walked its 9.3 million states (some 34 s of CPU, against 3 s for the one walk).
_KIND_MEMO = ("dense kind rows",)
_MAX_KIND_ROWS = 1_000_000     # rows kept per store; past it, all are let go
WHOLE_RUN_SHARE = 8            # the whole run is read once the sources' reads walked 1/8 of its chain
_KIND_RANGE = "SELECT seq, t, kind FROM events WHERE run = ? AND src = ? AND seq >= ? AND seq <= ? AND kind = ? ORDER BY seq"
_RARE_KINDS = tuple(sorted(k for k in (*_LATEST, *_TOUCH) if k in DENSE_KINDS and k != "entity.state"))
# every row of those kinds in the run's chain: a walk of the (run, chain_pos) index, in the file's order
_WHOLE_RUN = (f"SELECT src, kind, seq, t FROM events WHERE run = ? AND chain_pos < ? "
              f"AND kind IN ({', '.join(repr(k) for k in _RARE_KINDS)}) ORDER BY src, kind, seq LIMIT ?")


@dataclass
class _KindRows:
    """Every row (seq, t, kind) of one kind of one source with seq in [low, high], in seq order,
    as the chain (length, head) stood when they were read."""

    chain: tuple[int, str]
    low: int
    high: int
    rows: list[tuple[int, Any, str]]
    seqs: list[int]


@dataclass
class _RunRows:
    """What the sources' reads of one run and chain walked so far (seqs ranges, summed), and,
    once read, every row of the rare dense kinds of that chain by (src, kind), in seq order
    (None: not read yet, or too many to keep: then each source is read alone)."""

    chain: tuple[int, str]
    walked: int = 0
    whole: dict[tuple[str, str], _KindRows] | None = None
    refused: bool = False


@dataclass
class _Kept:
    """The memo: each source's rows by (run, src, kind), how many rows they hold, each run's _RunRows."""

    sources: dict[tuple[str, str, str], _KindRows] = field(default_factory=dict)
    size: int = 0
    runs: dict[str, _RunRows] = field(default_factory=dict)


def _kind_rows(store: Store, run: str, src: str, kind: str, low: int, top: int, t: int) -> list[tuple[int, Any, str]]:
    """What _LATEST_ROWS gives for the window (run, src, low, top, t) and this kind: the last
    SEQ_SLACK + 1 rows by seq with seq in [low, top] and t <= t, from the run's or the source's
    rows of the kind kept for the chain as it stands (the part of [low, top] not kept yet read first)."""
    if low > top:
        return []
    chain = chain_end(store.connection, run)
    kept: _Kept = store.cache.memo.setdefault(_KIND_MEMO, _Kept())
    entry, pieces = _lacking(kept, run, src, kind, low, top, chain)
    whole = _whole_run(store, kept, run, chain, sum(b - a + 1 for a, b in pieces))
    if whole is not None:
        entry = whole.get((src, kind)) or _KindRows(chain, low, top, [], [])
    elif pieces:
        _read(store, kept, run, src, kind, entry, pieces)
    lo, hi = bisect.bisect_left(entry.seqs, low), bisect.bisect_right(entry.seqs, top)
    return [row for row in entry.rows[lo:hi] if _at_or_before(row[1], t)][-(SEQ_SLACK + 1):]


def _lacking(kept: _Kept, run: str, src: str, kind: str, low: int, top: int,
             chain: tuple[int, str]) -> tuple[_KindRows, list[tuple[int, int]]]:
    """The source's rows of the kind kept for this chain (a fresh entry where there are none, or
    they are apart from [low, top]), and the seq ranges of [low, top] they lack."""
    entry = kept.sources.get((run, src, kind))
    if entry is None or entry.chain != chain or top < entry.low - 1 or low > entry.high + 1:
        return _KindRows(chain, low, top, [], []), [(low, top)]
    pieces = [(low, entry.low - 1)] if low < entry.low else []     # overlapping or next to it
    return entry, pieces + ([(entry.high + 1, top)] if top > entry.high else [])


def _read(store: Store, kept: _Kept, run: str, src: str, kind: str, entry: _KindRows,
          pieces: list[tuple[int, int]]) -> None:
    """Read the pieces into the entry and keep it (all kept entries let go past _MAX_KIND_ROWS)."""
    old = kept.sources.get((run, src, kind))
    kept.size -= len(old.rows) if old is not None else 0
    if kept.size > _MAX_KIND_ROWS:
        kept.sources.clear()
        kept.size = 0
    for a, b in pieces:
        found = store.connection.execute(_KIND_RANGE, (run, src, a, b, kind)).fetchall()
        entry.rows = found + entry.rows if a < entry.low else entry.rows + found
        entry.low, entry.high = min(entry.low, a), max(entry.high, b)
    entry.seqs = [row[0] for row in entry.rows]
    kept.sources[(run, src, kind)] = entry
    kept.size += len(entry.rows)


def _whole_run(store: Store, kept: _Kept, run: str, chain: tuple[int, str],
               walking: int) -> dict[tuple[str, str], _KindRows] | None:
    """Every rare dense row of the run's chain by (src, kind), read in one walk once the sources'
    reads would have walked (`walking`: the seqs this one would) 1/WHOLE_RUN_SHARE of the chain;
    None before that (or when there are more than _MAX_KIND_ROWS of them). Each (src, kind) holds
    its rows in seq order over the widest range there is, so any window of it is what _KIND_RANGE
    gives for that window."""
    state = kept.runs.get(run)
    if state is None or state.chain != chain:
        state = kept.runs[run] = _RunRows(chain)
    state.walked += walking
    if state.whole is None and not state.refused and state.walked * WHOLE_RUN_SHARE > chain[0]:
        kept.runs = {run: state}        # one run's rows kept at a time: a run judged after another lets it go
        rows = store.connection.execute(_WHOLE_RUN, (run, chain[0], _MAX_KIND_ROWS + 1)).fetchall()
        if len(rows) > _MAX_KIND_ROWS:
            state.refused = True
        else:
            state.whole = _grouped(rows, chain)
    return state.whole


def _grouped(rows: list[tuple[str, str, Any, Any]], chain: tuple[int, str]) -> dict[tuple[str, str], _KindRows]:
    """Rows (src, kind, seq, t) in (src, kind, seq) order, as a _KindRows of all seqs per (src, kind)."""
    out: dict[tuple[str, str], _KindRows] = {}
    for src, kind, seq, at in rows:
        entry = out.get((src, kind))
        if entry is None:
            entry = out[(src, kind)] = _KindRows(chain, _SEQ_MIN, _SEQ_MAX, [], [])
        entry.rows.append((seq, at, kind))
        entry.seqs.append(seq)
    return out


def _at_or_before(at: Any, t: int) -> bool:
    """SQLite's `at <= t` for a stored t and an integer t: numbers compared as numbers, any text
    or blob (none an append writes) greater than every number."""
    return type(at) in (int, float) and at <= t


def _last_of(rows: list[tuple[int, int, str]]) -> list[tuple[int, int, str]]:
    """The latest in (t, seq) order of a kind's last SEQ_SLACK + 1 rows by seq."""
    return [max(rows, key=lambda row: (row[1], row[0]))] if rows else []


def _needed(rows: list[tuple[int, int, str]]) -> set[int]:
    """The seqs whose bodies the fold reads: every event of a kind it folds in full, the latest
    of each kind of which it keeps only the latest."""
    latest: dict[str, int] = {}
    out: set[int] = set()
    for seq, _, kind in rows:
        if kind in _LATEST:
            latest[kind] = seq
        elif kind in _HANDLERS:
            out.add(seq)
    return out | set(latest.values())


def observation_at(store: Store, run: str, monitor: str, vehicle: str, t: int) -> dict[str, Any] | None:
    """The fold's monitors[monitor]["observations"][vehicle] at t: the monitor's last observation
    of the vehicle at or before t, if made within OBSERVATION_WINDOW_S of it."""
    horizon = t - OBSERVATION_WINDOW_S * _SECOND
    for at, seq, _, text in checked(store.connection.execute(_OBSERVED, (run, monitor, horizon, t, vehicle)), run):
        event = fastjson.loads(text)
        body = event.get("body") if isinstance(event, dict) else None
        if isinstance(body, dict) and _key(body.get("vehicle")) == vehicle:
            return {"src": monitor, "seq": seq, "t": at, "body": body}
    return None


def entity_since(store: Store, run: str, src: str) -> int | None:
    """The t of the source's first entity event: from then on state_at lists it among the
    entities (None: it never is one). A source whose role sends no dense kind (a monitor, a
    signal: spawns and despawns only) is looked up in the kind index; any other is read from
    its first event on, up to SEQ_SLACK places past its first entity event."""
    role = src.split("/", 1)[0]
    kinds = sorted(k for k in ENTITY_KINDS if role in SRC_ROLES.get(k, ()))
    if not kinds:
        return None
    if not set(kinds) & set(DENSE_KINDS):
        sql = _SPARSE_FIRST.format(",".join("?" * len(kinds)))
        return store.connection.execute(sql, (run, *kinds, src)).fetchone()[0]
    rows = store.connection.execute(_ENTITY_IN_ORDER.format(",".join("?" * len(_ENTITY_KIND_LIST))),
                                    (run, src, *_ENTITY_KIND_LIST, SEQ_SLACK + 1)).fetchall()
    return min((at for seq, at in rows if seq <= rows[0][0] + SEQ_SLACK), default=None)
