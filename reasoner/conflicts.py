"""Conflicts between a vehicle's path and another road user's, and the surrogate safety measures
of traffic-conflict analysis read from the two records (docs/history.md, "Conflicts").

    conflict(mine, theirs, act, walker=False) -> Conflict | None

Each road user's path is the polyline of its measured positions. The part of the road it sweeps
is that line widened by half its width; where the two swept areas overlap, near the point where
the two paths meet, is their conflict zone (shapely does the geometry). From the times each was
in the zone (its centre within half a car's length of it, found between samples by linear
interpolation along the segment that enters or leaves it) come the measures:

- PET, post-encroachment time (Allen, Shin & Cooper 1978): the time from the first road user
  leaving the zone to the second entering it; 0 where both were in it at once.
- TTC at the act (Hayward 1972): were both to keep their speeds along their paths from the
  moment of the act, the time until both would be in the zone together; none when they would not.
- The projected gap: were the other to keep the speed it had when it began to slow, the PET it
  would have had. A road user that slowed with a projected gap under PET_MAX_S slowed where an
  accident was to avoid; one whose unslowed gap was wider slowed for something else.
- DRAC, the deceleration rate to avoid the crash (Cooper & Ferguson 1976, as SUMO's SSM device
  computes it for crossing conflicts): the steady deceleration that, from the moment it began
  to slow, brings the other to the zone no earlier than the vehicle left it (to a stop short of
  it, where that comes first); and the deceleration it applied (motion.peak_deceleration).

The thresholds are those of SUMO's SSM device (MSDevice_SSM.cpp, DEFAULT_THRESHOLD_*; SUMO
documentation "SSM Device"), so that a conflict here is one the simulator's own account would
log with its default settings. Nothing is guessed: where a path or a speed is not in the record,
the measure is None and the caller says so.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any, Sequence

from shapely.geometry import LineString, Point
from shapely.geometry.base import BaseGeometry

from .history import Sample, position_at, speed_at, xy

SECOND = 1_000_000_000

VEHICLE_WIDTH_M = 2.55   # the widest a vehicle may be (Road Vehicles (Construction and Use) Regulations 1986 reg. 8)
CAR_LENGTH_M = 5.0       # a passenger car's length, SUMO's default vType (length 5 m)
WALKER_WIDTH_M = 0.48    # a pedestrian's width, SUMO's default pedestrian vType (width 0.478 m)
WALKER_LENGTH_M = 0.22   # ... and its length (0.215 m)
RIDER_WIDTH_M = 0.65     # a cyclist's width, SUMO's default bicycle vType (DEFAULT_BIKETYPE: width 0.65 m)
RIDER_LENGTH_M = 1.6     # ... and its length (1.6 m)
PET_MAX_S = 2.0          # SUMO SSM device, DEFAULT_THRESHOLD_PET: an encounter with a PET below 2 s is a conflict
TTC_MAX_S = 3.0          # SUMO SSM device, DEFAULT_THRESHOLD_TTC
DRAC_MAX_MPS2 = 3.0      # SUMO SSM device, DEFAULT_THRESHOLD_DRAC
SWERVE_M = 1.0           # a sideways departure from the line it was on beyond this is a change of course: a car
                         # centred in a 3.65 m lane (DMRB CD 127) has (3.65 - 1.8) / 2 = 0.9 m to either side
                         # (SUMO's default passenger vType is 1.8 m wide); more takes it out of its lane
SWERVE_MAX_M = 5.5       # ... and up to a lane's width and a car's (DMRB CD 127's 3.65 m + 1.8 m): a road user
                         # further than that from its line is on another way (a turn, a fork), not swerving on its own
TURNED_DEG = 45.0        # a road user whose way afterwards is more than this off its way before turned (its own
                         # manoeuvre, reaction.SAME_WAY_DEG), which is no swerve

SOURCES = {
    "PET_MAX_S": "SUMO SSM device default PET threshold (MSDevice_SSM.cpp DEFAULT_THRESHOLD_PET); PET as defined "
                 "by Allen, Shin & Cooper (1978)",
    "TTC_MAX_S": "SUMO SSM device default TTC threshold (DEFAULT_THRESHOLD_TTC); TTC as defined by Hayward (1972)",
    "DRAC_MAX_MPS2": "SUMO SSM device default DRAC threshold (DEFAULT_THRESHOLD_DRAC); DRAC as defined by Cooper & "
                     "Ferguson (1976)",
    "SWERVE_M": "stated here: the room a car centred in its lane has to either side, (3.65 m lane, DMRB CD 127, "
                "less a 1.8 m car, SUMO's default passenger vType) / 2 = 0.9 m, rounded up",
}


@dataclass(frozen=True)
class Occupancy:
    """When a road user was in the zone: from `entered` to `left` (ns); None where the record
    does not show it (already in at its first sample, still in at its last)."""

    entered: int | None
    left: int | None
    samples: tuple[Sample, ...]             # the samples about the two moments

    def to_json(self) -> dict[str, Any]:
        return {"entered": self.entered, "left": self.left, "evidence": [s.ref.to_json() for s in self.samples]}


@dataclass(frozen=True)
class Conflict:
    """Where two paths meet and how close in time the two road users came there."""

    x: float                                # the conflict point: where the two paths meet
    y: float
    area_m2: float                          # the conflict zone's area
    mine: Occupancy                         # the vehicle's time in the zone
    theirs: Occupancy | None                # the other's (None: the record never shows it there)
    pet_s: float | None                     # measured post-encroachment time
    first: str | None                       # "mine" or "theirs": who was in the zone first
    ttc_s: float | None = None              # at the act, both keeping their speeds
    projected_gap_s: float | None = None    # the PET the other would have had, unslowed
    drac_mps2: float | None = None          # the deceleration it needed to arrive once the vehicle left
    onset: int | None = None                # when the other began to slow (what the last two are taken at)
    onset_to_zone_m: float | None = None    # ... how far it was from the zone then
    onset_speed_mps: float | None = None    # ... and how fast it went

    def to_json(self) -> dict[str, Any]:
        def r(v: float | None) -> float | None:
            return None if v is None else round(v, 3)
        return {"x": r(self.x), "y": r(self.y), "area_m2": r(self.area_m2), "mine": self.mine.to_json(),
                "theirs": self.theirs.to_json() if self.theirs else None, "pet_s": r(self.pet_s), "first": self.first,
                "ttc_s": r(self.ttc_s), "projected_gap_s": r(self.projected_gap_s), "drac_mps2": r(self.drac_mps2),
                "onset": self.onset, "onset_to_zone_m": r(self.onset_to_zone_m),
                "onset_speed_mps": r(self.onset_speed_mps)}


def conflict(mine: Sequence[Sample], theirs: Sequence[Sample], act: int | None, *, walker: bool = False,
             onset: int | None = None, extend_m: float = 0.0, mine_walker: bool = False,
             rider: bool = False) -> Conflict | None:
    """The conflict between the vehicle's path (`mine`) and another road user's (`theirs`), with
    its measures: TTC taken at `act`, the projected gap and DRAC at `onset` (when the other began
    to slow). `extend_m`: the other's path goes on this far straight ahead of its last position
    (one whose record ends standing short of the junction: the way it was going). None when the
    two paths never come within their half widths of each other, or either path is not in the
    record (fewer than two positions). `mine_walker`: the first path is a pedestrian's (a road
    user other than the vehicle, whose conflict with the other's path is asked about:
    reasoner/attribution.py). `rider`: the other is a cyclist (`size`)."""
    a, b = _line(mine), _line(theirs, extend_m)
    if a is None or b is None:
        return None
    their_width, their_length = size(walker, rider)
    my_width, my_length = (WALKER_WIDTH_M, WALKER_LENGTH_M) if mine_walker else (VEHICLE_WIDTH_M, CAR_LENGTH_M)
    met = _zone(a, b, my_width, their_width)
    if met is None:
        return None
    point, zone = met
    my_time = _occupied(mine, zone, my_length, by_front=walker and not mine_walker)
    if my_time is None:
        return None
    their_time = _occupied(theirs, zone, their_length, by_front=mine_walker and not walker)
    pet, first = _pet(my_time, their_time)
    ttc = _ttc(mine, theirs, a, b, zone, act, their_length, my_length) if act is not None else None
    gap, drac, to_zone, speed = _projected(theirs, b, zone.buffer(their_length / 2), my_time, onset)
    return Conflict(point.x, point.y, zone.area, my_time, their_time, pet, first, ttc, gap, drac,
                    onset if gap is not None else None, to_zone, speed)


def size(walker: bool, rider: bool = False) -> tuple[float, float]:
    """The width and length of the part of the road a road user sweeps: a pedestrian's, a
    cyclist's (SUMO's default bicycle), else the widest vehicle's with a car's length. A cyclist
    read as a 2.55 m wide, 5 m long vehicle sweeps a metre or more into the lane beside its own:
    the paper run's cyclist 223, riding out of j2's south arm past 182 coming in the other lane
    (3.5 m between their lanes' centres) after crossing 182's way 4.7 s ahead of it, was read
    as in their conflict zone with 182 at once (post-encroachment time 0, "182 would endanger
    223"); SUMO's account has the two passing."""
    if walker:
        return WALKER_WIDTH_M, WALKER_LENGTH_M
    if rider:
        return RIDER_WIDTH_M, RIDER_LENGTH_M
    return VEHICLE_WIDTH_M, CAR_LENGTH_M


@dataclass(frozen=True)
class Swerve:
    """A change of course: how far a road user moved sideways off the line it was on at V's act,
    going on the same way (no turn of its own), and the post-encroachment time with V it would
    have had on that line (`kept_pet_s`: under PET_MAX_S, the swerve avoided an accident)."""

    offset_m: float                         # its largest sideways departure from the line
    widest: Sample                          # the sample where it was widest of the line
    before: tuple[Sample, Sample]           # the two samples its line at the act is read from
    kept_pet_s: float | None                # PET with V, had it kept to that line
    kept_first: str | None                  # who would have been in the zone first then
    departed: Sample | None = None          # its first sample SWERVE_M or more off the line

    def to_json(self) -> dict[str, Any]:
        return {"offset_m": round(self.offset_m, 3), "widest": self.widest.ref.to_json(),
                "before": [s.ref.to_json() for s in self.before],
                "kept_pet_s": None if self.kept_pet_s is None else round(self.kept_pet_s, 3),
                "kept_first": self.kept_first}


def swerve(mine: Sequence[Sample], theirs: Sequence[Sample], act: int, until: int) -> Swerve | None:
    """A change of course by the other road user between V's act and `until`: its line is the way
    it went over the second before the act (two placed samples a metre or more apart); a sample
    in the window SWERVE_M to SWERVE_MAX_M to the side of that line, with its way at the window's end
    within TURNED_DEG of the line's, is a swerve. Its measure is the conflict V would have had
    with it had it kept to the line: its samples taken at the same times, laid on the line.
    None where the record shows no such line, no such departure, or a turn."""
    placed = [s for s in theirs if s.placed]
    before = [s for s in placed if act - SECOND <= s.t <= act]
    if len(before) < 2:
        return None
    a, b = before[0], before[-1]
    (ax, ay), (bx, by) = xy(a), xy(b)
    length = math.hypot(bx - ax, by - ay)
    if length < 1.0:
        return None                         # standing or creeping: no line to leave
    ux, uy = (bx - ax) / length, (by - ay) / length
    window = [s for s in placed if act < s.t <= until]
    if len(window) < 2:
        return None
    side = [((x - bx) * -uy + (y - by) * ux, s) for s in window for x, y in [xy(s)]]
    offset, widest = max(side, key=lambda o: abs(o[0]))
    if abs(offset) < SWERVE_M or abs(offset) > SWERVE_MAX_M:
        return None                         # kept its line, or left it for another way
    last = placed[-1] if placed[-1].t <= until + 2 * SECOND else window[-1]
    tail = [s for s in placed if last.t - SECOND <= s.t <= last.t]
    if len(tail) >= 2:
        (x0, y0), (x1, y1) = xy(tail[0]), xy(tail[-1])
        dx, dy = x1 - x0, y1 - y0
        if math.hypot(dx, dy) >= 1.0:
            turn = abs(math.degrees(math.atan2(ux * dy - uy * dx, ux * dx + uy * dy)))
            if turn > TURNED_DEG:
                return None                 # it turned: its own manoeuvre
    kept = [s._replace(x=bx + ux * ((x - bx) * ux + (y - by) * uy),
                       y=by + uy * ((x - bx) * ux + (y - by) * uy)) if s.t > act else s
            for s in placed for x, y in [xy(s)]]
    c = conflict(mine, kept, act)
    departed = next(s for o, s in side if abs(o) >= SWERVE_M)
    return Swerve(abs(offset), widest, (a, b), c.pet_s if c else None, c.first if c else None, departed)


def has_path(samples: Sequence[Sample]) -> bool:
    """Whether the record holds a path for the road user (two distinct positions or more)."""
    return _line(samples) is not None


def _line(samples: Sequence[Sample], extend_m: float = 0.0) -> LineString | None:
    points: list[tuple[float, float]] = []
    for s in samples:
        if s.placed and (not points or (s.x, s.y) != points[-1]):
            points.append(xy(s))
    if len(points) < 2:
        return None
    if extend_m > 0:
        (x0, y0), (x1, y1) = points[-2], points[-1]
        length = math.hypot(x1 - x0, y1 - y0)
        points.append((x1 + (x1 - x0) / length * extend_m, y1 + (y1 - y0) / length * extend_m))
    return LineString(points)


def _meeting(a: LineString, b: LineString) -> Point:
    """Where the two paths meet: the first crossing along the vehicle's path; where they do not
    cross, the point of the vehicle's path nearest the other's."""
    crossing = a.intersection(b)
    points = [g for g in getattr(crossing, "geoms", [crossing]) if not g.is_empty]
    if points:
        first = min(points, key=lambda g: a.project(g.representative_point()))
        return first.representative_point() if first.geom_type != "Point" else first
    return a.interpolate(a.project(b.interpolate(b.project(a.centroid))))


def _occupied(samples: Sequence[Sample], zone: BaseGeometry, length: float, by_front: bool = False) -> Occupancy | None:
    """When a road user was in the zone: while its position was within half its length of it, as
    if the position were its middle. Between two vehicles that errs alike on both sides (each
    comes in and leaves half a length early at its own speed), so their post-encroachment time
    stands. Against a pedestrian (`by_front`), whose length is a fifth of a metre, it does not: a
    position is the vehicle's front (DESIGN, entity.state), so the vehicle comes into the zone
    when its front reaches it. A car standing at its line with its front 1.7 m short of a
    pedestrian's way is not in the zone with the pedestrian passing in front of it (the paper
    run's 249 and p9). It has left by the time its front is half its length past the zone (its
    back leaves a whole length past: its time there is never taken longer than the record
    shows). A path that only grazes the zone (its front never in it) is read as before."""
    near = _occupancy(samples, zone.buffer(length / 2))
    if near is None or not by_front:
        return near
    front = _occupancy(samples, zone)
    if front is None:
        return near
    return Occupancy(front.entered, near.left, tuple(dict.fromkeys(front.samples[:2] + near.samples[-2:])))


def _occupancy(samples: Sequence[Sample], region: BaseGeometry) -> Occupancy | None:
    """The first entry into `region` and the last exit from it, interpolated along the segments
    between placed samples; None when no segment of the path meets it."""
    placed = [s for s in samples if s.placed]
    entered: int | None = None
    left: int | None = None
    used: list[Sample] = []
    met = False
    for i, s in enumerate(placed):
        if i == 0:
            if region.contains(Point(s.x, s.y)):
                met, used = True, [s]
            continue
        p = placed[i - 1]
        seg = LineString([(p.x, p.y), (s.x, s.y)]) if (p.x, p.y) != (s.x, s.y) else None
        if seg is None:
            continue
        part = seg.intersection(region)
        if part.is_empty:
            continue
        fractions = [seg.project(Point(c)) / seg.length for g in getattr(part, "geoms", [part]) for c in g.coords]
        if not met:
            met = True
            entered = p.t + round((s.t - p.t) * min(fractions))
            used = [p, s]
        f = max(fractions)
        left = p.t + round((s.t - p.t) * f) if f < 1.0 - 1e-9 else None
        used = used[:2] + [p, s]
    if not met:
        return None
    if left is None and placed and not region.contains(Point(placed[-1].x, placed[-1].y)):
        left = placed[-1].t
    return Occupancy(entered, left, tuple(dict.fromkeys(used)))


def _pet(mine: Occupancy, theirs: Occupancy | None) -> tuple[float | None, str | None]:
    """The post-encroachment time and who was there first; None where the record leaves it open."""
    if theirs is None:
        return None, None
    if mine.left is not None and theirs.entered is not None and mine.left <= theirs.entered:
        return (theirs.entered - mine.left) / SECOND, "mine"
    if theirs.left is not None and mine.entered is not None and theirs.left <= mine.entered:
        return (mine.entered - theirs.left) / SECOND, "theirs"
    if mine.entered is not None and theirs.entered is not None:
        return 0.0, "mine" if mine.entered <= theirs.entered else "theirs"
    return None, None


def _along(line: LineString, region: BaseGeometry) -> tuple[float, float] | None:
    """How far along the line it enters the region and leaves it."""
    part = line.intersection(region)
    if part.is_empty:
        return None
    ats = [line.project(Point(c)) for g in getattr(part, "geoms", [part]) for c in g.coords]
    return min(ats), max(ats)


def _ttc(mine: Sequence[Sample], theirs: Sequence[Sample], a: LineString, b: LineString, zone: BaseGeometry,
         act: int, their_length: float, my_length: float = CAR_LENGTH_M) -> float | None:
    """Hayward's time to collision at the act: both keep the speeds they had then along their
    own paths; the time until both would be in the zone, or None."""
    spans = []
    for samples, line, length in ((mine, a, my_length), (theirs, b, their_length)):
        where, _ = position_at(samples, act)
        speed, _ = speed_at(samples, act)
        reach = _along(line, zone.buffer(length / 2))
        if where is None or speed is None or reach is None:
            return None
        here = line.project(Point(where))
        start, end = reach[0] - here, reach[1] - here
        if end < 0:
            return None                     # already past it
        if speed <= 0.1:
            if start > 0:
                return None                 # standing short of it: never there at this speed
            spans.append((0.0, math.inf))
            continue
        spans.append((max(start, 0.0) / speed, end / speed))
    (s1, e1), (s2, e2) = spans
    if s1 > e2 or s2 > e1:
        return None
    return max(s1, s2)


def _projected(theirs: Sequence[Sample], b: LineString, region: BaseGeometry, mine: Occupancy,
               onset: int | None) -> tuple[float | None, float | None, float | None, float | None]:
    """At `onset`, the other's distance to the zone and speed; the PET it would have had at that
    speed (negative: it would have been in the zone while the vehicle was); the deceleration it
    needed to arrive no earlier than the vehicle left (DRAC). Where the vehicle's record ends with
    it still in the zone, the other, coming in before that end, would have been there with it: the
    gap is at most its arrival less that end (its DRAC is not measured); coming in later, or
    through before it came, the gap is not in the record, as before. The paper run's 266,
    crawling out of j2's north arm into 205's lane ahead of it, was still in their zone where its
    record read for 279's passage ended."""
    if onset is None or (mine.left is None and not mine.samples):
        return None, None, None, None
    where, _ = position_at(theirs, onset)
    speed, _ = speed_at(theirs, onset)
    reach = _along(b, region)
    if where is None or speed is None or reach is None:
        return None, None, None, None
    to_zone = reach[0] - b.project(Point(where))
    if to_zone <= 0:
        return None, None, None, None       # already in it when it began to slow
    if speed <= 0.1:
        return math.inf, 0.0, to_zone, speed
    arrive = onset + to_zone / speed * SECOND
    leave = onset + (reach[1] - b.project(Point(where))) / speed * SECOND
    through_first = mine.entered is not None and leave <= mine.entered
    if mine.left is None:
        # the vehicle's record ends while it is still in the zone (it left later, when is not in the
        # record): only the other coming in before that end, while it was there, is measured
        if through_first or arrive >= mine.samples[-1].t:
            return None, None, None, None
        return (arrive - mine.samples[-1].t) / SECOND, None, to_zone, speed
    if through_first:
        gap = (mine.entered - leave) / SECOND   # it would have gone through first
    else:
        gap = (arrive - mine.left) / SECOND
    return gap, _drac(to_zone, speed, (mine.left - onset) / SECOND), to_zone, speed


def _zone(a: LineString, b: LineString, my_width: float, their_width: float) -> tuple[Point, BaseGeometry] | None:
    """Where the two paths meet and their conflict zone: the overlap of the areas they sweep, within
    twice their half widths of that point. None where they never overlap."""
    reach = (my_width + their_width) / 2
    overlap = a.buffer(my_width / 2, cap_style="flat").intersection(b.buffer(their_width / 2, cap_style="flat"))
    if overlap.is_empty or overlap.area <= 0:
        return None
    point = _meeting(a, b)
    zone = overlap.intersection(point.buffer(2 * reach))
    if zone.is_empty or zone.area <= 0:
        return None
    return point, zone


def exit_gap(mine: Sequence[Sample], theirs: Sequence[Sample], onset: int, extend_m: float = 0.0) -> float | None:
    """For a vehicle (`theirs`) already in its conflict zone with the vehicle of `mine` when it began
    to slow (at `onset`), where the projected gap is not defined (it was not on its way to the
    zone): had it kept the speed it had then along its path, the time from its leaving the zone to
    the other's coming in (0 or less: the other would have come in while it was still there; a
    road user standing then never leaves). None where it was not in the zone then, or the record
    cannot tell (a path, its position or speed then, the other's entry)."""
    a, b = _line(mine), _line(theirs, extend_m)
    if a is None or b is None:
        return None
    met = _zone(a, b, VEHICLE_WIDTH_M, VEHICLE_WIDTH_M)
    if met is None:
        return None
    zone = met[1]
    my_time = _occupancy(mine, zone.buffer(CAR_LENGTH_M / 2))
    reach = _along(b, zone.buffer(CAR_LENGTH_M / 2))
    where, _ = position_at(theirs, onset)
    speed, _ = speed_at(theirs, onset)
    if my_time is None or my_time.entered is None or reach is None or where is None or speed is None:
        return None
    here = b.project(Point(where))
    if not reach[0] <= here <= reach[1]:
        return None                         # short of the zone (the projected gap's), or past it
    if speed <= 0.1:
        return -math.inf
    return (my_time.entered - onset) / SECOND - (reach[1] - here) / speed


def _drac(distance: float, speed: float, within_s: float) -> float:
    """The steady deceleration that takes a road user `distance` metres from the zone at `speed`
    there no sooner than `within_s` seconds from now: to cover exactly the distance in that time,
    or, where that would need stopping on the way, to stop short of it."""
    if within_s <= 0 or speed * within_s <= distance:
        return 0.0
    needed = 2 * (speed * within_s - distance) / (within_s * within_s)
    if speed - needed * within_s < 0:
        return speed * speed / (2 * distance)
    return needed
