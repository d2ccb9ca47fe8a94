"""One vehicle's junction passages, rebuilt from a Record (reasoner/record.py).

A passage is a maximal stretch of the vehicle's positions within RADIUS_M of a junction's
centre. Within it, in this order, each from the measurements and the map alone:

- the series: its own entity.state, or the monitors' measurements where those are denser;
- the approach (where it came from) and the stop line facing it;
- the crossing of that line: the first pair of consecutive samples from before the line to at
  or past it, the moment interpolated linearly between them (steady speed assumed), counted only
  once a later sample shows it CONFIRM_M past the line (positions are measured to about a metre);
- the light facing the approach: at the crossing, and at each change before it, with where the
  vehicle was and how fast;
- standstills (speed rounding to 0 mph), and whether each was at the line (from PAST_TOLERANCE_M
  past it to STOP_ZONE_M before it);
- entry into and exit from the junction's area, interpolated on its edge;
- the speed limit of its road, its emergency status, and the other road users near the centre.

Whatever the record cannot settle is said in `uncertain`: samples too far apart, sequence gaps
between them, a light changing between two samples, no stop line on the map.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Mapping, NamedTuple

from store import EventRef

from .junctions import Junction, Map, Road, StopLine, heading_sector, sector
from .motion import STOPPED_MPS, Sample, between, lerp, peak_deceleration, position_at, speed_at, stop_could_hide, xy
from .others import near_and_same_approach, own_cause, through
from .passage_values import AtChange, Crossing, Moment, Other, Passage, Standstill
from .record import Record, Track
from .sensors import Sensor, stated
from .signals import Light, changed_between, shown
from ..when import format_time

SECOND = 1_000_000_000
RADIUS_M = 100.0          # a passage: 3 s of amber at 30 mph (40 m), the stopping distance at 40 mph (36 m), a queue
EXIT_M = 30.0             # ... and ends this far from the centre once the vehicle has been in the junction
REJOIN_S = 3.0            # two stretches this close in time are one passage (positions jitter at the edge)
SPLIT_S = 60.0            # no sample for this long ends a passage
LINE_EPS_M = 0.05         # positions are not measured finer: 5 cm past the line is still on it
CONFIRM_M = 1.0           # a crossing counts once a sample shows the vehicle this far past the line
STOP_ZONE_M = 5.0         # "at the line": a car's reported point may be its centre, ~2 m behind its front
PAST_TOLERANCE_M = 1.0    # ... or up to a metre past it (measurement)
MAX_BRACKET_S = 1.5       # samples further apart than this leave a moment between them uncertain
OTHERS_BEFORE_S = 3.0     # other road users are looked for from this long before the crossing or entry
ANTICIPATION_S = 3.0      # braking counts from this long before the vehicle crossed (a driver sees it coming)
REACTION_S = 3.0          # ... until this long after it left
PATH_AFTER_S = 8.0        # a road user that braked or stopped is followed this much further, to see its way through
STAND_ON_S = 30.0         # ... and one standing when that ends, until it moves off, at most this much further: a
                          # right-turner waiting on oncoming traffic and those crossing its way (HC 170, 180) moves
                          # off well within it (the town run's 188, 13.5 s on); past it, what holds the road user is
                          # read no further (bounded time and memory), and it counts as standing at the record's end


def passages(record: Record) -> tuple[Passage, ...]:
    """Every passage of the record's vehicle through a junction of its map, in time order."""
    found = [passage(record, span.junction, span.t0, span.t1, span.through) for span in _spans(record)]
    return tuple(sorted(found, key=lambda p: (p.start, p.junction.id)))


def nearest(record: Record, t: int, found: list[Span] | None = None) -> Passage | None:
    """Only the passage under way at t, else the one nearest to it in time (`found`: the
    record's spans, if already computed)."""
    span = nearest_span(_spans(record) if found is None else found, t)
    return None if span is None else passage(record, span.junction, span.t0, span.t1, span.through)


def nearest_span(found: list[Span], t: int) -> Span | None:
    return min(found, key=lambda s: (0 if s.t0 <= t <= s.t1 else min(abs(t - s.t0), abs(t - s.t1)), s.t0),
               default=None)


def _spans(record: Record) -> list[Span]:
    placed = sorted((s for s in record.own + record.seen if s.placed), key=lambda s: (s.t, s.ref.src, s.ref.seq))
    return spans(placed, record.map)


class Span(NamedTuple):
    junction: Junction
    t0: int
    t1: int
    through: bool          # it went through the junction and out EXIT_M: the passage is complete


def spans(placed: list[Sample], map_: Map) -> list[Span]:
    """(junction, first t, last t, through) of each stretch of positions within RADIUS_M of a junction,
    ended EXIT_M from the centre once the vehicle has been in the junction: what happens on its
    way out is no part of the passage."""
    open_: dict[str, list] = {}            # junction id -> [junction, t0, t1, been inside]
    through: set[str] = set()              # junctions passed through, until the vehicle is RADIUS_M away
    done: list[list] = []
    split = SPLIT_S * SECOND
    for s in placed:
        x, y = xy(s)
        near = map_.near(x, y, RADIUS_M)
        if not near and not open_:
            through.clear()
            continue
        ids = {j.id for j in near}
        if through:
            through &= ids
        for jid, span in list(open_.items()):
            out = span[3] and span[0].distance(x, y) > EXIT_M
            if out or jid not in ids or s.t - span[2] > split:
                done.append(open_.pop(jid) + [out])
                if out:
                    through.add(jid)
        for junction in near:
            opened = open_.get(junction.id)
            if opened is not None:
                opened[2] = s.t
                opened[3] = opened[3] or junction.inside(x, y)
            elif junction.id not in through:
                open_[junction.id] = [junction, s.t, s.t, junction.inside(x, y)]
    done += [span + [False] for span in open_.values()]
    done.sort(key=lambda span: (span[0].id, span[1]))
    merged: list[list] = []
    for span in done:
        last = merged[-1] if merged else None
        if last is not None and last[0].id == span[0].id and span[1] - last[2] <= REJOIN_S * SECOND:
            last[2], last[4] = max(last[2], span[2]), span[4]
        else:
            merged.append(list(span))
    return [Span(j, t0, t1, out) for j, t0, t1, _, out in merged]


def passage(record: Record, junction: Junction, t0: int, t1: int, through: bool = False) -> Passage:
    """One passage, from everything the record holds between t0 and t1 (`through`: it ended
    with the vehicle out of the junction, EXIT_M away)."""
    series, name = _series(record, t0, t1)
    placed = [s for s in series if s.placed]
    notes: list[str] = []
    approach, line, method = _approach(junction, placed, notes)
    timeline = record.signals.timeline(junction.id, approach)
    lights = _lights(timeline, t0, t1)
    pairs = [(s, line.to_line(*xy(s))) for s in placed] if line else []
    crossing = _crossing(record, pairs, timeline, notes)
    end = crossing.t if crossing else t1
    changes = tuple(_at_change(light, timeline, series, line) for light in lights if t0 < light.t <= end)
    standstills = _standstills(series, line)
    entered, left, exit_arm = _entry(junction, placed, record, notes)
    limit_mph, road = _limit(record, placed, entered)
    _notes(record, junction, approach, line, lights, pairs, crossing, standstills, series, t0, t1, through, notes)
    key = crossing.t if crossing else entered.t if entered else t1
    out = left.t if left else t1
    others, same = near_and_same_approach(record.others(junction, max(t0, key - int(OTHERS_BEFORE_S * SECOND)),
                                      out + int(REACTION_S * SECOND)),
                        junction, record.vehicle, approach, max(t0, key - int(OTHERS_BEFORE_S * SECOND)),
                        out + int(REACTION_S * SECOND),
                        (key - int(ANTICIPATION_S * SECOND), out + int(REACTION_S * SECOND)), record.signals,
                        lambda user: _type(record.spawns(user)) == "pedestrian")
    others = _ways(record, junction, tuple(_typed(o, record.spawns(o.user)) for o in others),
                   max(t0, key - int(OTHERS_BEFORE_S * SECOND)), out + int(REACTION_S * SECOND))
    same = _ways(record, junction, tuple(_typed(o, record.spawns(o.user)) for o in same),
                      max(t0, key - int(OTHERS_BEFORE_S * SECOND)), out + int(REACTION_S * SECOND), every=True)
    spawn = record.spawn
    lead, trail = _beside(record, t0, t1)
    return Passage(
        run=record.run, vehicle=record.vehicle, junction=junction, approach=approach, approach_method=method,
        line=line, start=t0, end=t1, series=name, samples=series, lights=lights, changes=changes,
        crossing=crossing, past_line_at_start=bool(pairs) and pairs[0][1] <= 0,
        standstills=standstills, entered=entered, left=left, exit=exit_arm, limit_mph=limit_mph,
        limit_road=road, emergency=_emergency(record), vehicle_type=_type(spawn),
        spawn=EventRef.of(spawn) if spawn else None, others=others, uncertain=tuple(dict.fromkeys(notes)),
        map_ref=record.map.ref, first_report=timeline[0].ref if timeline else None,
        roads=_roads(record, [s for s in lead if s.placed] + placed + [s for s in trail if s.placed]),
        lead=lead, trail=trail, sensors=_sensors(record, others), same_approach=same)


# --- the pieces -------------------------------------------------------------------------------

def _sensors(record: Record, others: tuple[Other, ...]) -> tuple[tuple[str, Sensor], ...]:
    """The stated tolerance of each source the passage reads (DESIGN "Kinds": an entity.spawn's
    `tolerance` for the road user's own states, a map monitor's for its observations)."""
    found = dict(record.map.sensors)
    for spawn in (record.spawn, *(record.spawns(o.user) for o in others)):
        if not isinstance(spawn, dict):
            continue
        body = spawn.get("body")
        sensor = stated(body.get("tolerance"), EventRef.of(spawn)) if isinstance(body, dict) else None
        if sensor is not None and isinstance(spawn.get("src"), str):
            found[spawn["src"]] = sensor
    return tuple(sorted(found.items()))


def _ways(record: Record, junction: Junction, others: tuple[Other, ...], t_from: int, t_to: int,
          every: bool = False) -> tuple[Other, ...]:
    """The others, each that braked or stopped while its record in the window ends before its way
    through the junction did given that way, read on for PATH_AFTER_S: whether that way meets the
    vehicle's is what tells braking for it from braking for a turn of its own (derived.explained),
    and a main-road car still slowing on its arm when the window closes shows no way at all. Where a
    cause of its own explains the braking (others.own_cause), derived.explained looks no further.
    One that braked or stopped and is standing when that ends is read on until it moves off and
    PATH_AFTER_S beyond, at most STAND_ON_S further: when it moved off is what tells a stop made
    for V from one that V's going did not end (derived.stood_on; the town run's 188, standing at its right-turn place from 2.8 s
    after 247 had left their zone until oncoming 150 had passed, 14.5 s).
    `every`: each, read on for PATH_AFTER_S whatever it did (the road users on the vehicle's own approach: one that
    emerges after it crosses a main-road car's way as the window closes, attribution.py).
    A road user braking inside the junction is read on as one braking on its arm is: the reasoner
    counts braking on the way into and in the conflict zone too (derived._toward_zone), and where
    its way ends in the junction, the vehicle's positions further down it are in no way to be
    measured against (reaction.well_ahead: the paper run's 186, braking at 2.3 m/s² in j2 behind
    193, which had turned into its lane 34 m ahead and slowed to 6 m/s, read as well ahead)."""
    until = t_to + int(PATH_AFTER_S * SECOND)
    longer: dict[int, Mapping[str, Track]] = {}   # without a store: the others of a longer window, each read once

    def read(o: Other, t_end: int) -> tuple[Sample, ...]:
        own = record.track(o.src if not o.src.startswith("monitor/") else f"vehicle/{o.user}", t_from, t_end)
        if own is None:
            if t_end not in longer:
                longer[t_end] = record.others(junction, t_from, t_end)
            own = longer[t_end][o.user][1] if o.user in longer[t_end] else ()
        return tuple(s for s in own if s.t >= t_from)

    def way_on(o: Other, stand_on: bool = False) -> tuple[Sample, ...]:
        path = read(o, until)
        if not stand_on or not _standing_at_end(path):
            return path
        on = read(o, until + int(STAND_ON_S * SECOND))
        moved = next((s.t for s in on if s.t > until and s.speed_mps is not None and s.speed_mps > STOPPED_MPS), None)
        end = until + int(STAND_ON_S * SECOND) if moved is None else moved + int(PATH_AFTER_S * SECOND)
        return tuple(s for s in on if s.t <= end)

    out = []
    for o in others:
        if every:
            path = way_on(o)
            if len([s for s in path if s.placed]) > len([s for s in o.samples if s.placed]):
                o = replace(o, path=path)
        elif (o.braking or o.stopped or _braked_inside(o, junction, t_from, t_to)) and not own_cause(o) \
                and not through(o.samples, junction):
            path = way_on(o, stand_on=True)
            if through(path, junction):
                o = replace(o, path=path)
        out.append(o)
    return tuple(out)


def _standing_at_end(series: tuple[Sample, ...]) -> bool:
    """Whether the last speed measured in the series is a standstill: the road user is still
    standing where the window closes, and when it moves off (derived.stood_on) is further on."""
    last = next((s.speed_mps for s in reversed(series) if s.speed_mps is not None), None)
    return last is not None and last <= STOPPED_MPS


def _braked_inside(o: Other, junction: Junction, t_from: int, t_to: int) -> bool:
    """Whether the road user slowed while inside the junction's area in [t_from, t_to]
    (others.braking_into counts braking outside it only)."""
    inside = tuple(s for s in o.samples if s.placed and junction.edge(*xy(s)) <= 0)
    braking = peak_deceleration(inside, t_from, t_to)
    return braking is not None and braking.decel_mps2 > 0


def _series(record: Record, t0: int, t1: int) -> tuple[tuple[Sample, ...], str]:
    """The vehicle's own entity.state in the passage, unless the monitors placed it more often."""
    own = tuple(s for s in record.own if t0 <= s.t <= t1)
    seen = tuple(s for s in record.seen if t0 <= s.t <= t1)
    if sum(s.placed for s in own) >= sum(s.placed for s in seen) and own:
        return own, "entity.state"
    return seen, "monitor.observation"


def _approach(junction: Junction, placed: list[Sample], notes: list[str]) -> tuple[str | None, StopLine | None, str]:
    """Where the vehicle came from, and its stop line: from its first position, if that is
    outside the junction and it then got closer; else from its heading."""
    if not placed:
        return None, None, "no position in the passage"
    first = placed[0]
    x, y = xy(first)
    if junction.edge(x, y) > 0 and _closing(junction, placed):
        arm = sector(x - junction.x, y - junction.y)
        line = _line(junction, arm, first)
        how = (f"from its first position in the passage, {junction.distance(x, y):.0f} m {arm} of the "
               f"centre ({first.label}), then closer")
    else:
        found = next(((s, s.heading_deg) for s in placed if s.heading_deg is not None), None)
        if found is None:
            notes.append("where the vehicle came from is not in the record: first seen in or leaving the junction, "
                         "with no heading")
            return None, None, "unknown"
        heading, degrees = found
        arm = heading_sector(degrees)
        line = junction.line_for(arm)
        how = f"from its heading, {degrees:.0f}° ({heading.label}): first seen in or leaving the junction"
    return (line.approach if line else arm), line, how


def _closing(junction: Junction, placed: list[Sample]) -> bool:
    first = junction.distance(*xy(placed[0]))
    return len(placed) == 1 or min(junction.distance(*xy(s)) for s in placed) < first - 0.5


def _line(junction: Junction, arm: str, first: Sample) -> StopLine | None:
    """The stop line of the approach named like the vehicle's sector, else the nearest line
    the vehicle is in front of."""
    x, y = xy(first)
    named = junction.line_for(arm)
    if named is not None and named.to_line(x, y) > 0:
        return named
    ahead = [line for line in junction.lines
             if line.to_line(x, y) > 0 and line.alongside(x, y)]
    return min(ahead, key=lambda line: line.to_line(x, y), default=None)


def _lights(timeline: tuple[Light, ...], t0: int, t1: int) -> tuple[Light, ...]:
    """The light showing at t0, then each change until t1."""
    first = shown(timeline, t0)
    return ((first,) if first else ()) + changed_between(timeline, t0, t1)


def _crossing(record: Record, pairs: list[tuple[Sample, float]], timeline: tuple[Light, ...],
              notes: list[str]) -> Crossing | None:
    i = _crossing_index(pairs, notes)
    if i is None:
        return None
    (a, da), (b, db) = pairs[i], pairs[i + 1]
    f = min(1.0, max(0.0, da / (da - db)))
    t = a.t + round(f * (b.t - a.t))
    before = "at the line" if abs(da) < 0.05 else f"{da:.1f} m before the line"
    method = f"linear interpolation between {a.label} ({before}) and {b.label} ({-db:.1f} m past it)"
    moment = Moment(t, (a, b), method, _bracket_doubt(record, a, b))
    light = shown(timeline, t)
    within = changed_between(timeline, a.t, b.t)
    doubt = None
    if within:
        change = within[-1]
        lag = (t - change.t) / SECOND
        doubt = (f"the light changed to {change.colour} between the two samples; the crossing is read at the "
                 f"interpolated moment, {abs(lag):.2f} s {'after' if lag >= 0 else 'before'} the change, which "
                 "assumes steady speed between them")
    gaps = record.gaps_of({r.src for r in ((light.ref,) if light else ())} | {x.ref.src for x in timeline},
                          light.t if light else a.t, t)
    if gaps:
        doubt = "; ".join(filter(None, [doubt, f"{gaps[0].words}: a change of the light may be missing"]))
    return Crossing(moment, da, db, lerp(a.speed_mps, b.speed_mps, f), light, within, doubt)


def _crossing_index(pairs: list[tuple[Sample, float]], notes: list[str]) -> int | None:
    """The first pair from at or before the line to past it (by more than LINE_EPS_M: a vehicle
    standing on the line has not crossed it) that a later sample confirms."""
    for i in range(len(pairs) - 1):
        if not pairs[i][1] >= -LINE_EPS_M > pairs[i + 1][1]:
            continue
        for s, d in pairs[i + 1:]:
            if d >= -LINE_EPS_M:
                break
            if d <= -CONFIRM_M:
                return i
        else:
            deepest = -min(d for _, d in pairs[i + 1:])
            notes.append(f"last seen {deepest:.1f} m past the stop line ({pairs[-1][0].label}), never {CONFIRM_M:g} m "
                         "past it: not counted as crossing it")
    return None


def _bracket_doubt(record: Record, a: Sample, b: Sample) -> str | None:
    doubts = []
    if b.t - a.t > MAX_BRACKET_S * SECOND:
        doubts.append(f"the two samples are {(b.t - a.t) / SECOND:.1f} s apart: the moment lies anywhere between them")
    for gap in record.gaps:
        if (a.ref.src == b.ref.src == gap.src and gap.between(a.ref.seq, b.ref.seq)) or \
                (gap.src in (a.ref.src, b.ref.src) and a.ref.src != b.ref.src and gap.overlaps(a.t, b.t)):
            doubts.append(f"{gap.words}: the moment lies in that gap")
    return "; ".join(doubts) or None


def _at_change(light: Light, timeline: tuple[Light, ...], series: tuple[Sample, ...],
               line: StopLine | None) -> AtChange:
    previous = next((x.colour for x in reversed(timeline) if x.t < light.t), None)
    position, placed_by = position_at(series, light.t)
    speed, timed_by = speed_at(series, light.t)
    to_line = line.to_line(*position) if line and position else None
    used = tuple(dict.fromkeys(placed_by + timed_by))
    method = between(placed_by or timed_by, light.t) if used else "no sample around the change"
    return AtChange(light, previous, to_line, speed, used, method)


def _standstills(series: tuple[Sample, ...], line: StopLine | None) -> tuple[Standstill, ...]:
    """Each run of consecutive speed samples at which the vehicle stood still."""
    runs: list[list[Sample]] = []
    still = False
    for s in series:
        speed = s.speed_mps
        if speed is None:
            continue
        if speed <= STOPPED_MPS:
            if still:
                runs[-1].append(s)
            else:
                runs.append([s])
        still = speed <= STOPPED_MPS
    out = []
    for run in runs:
        last = next((s for s in reversed(run) if s.placed), None)
        d = line.to_line(*xy(last)) if line and last else None
        out.append(Standstill(run[0], run[-1], len(run), d,
                              d is not None and -PAST_TOLERANCE_M <= d <= STOP_ZONE_M))
    return tuple(out)


def _entry(junction: Junction, placed: list[Sample], record: Record, notes: list[str]
           ) -> tuple[Moment | None, Moment | None, str | None]:
    """When the vehicle entered and left the junction's area, interpolated on its edge, and the
    arm it left by."""
    edges = [(s, junction.edge(*xy(s))) for s in placed]
    if not edges:
        return None, None, None
    inside = edges[0][1] <= 0
    if inside:
        notes.append(f"first seen inside the junction ({edges[0][0].label}): its entry is not in the record")
    entered = None
    for (a, ea), (b, eb) in zip(edges, edges[1:]):
        if not inside and ea > 0 >= eb and entered is None:
            entered, inside = _edge_moment(record, a, ea, b, eb), True
        elif inside and ea <= 0 < eb:
            x, y = xy(b)
            return entered, _edge_moment(record, a, ea, b, eb), sector(x - junction.x, y - junction.y)
    return entered, None, None


def _edge_moment(record: Record, a: Sample, ea: float, b: Sample, eb: float) -> Moment:
    f = ea / (ea - eb)
    t = a.t + round(f * (b.t - a.t))
    method = (f"linear interpolation between {a.label} ({abs(ea):.1f} m {'outside' if ea > 0 else 'inside'}) and "
              f"{b.label} ({abs(eb):.1f} m {'inside' if eb <= 0 else 'outside'} the junction's area)")
    return Moment(t, (a, b), method, _bracket_doubt(record, a, b))


def _limit(record: Record, placed: list[Sample], entered: Moment | None) -> tuple[float | None, str | None]:
    """The speed limit of the road the vehicle approached on (its last position before entering)."""
    before = [s for s in placed if entered is None or s.t <= entered.t] or placed
    for s in reversed(before):
        road = record.map.road(s.road, s.x, s.y)
        if road is not None:
            return road.limit_mph, road.id
    return None, None


LEAD_S = 30.0          # the vehicle's own samples kept from either side of a passage: a speeding stretch


def _beside(record: Record, t0: int, t1: int) -> tuple[tuple[Sample, ...], tuple[Sample, ...]]:
    """The vehicle's own samples read in the LEAD_S before the passage began and after it ended."""
    span = int(LEAD_S * SECOND)
    return (tuple(s for s in record.own if t0 - span <= s.t < t0),
            tuple(s for s in record.own if t1 < s.t <= t1 + span))


ROAD_EVERY_S = 0.5     # a position on no named road is snapped to the nearest road at most this often


def _roads(record: Record, placed: list[Sample]) -> tuple[tuple[int, str, float | None], ...]:
    """The roads the samples are on, each from the first sample on it (a speed limit is the
    road's: a speeding act is measured on its own road, not the passage's approach). A sample
    naming a road of the map is on it; one naming none is snapped to the nearest road, at most
    once every ROAD_EVERY_S (a map of many roads costs a search of them all per snap)."""
    out: list[tuple[int, str, float | None]] = []
    named: dict[str, Road | None] = {}
    snapped_at: int | None = None
    snapped: Road | None = None
    for s in placed:
        road = named.get(s.road) if isinstance(s.road, str) else None
        if road is None and isinstance(s.road, str) and s.road not in named:
            found = record.map.road(s.road, None, None)
            named[s.road] = found
            road = found
        if road is None:
            if snapped_at is None or s.t - snapped_at >= ROAD_EVERY_S * SECOND:
                snapped_at, snapped = s.t, record.map.road(None, s.x, s.y)
            road = snapped
        if road is not None and (not out or out[-1][1] != road.id):
            out.append((s.t, road.id, road.limit_mph))
    return tuple(out)


def _emergency(record: Record) -> tuple[tuple[int, bool, EventRef], ...]:
    """When the vehicle went on or off an emergency call: its spawn, then its states."""
    marks = []
    spawn = record.spawn
    if spawn and isinstance(spawn.get("body"), dict) and isinstance(spawn["body"].get("emergency"), bool):
        marks.append((spawn["t"], spawn["body"]["emergency"], EventRef.of(spawn)))
    marks += [(s.t, s.emergency, s.ref) for s in record.own if s.emergency is not None]
    out: list[tuple[int, bool, EventRef]] = []
    for mark in sorted(marks, key=lambda m: (m[0], m[2].seq)):
        if not out or out[-1][1] != mark[1]:
            out.append(mark)
    return tuple(out)


TYPES = frozenset({"car", "ambulance", "fire_engine", "police_car", "bus", "cyclist", "pedestrian"})   # DESIGN's


def _typed(other: Other, spawn: dict | None) -> Other:
    """The other road user with the type its entity.spawn gives, if any."""
    kind = _type(spawn)
    return replace(other, type=kind, spawn=EventRef.of(spawn)) if spawn is not None and kind in TYPES else other


def _type(spawn: dict | None) -> str | None:
    body = spawn.get("body") if spawn else None
    return body.get("type") if isinstance(body, dict) and isinstance(body.get("type"), str) else None


def _notes(record: Record, junction: Junction, approach: str | None, line: StopLine | None,
           lights: tuple[Light, ...], pairs: list, crossing: Crossing | None, standstills: tuple[Standstill, ...],
           series: tuple[Sample, ...], t0: int, t1: int, through: bool, notes: list[str]) -> None:
    """What the record leaves open about this passage, in words."""
    if line is None and approach is not None:
        notes.append(f"the map gives no stop line for the {approach} approach of {junction.id}: the crossing and "
                     "distances to the line are not derived")
    if junction.control == "lights" and not lights:
        notes.append(f"no signal.state for the {approach} approach of {junction.id}: its light is not known")
    if lights and lights[0].t < t0 and lights[0].colour == "amber" and crossing is not None:
        notes.append(f"the light turned amber ({format_time(lights[0].t)}) before the vehicle's first sample here: "
                     "where it was then is not in the record")
    if pairs and pairs[0][1] <= 0:
        notes.append(f"first seen already past the stop line ({pairs[0][0].label}): the crossing is not in the record")
    if line is not None and _stop_line(junction, line):
        _hidden_stops(series, line, crossing, standstills, notes)
    srcs = {s.ref.src for s in series}
    notes += [f"{gap.words}, within this passage" for gap in record.gaps_of(srcs, t0, t1)]
    start, end = record.window
    placed = [s.t for s in record.own + record.seen if s.placed]
    if start is not None and placed and t0 <= min(placed):
        notes.append("the passage begins with the first sample read: the vehicle was near the junction before "
                     "what was read, or before its record begins")
    if end is not None and placed and t1 >= max(placed) and not through:
        notes.append("the passage ends with the last sample read, the vehicle not yet out of the junction: the "
                     "read, or its record, stops there")


def _stop_line(junction: Junction, line: StopLine) -> bool:
    return line.kind == "stop_sign" or (not line.kind and junction.control == "stop")


def _hidden_stops(series: tuple[Sample, ...], line: StopLine, crossing: Crossing | None,
                  standstills: tuple[Standstill, ...], notes: list[str]) -> None:
    """Near a Stop line, two samples between which a stop could have passed unseen."""
    end = crossing.t if crossing else None
    if any(s.at_line and (end is None or s.first.t <= end) for s in standstills):
        return
    timed = [s for s in series if s.speed_mps is not None and s.placed and (end is None or s.t <= end)]
    for a, b in zip(timed, timed[1:]):
        near = -PAST_TOLERANCE_M <= line.to_line(*xy(b)) <= STOP_ZONE_M + 10.0
        if near and stop_could_hide(a, b):
            notes.append(f"between {a.label} ({a.speed_mps:.1f} m/s) and {b.label} ({b.speed_mps:.1f} m/s) the "
                         "vehicle could have stopped unseen: the samples cannot tell whether it stopped at the line")
            return
