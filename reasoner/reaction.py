"""Whether a road user's braking can have been a reaction to the vehicle that passed.

Para 1 of TSRGD 2016 Sch 9 Pt 7 (and HC 170-172) asks whether the vehicle caused another driver
"to change its speed or course in order to avoid an accident". A road user that braked while the
vehicle passed did not always brake for it. derived.explained looks for causes of the road user's
own (its light, its Stop line, a road user it followed, a path that never met the vehicle's); this
module answers two questions about time and place:

- Had the vehicle been out of the road user's way for longer than a perception-reaction time when
  the road user began to slow (`reacted_after_clearing`)? A main-road car that slows for its own
  right turn 3 s after a Stop-line vehicle crossed its lane did not slow for that vehicle.
- Was the vehicle, all the while it was in the road user's way from a reaction time before the
  slowing began, ahead of it, going its way, and far enough ahead that the road user could keep the
  two-second gap behind it with gentle braking (`well_ahead`)? A vehicle already 50 m down the lane
  a main-road car turns into is not what that car braked hard for.

Neither answers "yes" on missing measurements: where the record cannot tell, the braking stays
the vehicle's to explain, as before.
"""
from __future__ import annotations

import math
from dataclasses import replace
from typing import NamedTuple, Protocol, Sequence, cast

from .history import Junction
from .history import MIN_DECEL_SPAN_S, Sample, position_at, speed_at, xy
from .history import FOLLOW_M, FOLLOW_S, MOVING_MPS, VEHICLE_WIDTH_M, project, since, through
from .history import Other

SECOND = 1_000_000_000
FORCE_DECEL_MPS2 = 2.0  # Hupfer (1997), as cited by the criticality-metrics catalogue: below 2 m/s² a driver's
                        # reaction is adaptation or ordinary reaction, from 2 m/s² a "considerable reaction"
REACTION_TIME_S = 2.5   # AASHTO Green Book (2018) 3.2.2.1: the brake reaction time for stopping sight distance,
                        # above the 90th percentile of drivers' reaction times, surprise included
SPEED_NOISE_MPS = 0.5   # a road user still within this of its top speed has not yet begun to slow (1 mph)
SAME_WAY_DEG = 45.0     # a vehicle heading within this of the way's direction goes that way (not across it)
                        # (and one leaving a junction more than this off the way it came in by turned there)
_SAME_WAY = math.cos(math.radians(SAME_WAY_DEG))

Point = tuple[float, float]


class _Placed(Protocol):
    """A Sample whose position is measured (Sample.placed): x and y are floats. The lists of
    placed samples below are typed so (typing.cast: the filter on `placed` is what makes them so)."""

    @property
    def t(self) -> int: ...
    @property
    def x(self) -> float: ...
    @property
    def y(self) -> float: ...
    @property
    def speed_mps(self) -> float | None: ...
    @property
    def heading_deg(self) -> float | None: ...


class _HasSpeed(Protocol):
    """A Sample whose speed is measured (speed_mps not None)."""

    @property
    def t(self) -> int: ...
    @property
    def speed_mps(self) -> float: ...


def slowing_began(other: Other) -> int | None:
    """When the road user began the slowing that ended in its hardest braking or its stop: the last
    of its samples up to that moment still within SPEED_NOISE_MPS of the fastest it went before it.
    Braking is measured over its hardest second or more (motion.peak_deceleration); the driver's
    reaction began where the slowing did, which may be earlier, but no earlier than the reaction is
    counted from (`counted_from`: a stop apart from an earlier braking, others.stop_apart)."""
    marks = [m.t for m in (other.braking.first if other.braking else None, other.stopped) if m is not None]
    if not marks:
        return None
    until = min(marks)
    since = other.counted_from
    speeds = cast("list[_HasSpeed]", [s for s in other.samples
                                      if s.speed_mps is not None and s.t <= until and (since is None or s.t >= since)])
    if not speeds:
        return until
    top = max(s.speed_mps for s in speeds)
    return max(s.t for s in speeds if s.speed_mps >= top - SPEED_NOISE_MPS)


def stop_apart(other: Other, everyone: Sequence[Other], junction: Junction) -> Other | None:
    """The road user's stop as a reaction of its own: where, after its hardest braking and before
    it stopped, it went on at a steady speed (within SPEED_NOISE_MPS, moving at others.MOVING_MPS
    or more) for MIN_DECEL_SPAN_S or longer, a second in which it did not slow by the measure
    braking is taken over at all (motion.peak_deceleration), the stop that followed was a second
    braking, begun from that steady speed: the stop alone, counted from the start of that stretch
    (others.since; `counted_from`: its slowing is looked for there, its leader and its own line
    at the stop). None where the road user did not both brake and stop, or went on at no such steady
    speed between. The town run's 225 braked from 16.6 to 2.4 m/s behind 424, standing to turn
    in j11, crept on at 2.5 m/s for 2.4 s once 424 had gone and then stopped as 125 came across
    its way (SUMO's account: foe 125); taken as one slowing from 16.6 m/s, the stop was put down
    to 424."""
    b, stop = other.braking, other.stopped
    if b is None or stop is None or stop.t <= b.last.t:
        return None
    speeds = cast("list[_HasSpeed]", [s for s in other.samples
                                      if s.speed_mps is not None and b.last.t <= s.t < stop.t])
    begins: int | None = None
    first = 0
    for last, s in enumerate(speeds):
        if s.speed_mps < MOVING_MPS:
            first = last + 1
            continue
        while max(x.speed_mps for x in speeds[first:last + 1]) - min(x.speed_mps for x in speeds[first:last + 1]) \
                > SPEED_NOISE_MPS:
            first += 1
        if s.t - speeds[first].t >= MIN_DECEL_SPAN_S * SECOND:
            begins = speeds[first].t
    if begins is None:
        return None
    apart = since(other, everyone, junction, begins, stop_only=True)
    return replace(apart, counted_from=begins) if apart.stopped is not None else None


def braked_afresh(other: Other, set_off: int) -> Other | None:
    """The road user's braking as a change of speed of its own, begun after the vehicle set off from
    its standstill before its line (`set_off`), where it was already slowing before then: its
    braking counted from the set-off (others.since) began after it, and was harder, by
    FORCE_DECEL_MPS2 or more, than the slowing in the MIN_DECEL_SPAN_S before it began (Hupfer's
    considerable reaction, as a rise in deceleration: the driver braked anew, not on). Counted from
    the set-off (`counted_from`: its slowing is looked for there, reaction.slowing_began), so that
    the road user is taken at the speed and place it had when the vehicle's act began. None where
    the braking is the tail of one begun before (no such rise), or began before the set-off, or
    the record cannot tell. The paper run's 205 slowed at 4.5 m/s² for 279 crawling out of j2, eased
    to 2 m/s² from 324.5 s, and braked at 5.5 m/s² from 325.3 s, 0.3 s after 253 set off from its
    Give Way line (SUMO's account: foe 253, 8.7 m/s² from 325.4 s); the paper run's 187 braked at
    4.5 m/s² from 224.0 s to a stop at 226.6 s through 204's set-off at 226.0 s: one braking."""
    b = other.braking
    if b is None or b.first.t < set_off or b.first.speed_mps is None:
        return None
    began = slowing_began(other)
    if began is None or began >= set_off:
        return None                     # no slowing before the set-off to tell it apart from
    span = int(MIN_DECEL_SPAN_S * SECOND)
    before, _ = speed_at(other.samples, b.first.t - span)
    if before is None:
        return None
    prior = (before - b.first.speed_mps) / MIN_DECEL_SPAN_S
    if b.decel_mps2 - prior < FORCE_DECEL_MPS2:
        return None
    return replace(other, counted_from=set_off)


def cleared_at(mine: Sequence[Sample], theirs: Sequence[Sample], distance: float = VEHICLE_WIDTH_M) -> int | None:
    """When the vehicle was first seen `distance` or more from the other's way, after it was last
    within that distance of it: the moment it was out of the other's way. None when it never came
    that close, or was still that close at its last position in the record (it may not have left)."""
    way = _Way.of(theirs, distance)
    placed = cast("list[_Placed]", [s for s in mine if s.placed])
    if len(way.points) < 2:
        return None
    for i in range(len(placed) - 1, -1, -1):      # from the end: the last time it was near
        if way.hit((placed[i].x, placed[i].y)) is not None:
            return placed[i + 1].t if i + 1 < len(placed) else None
    return None


def reacted_after_clearing(mine: Sequence[Sample], other: Other) -> bool:
    """Whether the road user began to slow more than REACTION_TIME_S after the vehicle was out of
    its way (`cleared_at`: within VEHICLE_WIDTH_M of any point of its way through and beyond the
    junction): too late to be a reaction to the vehicle, gone from where the two could meet. One
    that merges into the lane ahead of it stays in its way and is never cleared (`well_ahead`)."""
    began = slowing_began(other)
    clear = cleared_at(mine, other.way)
    return began is not None and clear is not None and began - clear > REACTION_TIME_S * SECOND


def well_ahead(mine: Sequence[Sample], other: Other) -> bool:
    """Whether the vehicle, at each of its positions in the road user's way from REACTION_TIME_S
    before the road user began to slow, was ahead of it along that way, heading its way, and so far
    ahead that the road user could keep the two-second gap behind it (HC 126: FOLLOW_S, plus
    FOLLOW_M of a car's length) by braking at less than FORCE_DECEL_MPS2 (`needed_deceleration`),
    with at least one such position (the vehicle's record may end before the slowing began: it
    was then moving away down that way). Such a road user braked hard for something else (a turn
    of its own, oncoming traffic it gives way to)."""
    began = slowing_began(other)
    way = _Way.of(other.way, VEHICLE_WIDTH_M)
    if began is None or len(way.points) < 2:
        return False
    placed = cast("list[_Placed]", [s for s in mine if s.placed])
    seen = False
    for i, s in enumerate(placed):
        if s.t < began - REACTION_TIME_S * SECOND:
            continue
        hit = way.hit((s.x, s.y))
        if hit is None:
            continue
        if not _ahead_and_clear(placed, i, hit, way, other, began):
            return False
        seen = True
    return seen


def needed_deceleration(speed: float, ahead_speed: float, gap: float) -> float:
    """The steady deceleration that takes a road user at `speed` down to the speed of the one
    `gap` metres ahead of it before it is closer than the two-second rule's gap (FOLLOW_M +
    FOLLOW_S × that speed); infinite when it is already that close."""
    room = gap - FOLLOW_M - FOLLOW_S * max(ahead_speed, 0.0)
    if room <= 0:
        return math.inf
    closing = speed - ahead_speed
    return 0.0 if closing <= 0 else closing * closing / (2 * room)


class _Hit(NamedTuple):
    along_m: float          # how far along the way the nearest point is
    direction: Point        # the way's direction there (a unit vector)

    def goes_along(self, heading: Point | None) -> bool:
        """Whether a road user heading so (a unit vector) goes the way's way here: within
        SAME_WAY_DEG of its direction."""
        return heading is not None and \
            heading[0] * self.direction[0] + heading[1] * self.direction[1] >= _SAME_WAY


def _way(samples: Sequence[Sample]) -> list[Point]:
    return cast("list[Point]", [(s.x, s.y) for s in samples if s.placed])


class _Way:
    """A way (the placed positions of a road user's samples, a polyline) to measure points against
    within `distance`: `hit(point)` is the nearest point of the way within `distance` of the
    point, as measuring every segment in the way's order finds it (tests/reasoner/test_way_grid.py
    holds it to that, to the bit). Each
    segment's box, widened by `distance`, is worked out once, and a grid of GRID_M cells lists the
    segments whose widened box meets each cell (in the way's order): a point within a box lies in
    one of the cells it meets, so only the segments listed in the point's cell can hold it, and
    they are measured in the way's order with the same arithmetic. A vehicle's passage is
    measured against a road user's way point by point: hundreds of points, hundreds of segments."""

    GRID_M = 8.0
    MAX_CELLS = 64          # a segment meeting more cells (a jump in the record) is measured for every point

    def __init__(self, points: list[Point], distance: float) -> None:
        self.points = points
        self._segments: list[tuple[float, float, float, float, Point, Point, float, float]] = []
        self._cells: dict[tuple[int, int], list[int]] = {}
        self._wide: list[int] = []
        along = 0.0
        for i, (r, s) in enumerate(zip(points, points[1:])):
            length = math.dist(r, s)
            box = (min(r[0], s[0]) - distance, max(r[0], s[0]) + distance,
                   min(r[1], s[1]) - distance, max(r[1], s[1]) + distance)
            self._segments.append((*box, r, s, length, along))
            along += length
            low, high = self._cell(box[0], box[2]), self._cell(box[1], box[3])
            if low is None or high is None or (high[0] - low[0] + 1) * (high[1] - low[1] + 1) > self.MAX_CELLS:
                self._wide.append(i)
                continue
            (x0, y0), (x1, y1) = low, high
            for cx in range(x0, x1 + 1):
                for cy in range(y0, y1 + 1):
                    self._cells.setdefault((cx, cy), []).append(i)
        self._distance = distance

    @classmethod
    def of(cls, samples: Sequence[Sample], distance: float) -> _Way:
        return cls(_way(samples), distance)

    def _cell(self, x: float, y: float) -> tuple[int, int] | None:
        if not (math.isfinite(x) and math.isfinite(y)):
            return None
        return math.floor(x / self.GRID_M), math.floor(y / self.GRID_M)

    def hit(self, point: Point) -> _Hit | None:
        """The nearest point of the way within the distance of `point`, or None."""
        x, y = point
        cell = self._cell(x, y)
        if cell is None:        # not a finite position: every segment is measured
            candidates: Sequence[int] = range(len(self._segments))
        else:
            listed = self._cells.get(cell, [])
            candidates = sorted(listed + self._wide) if self._wide else listed
        best: tuple[float, float, Point] | None = None
        for i in candidates:
            x0, x1, y0, y1, r, s, length, along = self._segments[i]
            if x0 < x < x1 and y0 < y < y1:
                gap, f = project(point, r, s)
                if gap < self._distance and (best is None or gap < best[0]):
                    unit = ((s[0] - r[0]) / length, (s[1] - r[1]) / length) if length else (0.0, 0.0)
                    best = (gap, along + f * length, unit)
        return None if best is None else _Hit(best[1], best[2])


def _ahead_and_clear(placed: Sequence[_Placed], i: int, hit: _Hit, way: _Way, other: Other,
                     began: int) -> bool:
    """Whether the vehicle at placed[i] is ahead of the road user along its way, heading its way,
    with room enough (`needed_deceleration` below FORCE_DECEL_MPS2). The road user is taken as it
    was when it began to slow and, later than that, as if it had gone on unslowed: slowed down,
    it would be further back and slower, and its own braking would make the room it needed."""
    s = placed[i]
    when = min(s.t, began)
    where, _ = position_at(other.way, when)
    speed, _ = speed_at(other.way, when)
    heading = _heading(placed, i)
    if where is None or speed is None or heading is None or s.speed_mps is None:
        return False
    own = way.hit(where)
    if own is None:
        return False
    gap = hit.along_m - own.along_m - speed * max(0, s.t - began) / SECOND
    along = heading[0] * hit.direction[0] + heading[1] * hit.direction[1]
    if gap <= 0 or not hit.goes_along(heading):
        return False
    return needed_deceleration(speed, s.speed_mps * along, gap) < FORCE_DECEL_MPS2


def _heading(placed: Sequence[_Placed], i: int) -> Point | None:
    """The vehicle's direction of travel at placed[i] (a unit vector): from its heading where it
    states one, else from its positions on either side."""
    s = placed[i]
    if s.heading_deg is not None:
        angle = math.radians(s.heading_deg)
        return math.cos(angle), math.sin(angle)
    a, b = placed[max(i - 1, 0)], placed[min(i + 1, len(placed) - 1)]
    length = math.dist((a.x, a.y), (b.x, b.y))
    return None if length < 0.1 else ((b.x - a.x) / length, (b.y - a.y) / length)


def turn_deg(inside: Sequence[Point]) -> float | None:
    """How far the road user's direction turned through the junction, in degrees (0 to 180): from
    its way in (the first step of `inside`, others.through's positions in the junction's area with
    the one before and after) to its way out (the last step). None where the record shows no way
    both in and out of the area."""
    steps = [(b[0] - a[0], b[1] - a[1]) for a, b in zip(inside, inside[1:]) if math.dist(a, b) > 0.05]
    if len(steps) < 2:
        return None
    (ax, ay), (bx, by) = steps[0], steps[-1]
    turn = abs(math.degrees(math.atan2(by, bx) - math.atan2(ay, ax))) % 360
    return min(turn, 360 - turn)


def turn_seen(series: Sequence[Sample], junction: Junction) -> float | None:
    """How far the road user is seen to turn through the junction (`turn_deg`): over its positions
    in the junction's area with the one before and after (others.through), or, where its record
    begins inside the area (a road user read from a moment it was already there), from its first
    position there to the one after it left: the turn it is seen making, never more than it
    made. None where the record shows it neither leave the area nor two steps in it."""
    seen = through(series, junction)
    if seen:
        return turn_deg(seen)
    placed = cast("list[Point]", [(s.x, s.y) for s in series if s.placed])
    inside = [i for i, (x, y) in enumerate(placed) if junction.edge(x, y) <= 0]
    if not inside or inside[0] != 0 or inside[-1] == len(placed) - 1:
        return None
    return turn_deg(placed[:inside[-1] + 2])


class Turn(NamedTuple):
    """The speed a road user took its turn at, from its own record, and when."""

    speed_mps: float        # its own stated speed there, else the distance from its last position over the time
    t: int                  # the sample's (ns)


def turn_taken(other: Other, junction: Junction) -> Turn | None:
    """The slowest the road user went through the junction's area from when it began to slow
    (`slowing_began`), from its own record: at each of its placed samples in the area (within the
    junction's edge), its own speed there, or, where its record states none, the distance from
    its position before over the time between (a chord across a bend is shorter than the way, so
    that reading is low, never high), where it went no slower than that, less SPEED_NOISE_MPS,
    anywhere from its onset until it left the area: its slowing went down to the speed it took its
    turn at, and no lower. None where it slowed further before the junction, or the record cannot
    tell (no onset, no positions in the area, the area never left)."""
    began = slowing_began(other)
    placed = cast("list[_Placed]", [s for s in other.way if s.placed and began is not None and s.t >= began])
    speeds = [(b.speed_mps if b.speed_mps is not None else math.dist((a.x, a.y), (b.x, b.y)) * SECOND / (b.t - a.t), b)
              for a, b in zip(placed, placed[1:]) if b.t > a.t]
    inside = [(v, b) for v, b in speeds if junction.edge(b.x, b.y) <= 0]
    if not inside or junction.edge(placed[-1].x, placed[-1].y) <= 0:
        return None
    left = max(b.t for _, b in inside)
    speed, at = min(inside, key=lambda step: step[0])
    if min(v for v, b in speeds if b.t <= left) < speed - SPEED_NOISE_MPS:
        return None
    return Turn(speed, at.t)


def behind_at_turn(mine: Sequence[Sample], other: Other, turn: Turn) -> bool:
    """Whether the road user, taken from where it was when it began to slow on along its way at
    the speed it took its turn at (`turn_taken`), would have kept HC 126's gap behind the vehicle as the
    vehicle went on down that way: at each of the vehicle's positions on its way (within
    VEHICLE_WIDTH_M), heading its way (within SAME_WAY_DEG), from that moment until the road
    user's record ends, the vehicle was FOLLOW_M + FOLLOW_S × that speed or more ahead of it (the
    two-second gap at the road user's own speed, HC 126: "the time it would take to reach where
    that vehicle is", a car's length and a queue's gap besides), with at least one such position;
    and the speed was below the slowest the vehicle went from then until the road user took its
    turn by as much as a change of speed counts from (FORCE_DECEL_MPS2 over MIN_DECEL_SPAN_S):
    the vehicle was pulling away, and did not set the road user's pace. A road user that must slow
    for its own turn anyway, and at the speed it took it comes in behind the vehicle with the gap
    kept, had no accident with the vehicle to avoid (TSRGD 2016 Sch 9 Pt 7 para 1) whatever it
    would have met at a speed no turn is taken at. The paper run's 228 (from the west, right into
    j2's south arm behind 116 out of the north Stop arm) slowed from 13.03 to 6.28 m/s and took its
    turn at that, 116 going on at 9.6 to 13.4 m/s, 28.8 m ahead when 228 began to slow (20.6 m
    keeps two seconds at 6.28 m/s). False where the record cannot tell."""
    began = slowing_began(other)
    way = _Way.of(other.way, VEHICLE_WIDTH_M)
    here, _ = position_at(other.way, began) if began is not None else (None, ())
    own = way.hit(here) if here is not None and len(way.points) >= 2 else None
    if began is None or own is None:
        return False
    paced = [s.speed_mps for s in mine if s.speed_mps is not None and began <= s.t <= turn.t]
    if not paced or turn.speed_mps > min(paced) - FORCE_DECEL_MPS2 * MIN_DECEL_SPAN_S:
        return False
    end = max(s.t for s in other.way)
    kept = FOLLOW_M + FOLLOW_S * turn.speed_mps
    placed = cast("list[_Placed]", [s for s in mine if s.placed])
    seen = False
    for i, s in enumerate(placed):
        if s.t < began or s.t > end:
            continue
        hit = way.hit((s.x, s.y))
        heading = _heading(placed, i)
        if hit is None or not hit.goes_along(heading):
            continue
        if hit.along_m - own.along_m - turn.speed_mps * (s.t - began) / SECOND < kept:
            return False
        seen = True
    return seen
