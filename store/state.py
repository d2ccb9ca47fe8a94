"""State at a time: what the record says every entity, signal and monitor was at any t.

The reasoner rebuilds the Vehicle, Monitor and Validator Scenarios from this, so every piece of
state is the event it came from, cut down to a citation and a body: {"src", "seq", "t", "body"}.
Where the fold points at an event (the last one folded, a colour's `since`, the ADS status's
`since` and the manoeuvres in progress) it keeps only the compact {src, seq, t} (`_cite`), not a
store.EventRef: that shape is stored in the cached snapshots, and a reader that cites a piece
adds the run and kind it lacks (EventRef.of). State at t is the fold of the run's events with
t' <= t in (t, seq, src) order, a total order fixed by the events themselves, so the answer never
depends on the order or the batches in which the events arrived.

The state (a frozen State, state_value.py, holding plain JSON data; the fold itself and the
snapshots work on a dict of the same keys but run and t):
    run, t            what was asked
    events, last      how many events were folded, and the ref of the last one
    start             run.start, with the map, seed, config and the rulebooks in force (name,
                      version and sha256; the LE text is in the cited event and the rulebook store)
    end               run.end, or null
    entities          per src: spawn, state, perception, decision (latest of each kind), ads
                      (status folded from the ads.event history, see ads_status), despawned (the
                      entity.despawn, null while present). A new entity.spawn starts a fresh record.
    signals           per junction, per approach ("*" when the event names none): colour,
                      since (ref of the event that first showed this colour), last (latest report)
    monitors          per monitor src: observations, the latest per vehicle made within
                      OBSERVATION_WINDOW_S before t (an older one no longer says what the monitor
                      sees at t), and potential_violations, the latest per vehicle
    collisions        per entity id named in a collision: the latest collision naming it
vehicle.trace events are counted but not folded: decisions cite their trace by seq.

Cost: snapshots (store/snapshots.py, kept in the store's cache file, never in the store) hold
the fold every SNAPSHOT_EVERY events, so state_at loads the nearest one and folds fewer than
that many events. Reads write missing snapshots to the cache as they go, in bounded batches;
`build_snapshots` writes them for a whole run ahead of the reads.
Late events never make a read wrong, whoever appended them (see store/snapshots.py); a process
that appends to runs being read as they grow (the ingest) should call
`snapshots.enable_snapshots(store)` once, so that the readers do not have to check its appends.
`check_snapshots` re-folds a run to find snapshots altered behind the store's back.
"""

from __future__ import annotations

import gc
import json
import sqlite3
from typing import TYPE_CHECKING, Any, Callable

from . import fastjson
from .cache import snapshots
if TYPE_CHECKING:                       # annotations only: the store's faces load before db is done
    from .db import Store
from .errors import EvidenceError
from .reading import one_snapshot
from .cache.snapshots import Fresh, Position
from .state_value import State

OBSERVATION_WINDOW_S = 10  # a monitor observation older than this says nothing of the moment
_SECOND = 1_000_000_000
SNAPSHOT_EVERY = 500  # events between snapshots: bench/scene_at_t.py measures the trade-off
_CHUNK = 4096  # rows fetched at a time, so that memory stays bounded whatever the window
_HELD = 64  # snapshots held in memory before they are written
_T_MAX = (1 << 63) - 1

Row = tuple[str, int, int, str, str]  # src, seq, t, kind, event JSON: as selected below
Piece = dict[str, Any]


def _select(after: bool, through: bool) -> str:
    """A run's events up to t in fold order; optionally only those after one position and up to
    another (row values: both bounds are ranges of the (run, t, seq, src) index)."""
    sql = "SELECT src, seq, t, kind, event FROM events WHERE run = ? AND t <= ?"
    sql += " AND (t, seq, src) > (?, ?, ?)" if after else ""
    sql += " AND (t, seq, src) <= (?, ?, ?)" if through else ""
    return sql + " ORDER BY t, seq, src"


_FROM_START, _AFTER = _select(False, False), _select(True, False)
_BETWEEN = {False: _select(False, True), True: _select(True, True)}


# --- public API -------------------------------------------------------------------------------


def state_at(store: Store, run: str, t: int, *, use_snapshots: bool = True) -> State:
    """The state of `run` at time t (ns): the fold of its events with t' <= t.

    With use_snapshots (the default) the fold starts from the nearest snapshot and any missing
    snapshots on the way are written to the cache file (the store itself is never written).
    use_snapshots=False folds every event from the start, reading the events only: the slow
    reference the snapshots are tested against."""
    with CollectorPaused():
        return State.of(run, t, fold_at(store, run, t, use_snapshots=use_snapshots))


def fold_at(store: Store, run: str, t: int, *, use_snapshots: bool = True) -> dict[str, Any]:
    """The fold's own dict at t, for a reader that folds on from it (timeline.py); the caller
    pauses the collector."""
    if use_snapshots:
        state = _advance(store, run, t, SNAPSHOT_EVERY)
    else:
        state = _fold_all(store.connection, run, t)
    prune(state, t)
    return state


def prune(state: dict[str, Any], t: int) -> None:
    """Drop the monitor observations made more than OBSERVATION_WINDOW_S before t.

    Snapshots are pruned at their own time too, which keeps them small; that never changes an
    answer, because whatever is pruned at a snapshot's time is older still for any later t."""
    horizon = t - OBSERVATION_WINDOW_S * _SECOND
    for monitor in state["monitors"].values():
        observations = monitor["observations"]
        stale = [vehicle for vehicle, piece in observations.items() if piece["t"] < horizon]
        for vehicle in stale:
            del observations[vehicle]


def build_snapshots(store: Store, run: str, *, every: int = SNAPSHOT_EVERY) -> int:
    """Write the snapshots of a whole run now rather than on the first reads; return how many the
    run has. Runs in bounded memory, committing a batch of snapshots at a time."""
    if every < 1:
        raise ValueError("every must be at least 1")
    with CollectorPaused():
        _advance(store, run, _T_MAX, every)
    return snapshots.count(store, run)


def check_snapshots(store: Store, run: str) -> list[Position]:
    """Positions of the run's snapshots that differ from a fresh fold of the events.

    Snapshots are a cache, not evidence: nothing chains them, so whoever can write the file can
    change what state_at answers without touching an event. This reads every event once to catch
    that; a wrong snapshot is cured by snapshots.clear(store, run), or by deleting the cache file.
    Only the snapshots a read may use are checked (not those of another chain or made stale by
    late events). A store without a cache has nothing to check, and is left without one (this
    is what `gaps verify --snapshots` runs)."""
    if not snapshots.has_tables(store):
        return []
    conn = store.connection
    state, position, wrong = empty_state(), None, []
    with one_snapshot(conn), CollectorPaused():
        for held in snapshots.listed(store, run, snapshots.marks(store, run)):
            after = () if position is None else position
            params = (run, held.position[0], *after, *held.position)
            cursor = conn.execute(_BETWEEN[position is not None], params)
            for rows in iter(lambda: cursor.fetchmany(_CHUNK), []):
                fold_rows(state, rows)
            position = held.position
            prune(state, position[0])
            if held.state != state:
                wrong.append(position)
    return wrong


def _cite(piece: Piece) -> dict[str, Any]:
    """The fold's compact citation {src, seq, t} of a piece of state, not an EventRef: the state
    already says the run, and this shape is stored in the cached snapshots, so it must not change."""
    return {"src": piece["src"], "seq": piece["seq"], "t": piece["t"]}


def empty_state() -> dict[str, Any]:
    """The fold state before the first event (State.of adds run and t)."""
    return {
        "events": 0,
        "last": None,
        "start": None,
        "end": None,
        "entities": {},
        "signals": {},
        "monitors": {},
        "collisions": {},
    }


# --- reading ----------------------------------------------------------------------------------


class CollectorPaused:
    """No cyclic garbage collection while a state is read and folded.

    Parsing a snapshot creates some ten thousand dicts and lists. With the collector on, it runs
    every 700 of them, and it traverses every tracked object young enough (now and then every one
    in the process, the state the caller still holds included): a sixth to a third of the time of
    state_at on the benchmark, all of it wasted, since parsed JSON and the fold's own dicts hold
    no reference cycles. It is switched back on at the end if it was on.

    Also why this is a class and state_at returns from inside it: the collector runs at the first
    allocation after it is switched back on, while the count of allocations is high. When nothing
    is allocated between switching it on and the caller dropping the previous state (whose freed
    objects bring the count back down), it does not run at all. A contextmanager generator would
    allocate its StopIteration in between."""

    __slots__ = ("_was_enabled",)

    def __enter__(self) -> None:
        self._was_enabled = gc.isenabled()
        gc.disable()

    def __exit__(self, *exc: object) -> None:
        if self._was_enabled:
            gc.enable()


def _fold_all(conn: sqlite3.Connection, run: str, t: int) -> dict[str, Any]:
    state = empty_state()
    with one_snapshot(conn):
        cursor = conn.execute(_FROM_START, (run, t))
        for rows in iter(lambda: cursor.fetchmany(_CHUNK), []):
            fold_rows(state, rows)
    return state


def _advance(store: Store, run: str, t: int, every: int) -> dict[str, Any]:
    """Fold from the nearest snapshot to t, writing a snapshot every `every` events on the way.

    Each pass reads in one transaction and folds until t or until _HELD new snapshots are held,
    then writes them (checked against anything appended meanwhile) and starts again from the
    nearest snapshot, so memory stays bounded on a first read far into a long run. If the file
    cannot be written the pass folds on to t without holding snapshots."""
    conn = store.connection
    saving = True
    while True:
        with one_snapshot(conn):
            seen = snapshots.marks(store, run)
            base = snapshots.nearest(store, run, t, seen)
            state = empty_state() if base is None else base.state
            position = None if base is None else base.position
            fresh, done = _fold_window(conn, run, state, position, t, every if saving else 0)
        if saving and (fresh or seen.unchecked):
            saving = snapshots.save(store, run, fresh, seen)
        if done:
            return state


def _fold_window(
    conn: sqlite3.Connection,
    run: str,
    state: dict[str, Any],
    position: Position | None,
    t: int,
    every: int,
) -> tuple[list[Fresh], bool]:
    """Fold the events after `position` up to t into state, snapshotting every `every` events
    (0: never). Returns the snapshots and whether t was reached (False: _HELD were taken)."""
    if position is None:
        cursor = conn.execute(_FROM_START, (run, t))
    else:
        cursor = conn.execute(_AFTER, (run, t, *position))
    fresh: list[Fresh] = []
    since = 0
    try:
        while True:
            wanted = _CHUNK if not every else min(_CHUNK, every - since)
            rows = cursor.fetchmany(wanted)
            if not rows:
                return fresh, True
            fold_rows(state, rows)
            since += len(rows)
            if every and since >= every:
                fresh.append(_snapshot(state))
                since = 0
                if len(fresh) >= _HELD:
                    return fresh, False
    finally:
        cursor.close()


def _snapshot(state: dict[str, Any]) -> Fresh:
    """Encoded now: the fold goes on changing the state in place."""
    last = state["last"]
    prune(state, last["t"])
    return (last["t"], last["seq"], last["src"]), snapshots.encode(state)


# --- the fold ---------------------------------------------------------------------------------

# Kinds whose fold is "this entity's slot holds the latest such event": within a batch of rows
# only the last of each (src, kind) changes the result, so the others are not even parsed.
_LATEST = {"entity.state": "state", "vehicle.perception": "perception", "vehicle.decision": "decision"}
# Kinds that make their src an entity without adding anything to fold.
_TOUCH = frozenset(("vehicle.trace",))


def fold_rows(state: dict[str, Any], rows: list[Row]) -> None:
    """Fold rows (src, seq, t, kind, event JSON), already in (t, seq, src) order, into state."""
    if not rows:
        return
    last_of: dict[tuple[str, str], int] = {}
    for i, row in enumerate(rows):
        if row[3] in _LATEST:
            last_of[row[0], row[3]] = i
    parse = [
        i
        for i, (src, _, _, kind, _) in enumerate(rows)
        if kind in _HANDLERS and last_of.get((src, kind), i) == i
    ]
    try:
        events = iter(fastjson.loads("[" + ",".join([rows[i][4] for i in parse]) + "]"))
    except ValueError:
        bad = next((i for i in parse if not _is_json(rows[i][4])), parse[0])
        raise _damaged(rows[bad], "is not JSON") from None
    parsed = iter(parse)
    next_parsed = next(parsed, -1)
    for i, (src, seq, t, kind, _) in enumerate(rows):
        if i == next_parsed:
            try:
                piece = {"src": src, "seq": seq, "t": t, "body": next(events)["body"]}
                _HANDLERS[kind](state, piece)
            except (KeyError, TypeError, ValueError, AttributeError, StopIteration):
                raise _damaged(rows[i], f"is not a {kind} event") from None
            next_parsed = next(parsed, -1)
        elif kind in _LATEST or kind in _TOUCH:
            _entity(state, src)  # superseded within the batch, but the entity exists from here
    src, seq, t = rows[-1][:3]
    state["events"] += len(rows)
    state["last"] = {"src": src, "seq": seq, "t": t}


def _is_json(text: str) -> bool:
    try:
        fastjson.loads(text)
    except ValueError:
        return False
    return True


def _damaged(row: Row, what: str) -> EvidenceError:
    """A row whose text no append writes (a damaged or altered file): the fold cannot go on."""
    return EvidenceError(f"event src={row[0]} seq={row[1]}: the stored text {what}, which no append writes: "
                         "the file was damaged or altered behind the store's back; `gaps verify` says where")


def _key(value: Any) -> str:
    """A body value as a dict key. Bodies are checked for their required fields only, so a
    value of the wrong type is written out rather than trusted (or allowed to crash the fold)."""
    return value if isinstance(value, str) else json.dumps(value, sort_keys=True)


def _new_entity() -> dict[str, Any]:
    return dict.fromkeys(("spawn", "state", "perception", "decision", "ads", "despawned"))


def _entity(state: dict[str, Any], src: str) -> dict[str, Any]:
    entities = state["entities"]
    record = entities.get(src)
    if record is None:
        record = entities[src] = _new_entity()
    return record


def _fold_start(state: dict[str, Any], piece: Piece) -> None:
    """run.start, without the rulebooks' LE text: it is large, and cited by sha256."""
    body = dict(piece["body"])
    books = body.get("rulebooks")
    if isinstance(books, list):
        body["rulebooks"] = [_without_text(book) for book in books]
    state["start"] = {**piece, "body": body}


def _without_text(book: Any) -> Any:
    return {k: v for k, v in book.items() if k != "text"} if isinstance(book, dict) else book


def _fold_end(state: dict[str, Any], piece: Piece) -> None:
    state["end"] = piece


def _fold_spawn(state: dict[str, Any], piece: Piece) -> None:
    record = _new_entity()
    record["spawn"] = piece
    state["entities"][piece["src"]] = record


def _fold_latest(slot: str) -> Callable[[dict[str, Any], Piece], None]:
    def fold(state: dict[str, Any], piece: Piece) -> None:
        _entity(state, piece["src"])[slot] = piece

    return fold


def _fold_despawn(state: dict[str, Any], piece: Piece) -> None:
    _entity(state, piece["src"])["despawned"] = piece


def _fold_signal(state: dict[str, Any], piece: Piece) -> None:
    """A colour's `since` is the first report of it after a different colour (or none)."""
    body = piece["body"]
    approaches = state["signals"].setdefault(_key(body.get("junction")), {})
    approach = _key(body.get("approach", "*"))
    colour = body.get("colour")
    before = approaches.get(approach)
    since = before["since"] if before is not None and before["colour"] == colour else _cite(piece)
    approaches[approach] = {"colour": colour, "since": since, "last": piece}


def _monitor(state: dict[str, Any], src: str) -> dict[str, Any]:
    return state["monitors"].setdefault(src, {"observations": {}, "potential_violations": {}})


def _fold_observation(state: dict[str, Any], piece: Piece) -> None:
    _monitor(state, piece["src"])["observations"][_key(piece["body"].get("vehicle"))] = piece


def _fold_potential_violation(state: dict[str, Any], piece: Piece) -> None:
    _monitor(state, piece["src"])["potential_violations"][_key(piece["body"].get("vehicle"))] = piece


def _fold_collision(state: dict[str, Any], piece: Piece) -> None:
    named = piece["body"].get("entities")
    for entity in named if isinstance(named, list) else [named]:
        state["collisions"][_key(entity)] = piece


def _fold_ads(state: dict[str, Any], piece: Piece) -> None:
    record = _entity(state, piece["src"])
    record["ads"] = ads_status(record["ads"], piece)


_NO_ADS = {
    "engaged": False,
    "since": None,
    "last": None,
    "transition_demand": None,
    "minimal_risk_manoeuvre": None,
    "emergency_manoeuvre": None,
    "failure": None,
}


def ads_status(before: dict[str, Any] | None, piece: Piece) -> dict[str, Any]:
    """The ADS status after one ads.event (UN R157 para 8.2.1 DSSAD events).

    engaged: whether the system is in control, `since` citing the event that made it so.
    transition_demand, minimal_risk_manoeuvre, emergency_manoeuvre: refs of the events that
    started them while they are in progress, else null. A transition demand stays pending until
    the driver takes over (deactivated, driver_override) or the system is activated afresh;
    during a minimal risk manoeuvre it stays pending, as R157 para 5.4 requires. failure: the
    latest failure reported, kept as history (nothing in the catalogue clears it)."""
    status = dict(_NO_ADS if before is None else before)
    status["last"] = piece
    event, here = piece["body"].get("event"), _cite(piece)
    if event == "activated":
        if not status["engaged"]:
            status.update(engaged=True, since=here)
        status.update(transition_demand=None, minimal_risk_manoeuvre=None)
    elif event in ("deactivated", "driver_override"):
        if status["engaged"]:
            status.update(engaged=False, since=here)
        status.update(transition_demand=None, minimal_risk_manoeuvre=None, emergency_manoeuvre=None)
    elif event == "transition_demand":
        status["transition_demand"] = status["transition_demand"] or here
    elif event == "minimal_risk_manoeuvre":
        status["minimal_risk_manoeuvre"] = status["minimal_risk_manoeuvre"] or here
    elif event == "emergency_manoeuvre_start":
        status["emergency_manoeuvre"] = status["emergency_manoeuvre"] or here
    elif event == "emergency_manoeuvre_end":
        status["emergency_manoeuvre"] = None
    elif event == "failure":
        status["failure"] = here
    return status


_HANDLERS: dict[str, Callable[[dict[str, Any], Piece], None]] = {
    "run.start": _fold_start,
    "run.end": _fold_end,
    "entity.spawn": _fold_spawn,
    "entity.despawn": _fold_despawn,
    "signal.state": _fold_signal,
    "ads.event": _fold_ads,
    "monitor.observation": _fold_observation,
    "monitor.potential_violation": _fold_potential_violation,
    "collision": _fold_collision,
    **{kind: _fold_latest(slot) for kind, slot in _LATEST.items()},
}
