"""The other road users near the conflict point while a vehicle passed, and how they moved.

The conflict point is the junction's centre, where the paths of its approaches cross. A road user
counts as near when it came within CONFLICT_M of it in the window read; one following the vehicle
on its own approach is left out (it does not cross its path). For each: the arm it was first seen
on and whether it was closing on the centre, whether that arm is the major road, the hardest it braked while the vehicle passed (its speed
series, averaged over at least a second: motion.peak_deceleration), whether it came to a stop, and
what its own signal showed then (braking for one's own red light is not being forced by another; a
stop counts only on the way into the junction: `since` recounts both from a later moment)
or whether a Stop line of its own was ahead of it (stopping there is its own duty, HC 171),
and whether a road user ahead of it on its arm explains its braking (following a slower or stopped
vehicle within FOLLOW_S of headway is not being forced by the vehicle that passed).
"""
from __future__ import annotations

from dataclasses import replace
from typing import Callable, Mapping, Sequence

from .junctions import Junction, heading_sector, sector
from .motion import STOPPED_MPS, Braking, Sample, peak_deceleration, position_at, speed_at, xy
from .passage_values import Other
from .record import Track
from .signals import Signals, shown

CONFLICT_M = 50.0      # 30 mph covers 50 m in under 4 s, and a car needs 23 m to stop from it (HC 126)
MOVING_MPS = 2.0       # "came to a stop" needs it moving at least this fast first (4.5 mph)
MAX_OTHERS = 64        # the nearest this many; a crowd beyond that adds nothing to a judgement
FOLLOW_S = 2.0         # headway of the two-second rule (HC 126): a road user this close behind another follows it
FOLLOW_M = 8.0         # ... plus a car's length and the gap of a queue (a stopped one behind a stopped one)


def near_and_same_approach(tracks: Mapping[str, Track], junction: Junction, vehicle: str, approach: str | None,
                       t_from: int, t_to: int, passing: tuple[int, int], signals: Signals,
                       walking: Callable[[str], bool] | None = None) -> tuple[tuple[Other, ...], tuple[Other, ...]]:
    """`near_users`, and those it leaves out as on the vehicle's own approach, going its way
    (behind it, or ahead of it in the same queue): they do not cross the vehicle's path, but may
    cross a main-road car's just before or after it (another emerger out of the same line), and
    that car's braking may have been for them (reasoner/attribution.py weighs them; nothing else
    reads them)."""
    found: list[Other] = []
    following: list[Other] = []
    for user, (src, series) in tracks.items():
        if user == vehicle:
            continue
        window = tuple(s for s in series if t_from <= s.t <= t_to)
        placed = [s for s in window if s.placed]
        if not placed:
            continue
        closest = min(junction.distance(*xy(s)) for s in placed)
        if closest > CONFLICT_M:
            continue
        arm, closing = _arm(junction, placed)
        behind = arm is not None and arm == approach and closing and not src.startswith("pedestrian/") \
            and not (walking and walking(user))
        (following if behind else found).append(_other(user, src, window, junction, arm, closing, closest, passing,
                                                       signals))
    found = [_followed(o, found, junction) for o in found]
    found.sort(key=lambda o: (o.closest_m, o.user))
    following.sort(key=lambda o: (o.closest_m, o.user))
    return tuple(found[:MAX_OTHERS]), tuple(following[:MAX_OTHERS])


def _arm(junction: Junction, placed: list[Sample]) -> tuple[str | None, bool]:
    """The arm a road user was first seen on (its position's sector, outside the junction; else
    where its heading says it came from), and whether it was then closing on the centre."""
    x, y = xy(placed[0])
    if junction.edge(x, y) > 0:
        return sector(x - junction.x, y - junction.y), len(placed) > 1 and _closing(junction, placed)
    heading = next((s.heading_deg for s in placed if s.heading_deg is not None), None)
    return (heading_sector(heading) if heading is not None else None), False


def _closing(junction: Junction, placed: list[Sample]) -> bool:
    return min(junction.distance(*xy(s)) for s in placed) < junction.distance(*xy(placed[0])) - 0.5


def _other(user: str, src: str, window: tuple[Sample, ...], junction: Junction, arm: str | None, closing: bool,
           closest: float, passing: tuple[int, int], signals: Signals) -> Other:
    braking = braking_into(window, junction, passing)
    stopped = _stopped(window, junction, passing)
    timeline = signals.timeline(junction.id, arm) if arm else ()
    moment = stopped.t if stopped is not None else braking.first.t if braking is not None else None
    light = shown(timeline, moment) if moment is not None and timeline else None
    return Other(user, src, window, arm, closing, junction.is_major(arm), closest, braking, stopped, light,
                 own_stop_line=_before_own_stop_line(junction, arm, window, moment))


OWN_LINES = ("stop", "give_way")     # controls whose line on its own arm explains a road user's braking to it


def _before_own_stop_line(junction: Junction, arm: str | None, window: tuple[Sample, ...], moment: int | None) -> bool:
    """Whether the road user braked or stopped before a Stop or Give Way line on its own arm: a
    Stop line makes it stop whoever passes (HC 171), a Give Way line makes it slow to give way to
    the major road's traffic whoever else passes (HC 172); braking to its own line is its own
    control (issue 35's "Attribution": its own signal, Stop or Give Way line), not a change of
    speed the vehicle passing caused: the vehicle crosses the junction beyond that line, never
    the road user's arm before it. SUMO's account names such a braking's cause "line"."""
    line = junction.line_for(arm) if arm is not None else None
    if line is None or moment is None or junction.control_from(arm) not in OWN_LINES:
        return False
    here, _ = position_at(window, moment)
    return here is not None and line.to_line(*here) >= -1.0


def _followed(other: Other, everyone: list[Other], junction: Junction) -> Other:
    """The road user with, where one explains its braking or stop, the one it followed: ahead of
    it on the same arm, heading for the centre or standing, no faster, within FOLLOW_S of headway
    when it began to brake (or stopped, without braking measured)."""
    moment = other.braking.first.t if other.braking is not None else other.stopped.t if other.stopped else None
    if moment is None or other.arm is None:
        return other
    here, _ = position_at(other.samples, moment)
    speed, _ = speed_at(other.samples, moment)
    if here is None or speed is None:
        return other
    mine = junction.distance(*here)
    for ahead in everyone:
        if ahead.user == other.user or ahead.type == "pedestrian" or ahead.src.startswith("pedestrian/"):
            continue            # a pedestrian on the footway leads nobody in the lane
        there, _ = position_at(ahead.samples, moment)
        its, _ = speed_at(ahead.samples, moment)
        if there is None or its is None or sector(there[0] - junction.x, there[1] - junction.y) != other.arm:
            continue
        gap = mine - junction.distance(*there)
        earlier, _ = position_at(ahead.samples, moment - 500_000_000)
        heading_in = its <= STOPPED_MPS or (earlier is not None and junction.distance(*earlier) > junction.distance(*there))
        if 0 < gap <= FOLLOW_M + FOLLOW_S * speed and its <= speed and heading_in:
            return replace(other, followed=ahead.user)
    return other


def braking_into(window: tuple[Sample, ...], junction: Junction, passing: tuple[int, int]) -> Braking | None:
    """The hardest braking while the vehicle passed, counted only while the road user was
    still outside the junction and heading into it."""
    before = tuple(s for s in window if not s.placed or junction.edge(*xy(s)) > 0)
    braking = peak_deceleration(before, *passing)
    if braking is None or braking.decel_mps2 <= 0:
        return None
    a, b = braking.first, braking.last
    if a.placed and b.placed and junction.distance(*xy(b)) > junction.distance(*xy(a)) + 0.5:
        return None    # moving away from the centre: not braking for the junction
    return braking


def _stopped(window: tuple[Sample, ...], junction: Junction, passing: tuple[int, int],
             moving_from: int | None = None) -> Sample | None:
    """The sample at which the road user came to a stop while the vehicle passed, having been
    moving at MOVING_MPS or more before it (in the window, or from `moving_from` on), on its way
    into the junction: closer to its centre than when it was last moving. A road
    user that stops on its way out of the junction, beyond the vehicle, stops for what lies ahead
    of it, not for the vehicle behind it."""
    last_moving: Sample | None = None
    for s in window:
        if s.speed_mps is None or s.t > passing[1]:
            continue
        if s.speed_mps >= MOVING_MPS and (moving_from is None or s.t >= moving_from):
            last_moving = s
        elif last_moving is not None and s.speed_mps <= STOPPED_MPS and s.t >= passing[0]:
            if _heading_in(junction, last_moving, s):
                return s
            last_moving = None
    return None


def _heading_in(junction: Junction, moving: Sample, stop: Sample) -> bool:
    """Whether a road user stopped nearer the junction's centre than it was while last moving
    (unplaced samples cannot tell: taken as heading in, as before positions were looked at)."""
    if not (moving.placed and stop.placed):
        return True
    return junction.distance(*xy(stop)) < junction.distance(*xy(moving))


def since(other: Other, everyone: Sequence[Other], junction: Junction, t_from: int, *, stop_only: bool = False) -> Other:
    """The road user with its braking and its stop counted only from `t_from`: the moment the
    vehicle set off from a standstill before its line. Until then the vehicle stood where the law
    asks it to wait, so a road user slowing before then was slowing for something else; a stop
    counts only if it was still moving at MOVING_MPS or more once the vehicle set off. What
    explains the reaction (a Stop line of its own, one it followed) is looked for again at its
    new moment; its own light stays as found (the signals are not at hand here). `stop_only`: its
    stop alone, with no braking (reaction.stop_apart: a stop after a steady stretch from `t_from`)."""
    end = max((s.t for s in other.samples), default=t_from)
    passing = (t_from, end)
    braking = None if stop_only else braking_into(other.samples, junction, passing)
    stopped = _stopped(other.samples, junction, passing, moving_from=t_from)
    moment = stopped.t if stopped is not None else braking.first.t if braking is not None else None
    recounted = replace(other, braking=braking, stopped=stopped, followed=None,
                        own_stop_line=_before_own_stop_line(junction, other.arm, other.samples, moment))
    return _followed(recounted, list(everyone), junction)


def own_cause(other: Other) -> bool:
    """Whether a cause of the road user's own explains its braking or stop: a red or amber light of
    its own, a Stop or Give Way line of its own, a road user it followed."""
    return (other.light is not None and other.light.colour != "green") or other.followed is not None \
        or other.own_stop_line


VEHICLE_WIDTH_M = 2.55  # the widest a vehicle may be (Road Vehicles (Construction and Use) Regulations 1986 reg. 8)


def paths_within(mine: Sequence[Sample], theirs: Sequence[Sample], junction: Junction,
                 distance: float) -> bool | None:
    """Whether two road users' paths through the junction came closer than `distance`, wherever
    each was when (the polylines of their positions inside the junction's area, with the sample
    before and after it); None when either path, in and out, is not in the record. Paths whose
    centre lines stay VEHICLE_WIDTH_M or more apart cannot both be occupied at once: a road user
    on such a path (a main-road car turning left into the arm the vehicle leaves) has no conflict
    point with the vehicle, and slows for its own manoeuvre, not to avoid it."""
    a, b = through(mine, junction), through(theirs, junction)
    if len(a) < 2 or len(b) < 2:
        return None
    return polylines_within(a, b, distance)


def polylines_within(a: Sequence[tuple[float, float]], b: Sequence[tuple[float, float]], distance: float) -> bool:
    """Whether some segment of polyline a comes closer than `distance` to some segment of b.

    Pairs of segments whose bounding boxes are `distance` or more apart along either axis cannot
    come that close and are not measured: at 10 Hz two paths through a junction are a few thousand
    pairs, and most are metres apart."""
    boxes = [(min(r[0], s[0]) - distance, max(r[0], s[0]) + distance,
              min(r[1], s[1]) - distance, max(r[1], s[1]) + distance, r, s) for r, s in zip(b, b[1:])]
    for p, q in zip(a, a[1:]):
        x0, x1, y0, y1 = min(p[0], q[0]), max(p[0], q[0]), min(p[1], q[1]), max(p[1], q[1])
        for bx0, bx1, by0, by1, r, s in boxes:
            if x1 <= bx0 or x0 >= bx1 or y1 <= by0 or y0 >= by1:
                continue
            if _segment_gap(p, q, r, s) < distance:
                return True
    return False


def through(series: Sequence[Sample], junction: Junction) -> list[tuple[float, float]]:
    """The positions inside the junction's area, with the one just before and just after; none
    unless the record shows the road user both come into the area and leave it: a path cut
    short (one that stopped in the junction, or whose record ends there) is not its path."""
    placed = [xy(s) for s in series if s.placed]
    inside = [i for i, (x, y) in enumerate(placed) if junction.edge(x, y) <= 0]
    if not inside or inside[0] == 0 or inside[-1] == len(placed) - 1:
        return []
    return placed[inside[0] - 1:inside[-1] + 2]


def _segment_gap(p, q, r, s) -> float:
    """The smallest distance between segments pq and rs (0 when they cross)."""
    if _cross(p, q, r, s):
        return 0.0
    return min(point_gap(p, r, s), point_gap(q, r, s), point_gap(r, p, q), point_gap(s, p, q))


def _cross(p, q, r, s) -> bool:
    def side(a, b, c) -> float:
        return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    d1, d2, d3, d4 = side(r, s, p), side(r, s, q), side(p, q, r), side(p, q, s)
    return ((d1 > 0) != (d2 > 0)) and ((d3 > 0) != (d4 > 0)) and 0 not in (d1, d2, d3, d4)


def point_gap(p, a, b) -> float:
    """The distance from point p to segment ab."""
    return project(p, a, b)[0]


def project(p, a, b) -> tuple[float, float]:
    """The distance from point p to segment ab, and how far along ab (0 to 1) its nearest point is."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = dx * dx + dy * dy
    f = 0.0 if length == 0 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length))
    return ((p[0] - a[0] - f * dx) ** 2 + (p[1] - a[1] - f * dy) ** 2) ** 0.5, f
