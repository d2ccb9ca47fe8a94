"""Per-vehicle junction passages, rebuilt from the whole record (DESIGN "Reasoning": histories).

    ctx = history.run_context(store, run)              # the run's map and signals, read once
    found = history.passages(store, run, "173", around=t, context=ctx)
    p = history.passage_at(found, t)                   # the passage of the act at t
    facts = derived.facts(p, t)                        # reasoner/derived.py

or, from a list of events (a file looked at before import, a test): `history.from_events(events,
"173", around=t)`. Both fill a `Record` (reasoner/record.py) and hand it to reasoner/rebuild.py,
which computes every passage; this module only reads.

From a store, through its public reads only: the vehicle's entity.state in the window
(`Store.source_events`, whose cost follows the window, not the run); the monitors' measurements of
it (`Store.observations_of`) only where its own series is missing or has holes; its spawn; the
run's map and signal timelines once per run (`run_context`); the sequence gaps of its sources; and,
for the other road users near a junction, the junction's monitors' observations in a short window
(their own entity.state where those are sparse), or, at a junction no monitor watches, every
entity.state of that window. Every read is capped, so a hostile run costs bounded time and memory.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from itertools import islice
from typing import Iterable, Mapping

from store import Store
from store.cache import sources_near

from . import rebuild
from .junctions import Junction, Map, finite, read_map
from .motion import Sample, samples
from .others import CONFLICT_M
from .passage_values import Passage
from .record import Gap, Record, Track
from .signals import MAX_SIGNAL_EVENTS, Signals, read_signals
from .state_samples import StateSamples

SECOND = 1_000_000_000
BEFORE_S = 60.0             # read at most this long before the moment asked about: a wait through a red phase
AFTER_S = 30.0              # ... and this long after: a queue clearing the junction
MAX_SAMPLES = 200_000       # a vehicle's samples read at once (5.5 hours at 10 Hz)
MAX_OTHER_EVENTS = 50_000   # events read to find the road users near a junction in one window
FIRST_BEFORE_S = 10.0       # the first read around a moment: a moving vehicle's passage up to its act (100 m at 25 mph: 9 s)
FIRST_AFTER_S = 4.0         # ... and out of the junction (30 m beyond its centre)
HOLE_S = 1.5                # a hole this long in its own series and the monitors' measurements are read too
MAX_KEPT_SPAWNS = 100_000   # road users whose entity.spawn a run context keeps


@dataclass(frozen=True)
class RunContext:
    """What every passage of a run shares, read once: its map, its signal timelines, and
    whether any of its sources misses a seq (the gaps themselves are looked up per source).
    What the passages read is kept too, for the next act at the same junction and time: the
    road users' entity.state (states), the junction's observations (_Seen), spawns."""

    run: str
    map: Map
    signals: Signals
    gappy: bool
    signal_srcs: frozenset[str]                  # every signal's src: every passage's gaps include theirs
    states: StateSamples = field(compare=False, repr=False)
    _gaps: dict[str, tuple[Gap, ...]] = field(default_factory=dict, compare=False, repr=False)
    _spawns: dict[str, dict | None] = field(default_factory=dict, compare=False, repr=False)
    _seen: dict[str, _Seen] = field(default_factory=dict, compare=False, repr=False)


def run_context(store: Store, run: str) -> RunContext:
    start = next(iter(store.events(run, kinds=["run.start"])), None)
    signals = read_signals(islice(store.events(run, kinds=["signal.state"]), MAX_SIGNAL_EVENTS + 1))
    return RunContext(run, read_map(start), signals, store.has_sequence_gaps(run),
                      frozenset(light.ref.src for line in signals.lines.values() for light in line),
                      StateSamples(store, run))


def vehicle_src(vehicle: str) -> str:
    """"173" is vehicle/173; a src ("pedestrian/p1") is taken as it is."""
    return vehicle if "/" in vehicle else f"vehicle/{vehicle}"


def user_id(src: str) -> str:
    return src.split("/", 1)[1] if "/" in src else src


def passages(store: Store, run: str, vehicle: str, *, around: int | None = None, before_s: float = BEFORE_S,
             after_s: float = AFTER_S, context: RunContext | None = None) -> tuple[Passage, ...]:
    """The vehicle's passages through junctions: around a moment (reading at most before_s
    before it and after_s after it), or in the whole record (around=None)."""
    return rebuild.passages(_record(store, run, vehicle, around, before_s, after_s, context)[0])


def passage(store: Store, run: str, vehicle: str, t: int, *, context: RunContext | None = None) -> Passage | None:
    """The vehicle's passage of the act at t (the one under way then, else the nearest); only
    that one is rebuilt."""
    record, found = _record(store, run, vehicle, t, BEFORE_S, AFTER_S, context)
    return rebuild.nearest(record, t, found)


def _record(store: Store, run: str, vehicle: str, around: int | None, before_s: float, after_s: float,
            context: RunContext | None) -> tuple[Record, list[rebuild.Span] | None]:
    """What the store holds for the vehicle's passages around a moment (or in its whole record),
    and the stretches near junctions already found in it (None: not looked for)."""
    ctx = context or run_context(store, run)
    src, ident = vehicle_src(vehicle), user_id(vehicle_src(vehicle))
    notes: list[str] = []
    own, skipped, (t_from, t_to), found = _own(store, ctx, src, around, before_s, after_s, notes)
    seen: tuple[Sample, ...] = ()
    if _holes(own):
        seen, more = samples(_capped(store.observations_of(run, ident, t_from=t_from, t_to=t_to), notes,
                                     f"monitor observations of {ident}"))
        skipped += more
        found = None
    spawns = list(islice(store.events(run, kinds=["entity.spawn"], srcs=[src], t_to=t_to), 100))
    return Record(run, ident, ctx.map, ctx.signals, own, seen, spawns[-1] if spawns else None,
                  _store_gaps(store, ctx, {src} | {s.ref.src for s in seen}), tuple(notes) + skipped[:20],
                  _store_others(store, ctx, ident), (t_from, t_to), _store_spawns(store, ctx),
                  _store_track(ctx)), found


def passage_at(found: Iterable[Passage], t: int) -> Passage | None:
    """The passage under way at t, else the one nearest to it in time."""
    best = None
    for p in found:
        distance = 0 if p.start <= t <= p.end else min(abs(t - p.start), abs(t - p.end))
        if best is None or distance < best[0]:
            best = (distance, p)
    return best[1] if best else None


def from_events(events: Iterable[dict], vehicle: str, *, around: int | None = None, before_s: float = BEFORE_S,
                after_s: float = AFTER_S) -> tuple[Passage, ...]:
    """The same passages from a list of one run's events, in any order (at most MAX_SAMPLES of
    any one kind of evidence are kept)."""
    src, ident = vehicle_src(vehicle), user_id(vehicle_src(vehicle))
    t_from, t_to = (None, None) if around is None else (around - int(before_s * SECOND), around + int(after_s * SECOND))
    index = _Index(src, ident, t_from, t_to)
    for event in events:
        index.add(event)
    own, skipped = samples(index.own)
    seen, more = samples(index.seen) if _holes(own) else ((), ())      # as from a store
    return rebuild.passages(Record(
        index.run, ident, read_map(index.start), read_signals(index.signals), own, seen, index.spawn,
        index.gaps(), tuple(index.notes) + (skipped + more)[:20], index.others, (t_from, t_to), index.spawn_of))


# --- reading a store ----------------------------------------------------------------------------

def _own(store: Store, ctx: RunContext, src: str, around: int | None, before_s: float, after_s: float,
         notes: list[str]) -> tuple[tuple[Sample, ...], tuple[str, ...], tuple[int | None, int | None],
                                    list[rebuild.Span] | None]:
    """The vehicle's entity.state samples, notes on what they left out, the window read, and
    the stretches near junctions found in them. Around a moment, a short window first
    (FIRST_BEFORE_S, FIRST_AFTER_S), doubled on a side while the passage at the moment holds
    that side's first or last sample (the vehicle was already, or still, near the junction), up
    to before_s and after_s: most passages take a few hundred events of reading, however long
    the run."""
    def read(a: int | None, b: int | None) -> tuple[tuple[Sample, ...], tuple[str, ...]]:
        if a is None or b is None:
            found = store.source_events(ctx.run, src, kinds=["entity.state"], t_from=a, t_to=b)
            return samples(_capped(found, notes, f"{src} entity.state"))
        window = ctx.states.window(src, a, b, MAX_SAMPLES)
        if window.events > MAX_SAMPLES:
            notes.append(f"{window.events} {src} entity.state in the window; the first {MAX_SAMPLES} are read")
        return window.samples, window.notes

    if around is None:
        return (*read(None, None), (None, None), None)
    back, ahead = min(FIRST_BEFORE_S, before_s), min(FIRST_AFTER_S, after_s)
    t_from, t_to = around - int(back * SECOND), around + int(ahead * SECOND)
    own, skipped = read(t_from, t_to)
    while True:
        placed = [s for s in own if s.placed]
        found = rebuild.spans(placed, ctx.map)
        early, late = _reaches(found, placed, around)
        grow_back, grow_ahead = early and back < before_s, late and ahead < after_s
        if not (grow_back or grow_ahead) or len(own) >= MAX_SAMPLES:
            return own, skipped, (t_from, t_to), found
        if grow_back:
            back = min(2 * back, before_s)
            lower = around - int(back * SECOND)
            more, why = read(lower, t_from - 1)
            own, skipped, t_from = more + own, why + skipped, lower
        if grow_ahead:
            ahead = min(2 * ahead, after_s)
            upper = around + int(ahead * SECOND)
            more, why = read(t_to + 1, upper)
            own, skipped, t_to = own + more, skipped + why, upper


def _reaches(found: list[rebuild.Span], placed: list[Sample], around: int) -> tuple[bool, bool]:
    """Whether the passage at `around` may go on before the first sample read (it already
    holds it) and after the last (it holds it and had not ended)."""
    span = rebuild.nearest_span(found, around)
    if span is None:
        return not placed, not placed
    return span.t0 <= placed[0].t, not span.through and span.t1 >= placed[-1].t


def _capped(events: list[dict], notes: list[str], what: str) -> list[dict]:
    if len(events) > MAX_SAMPLES:
        notes.append(f"{len(events)} {what} in the window; the first {MAX_SAMPLES} are read")
        return events[:MAX_SAMPLES]
    return events


def _holes(own: tuple[Sample, ...]) -> bool:
    """Whether the vehicle's own positions leave a hole the monitors may fill."""
    placed = [s for s in own if s.placed]
    return len(placed) < 2 or any(b.t - a.t > HOLE_S * SECOND for a, b in zip(placed, placed[1:]))


def _store_gaps(store: Store, ctx: RunContext, srcs: set[str]) -> tuple[Gap, ...]:
    """The sequence gaps of these sources and of every signal (none when the run has none)."""
    if not ctx.gappy:
        return ()
    out: list[Gap] = []
    for src in sorted(srcs | ctx.signal_srcs):
        if src not in ctx._gaps:
            ctx._gaps[src] = tuple(Gap(src, first, last, store.t_of(ctx.run, src, first - 1),
                                       store.t_of(ctx.run, src, last + 1))
                                   for first, last in store.sequence_gaps(ctx.run, src)[:100])
        out += ctx._gaps[src]
    return tuple(out)


def _store_spawns(store: Store, ctx: RunContext):
    """Another road user's entity.spawn (its type), as a vehicle or a pedestrian source; read
    once per road user and run (the same road users pass one junction after another)."""
    def find(user: str) -> dict | None:
        if user not in ctx._spawns:
            srcs = [user] if "/" in user else [f"vehicle/{user}", f"pedestrian/{user}"]
            found = list(islice(store.events(ctx.run, kinds=["entity.spawn"], srcs=srcs), 10))
            if len(ctx._spawns) >= MAX_KEPT_SPAWNS:
                ctx._spawns.clear()
            ctx._spawns[user] = found[-1] if found else None
        return ctx._spawns[user]
    return find


def _store_track(ctx: RunContext):
    """One road user's own entity.state in a window, from the run's samples kept across acts."""
    def track(src: str, t_from: int, t_to: int) -> tuple[Sample, ...]:
        return ctx.states.window(src, t_from, t_to, MAX_OTHER_EVENTS).samples
    return track


def _store_others(store: Store, ctx: RunContext, vehicle: str):
    """The road users near a junction in a window: from its monitors, and, where no monitor's
    cone covers an arm (a camera on the minor road only), from every entity.state of the window
    too, so that the traffic on that arm is not missed; at a junction no monitor watches, from
    every entity.state."""
    def find(junction: Junction, t_from: int, t_to: int) -> Mapping[str, Track]:
        if not junction.monitors:
            return _states_near(store, ctx, junction, vehicle, t_from, t_to)
        tracks = _observed(_watched(store, ctx, junction, t_from, t_to), vehicle, junction)
        for user, (src, series) in list(tracks.items()):
            if _holes(series):
                own = ctx.states.window(f"vehicle/{user}", t_from, t_to, MAX_SAMPLES).samples
                if own:
                    tracks[user] = (f"vehicle/{user}", own)
        if junction.unwatched:      # their own record, where it holds more than the cameras saw of them
            for user, track in _states_near(store, ctx, junction, vehicle, t_from, t_to).items():
                if user not in tracks or len(track[1]) > len(tracks[user][1]):
                    tracks[user] = track
        return tracks
    return find


def _states_near(store: Store, ctx: RunContext, junction: Junction, vehicle: str, t_from: int,
                 t_to: int) -> dict[str, Track]:
    """The road users' own entity.state of the window, of those the store's index of where
    each was (store.sources_near) puts within CONFLICT_M of the junction in it: the index
    can name some that never came that near (near_users measures them), never leave out one
    that did. MAX_OTHER_EVENTS at most, the sources in name order."""
    tracks: dict[str, Track] = {}
    read = 0
    for src in sources_near(store, ctx.run, junction.x, junction.y, CONFLICT_M, t_from, t_to):
        if src.split("/", 1)[0] in ("vehicle", "pedestrian") and user_id(src) != vehicle:
            window = ctx.states.window(src, t_from, t_to, MAX_OTHER_EVENTS - read)
            if window.events:
                tracks[user_id(src)] = (src, window.samples)
            read += window.events
            if read >= MAX_OTHER_EVENTS:
                break
    return tracks


@dataclass(frozen=True)
class _Seen:
    """A junction's monitor observations read for a passage: all of them in [t_from, t_to], in
    the store's (t, seq, src) order."""

    t_from: int
    t_to: int
    events: list[dict]


def _watched(store: Store, ctx: RunContext, junction: Junction, t_from: int, t_to: int) -> list[dict]:
    """The first MAX_OTHER_EVENTS observations by the junction's monitors in [t_from, t_to].
    Acts at a junction come close together (a queue through a red light, a recorded act and the
    passage before it): what the last read at this junction holds of the window is taken from
    it, and only the rest is read. The pieces are disjoint in time and each in the store's
    order, so together they are what one read of the window gives."""
    last = ctx._seen.get(junction.id)
    if last is None or last.t_from > t_to or last.t_to < t_from:
        pieces = [_read_watched(store, ctx, junction, t_from, t_to)]
    else:
        kept = [e for e in last.events if t_from <= e["t"] <= t_to]
        pieces = [_read_watched(store, ctx, junction, t_from, last.t_from - 1) if t_from < last.t_from else [],
                  kept,
                  _read_watched(store, ctx, junction, last.t_to + 1, t_to) if t_to > last.t_to else []]
    events = [e for piece in pieces for e in piece]
    if len(events) > MAX_OTHER_EVENTS:
        ctx._seen.pop(junction.id, None)        # (a piece may be cut short: not a whole window)
        return events[:MAX_OTHER_EVENTS]
    ctx._seen[junction.id] = _Seen(t_from, t_to, events)
    return events


def _read_watched(store: Store, ctx: RunContext, junction: Junction, t_from: int, t_to: int) -> list[dict]:
    """One read of the junction's monitors' observations, MAX_OTHER_EVENTS + 1 at most (one
    more than is used tells that the window held more)."""
    return list(islice(store.events(ctx.run, kinds=["monitor.observation"], srcs=list(junction.monitors),
                                    t_from=t_from, t_to=t_to), MAX_OTHER_EVENTS + 1))


def _observed(events: Iterable[dict], vehicle: str, junction: Junction) -> dict[str, Track]:
    """Monitor measurements grouped by the road user observed, for the users measured within
    CONFLICT_M of the centre (the others are not even turned into samples)."""
    grouped: dict[str, list[dict]] = {}
    near: set[str] = set()
    for event in events:
        body = event.get("body")
        if type(body) is not dict:
            continue
        user = body.get("vehicle")
        if type(user) is not str or user == vehicle:
            continue
        grouped.setdefault(user, []).append(event)
        if user not in near:
            x, y = finite(body.get("x")), finite(body.get("y"))
            if x is not None and y is not None and junction.distance(x, y) <= CONFLICT_M:
                near.add(user)
    out = {}
    for user in near:
        series, _ = samples(grouped[user])
        out[user] = (series[0].ref.src, series)
    return out


# --- reading a list of events -------------------------------------------------------------------

class _Index:
    """One pass over a run's events: what a Record of one vehicle needs, and the rest kept by
    source for the other road users and the sequence gaps."""

    def __init__(self, src: str, ident: str, t_from: int | None, t_to: int | None) -> None:
        self.src, self.ident, self.t_from, self.t_to = src, ident, t_from, t_to
        self.run = ""
        self.start: dict | None = None
        self.spawn: dict | None = None
        self.signals: list[dict] = []
        self.own: list[dict] = []
        self.seen: list[dict] = []
        self.states: dict[str, list[dict]] = {}
        self.observed: dict[str, list[dict]] = {}
        self.seqs: dict[str, dict[int, int]] = {}
        self.notes: list[str] = []
        self.spawns: dict[str, dict] = {}

    def add(self, event: dict) -> None:
        if not isinstance(event, dict) or not isinstance(event.get("src"), str):
            return
        t, seq, src, kind = event.get("t"), event.get("seq"), event["src"], event.get("kind")
        if not isinstance(t, int) or not isinstance(seq, int) or isinstance(t, bool):
            return
        self.run = self.run or str(event.get("run", ""))
        seqs = self.seqs.setdefault(src, {})
        if len(seqs) < MAX_SAMPLES:
            seqs[seq] = t
        if kind == "run.start" and self.start is None:
            self.start = event
        elif kind == "signal.state":
            self._keep(self.signals, event)
        elif kind == "entity.spawn" and src == self.src and (self.t_to is None or t <= self.t_to):
            self.spawn = event
        elif kind == "entity.spawn" and src.split("/", 1)[0] in ("vehicle", "pedestrian"):
            self.spawns.setdefault(user_id(src), event)
        elif kind == "entity.state" and self._within(t):
            self._keep(self.own if src == self.src else self.states.setdefault(src, []), event)
        elif kind == "monitor.observation" and self._within(t):
            body = event.get("body")
            user = body.get("vehicle") if isinstance(body, dict) else None
            if isinstance(user, str):
                self._keep(self.seen if user == self.ident else self.observed.setdefault(user, []), event)

    def _within(self, t: int) -> bool:
        return (self.t_from is None or t >= self.t_from) and (self.t_to is None or t <= self.t_to)

    def _keep(self, kept: list[dict], event: dict) -> None:
        if len(kept) < MAX_SAMPLES:
            kept.append(event)
        elif len(self.notes) < 10:
            self.notes.append(f"more than {MAX_SAMPLES} events of one kind from {event['src']}: the rest are not read")

    def gaps(self) -> tuple[Gap, ...]:
        out = []
        for src, seqs in self.seqs.items():
            present = sorted(seqs)
            expected = 0
            for seq in present:
                if seq > expected:
                    out.append(Gap(src, expected, seq - 1, seqs.get(expected - 1), seqs[seq]))
                expected = max(expected, seq + 1)
        return tuple(out[:1000])

    def spawn_of(self, user: str) -> dict | None:
        return self.spawns.get(user_id(user))

    def others(self, junction: Junction, t_from: int, t_to: int) -> Mapping[str, Track]:
        tracks: dict[str, Track] = {}
        for user, found in self.observed.items():
            series, _ = samples(e for e in found if t_from <= e["t"] <= t_to)
            if series:
                tracks[user] = (series[0].ref.src, series)
        for src, found in self.states.items():
            series, _ = samples(e for e in found if t_from <= e["t"] <= t_to)
            if series and user_id(src) != self.ident:
                tracks[user_id(src)] = (src, series)
        return tracks
