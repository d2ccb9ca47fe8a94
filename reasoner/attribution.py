"""Which road user a braking was for, when more than the vehicle V was about (issue 35).

Para 1 of TSRGD 2016 Sch 9 Pt 7 (and HC 170-172, Sch 14 Pt 1 para 5(5)) asks whether V caused
another driver "to change its speed or course in order to avoid an accident". A road user U that
braked while V passed may have been resolving another conflict than V's. Traffic-conflict
analysis attributes an evasive action to the conflict it resolved (Hydén 1987, the Swedish
Traffic Conflict Technique: the time to accident is measured to the road user the action was
taken for); this module finds, from the measured paths alone, a road user other than V that
explains U's braking:

- `leader`: a road user ahead of U on U's own way when U began to slow, going U's way (or
  standing), no faster than U, so close that U could keep the two-second rule's gap behind it
  (HC 126: FOLLOW_S, plus FOLLOW_M of a car's length) only by braking at FORCE_DECEL_MPS2 or
  harder (reaction.needed_deceleration: within that gap already, or closing fast on it); or one
  at its speed (within SPEED_NOISE_MPS) within that gap that was slowing with it. U was
  slowing behind its leader (a queue, one standing in its way, or one that had joined its lane
  ahead of it), whatever lane that leader came from; others.py's `followed` looks on U's own arm
  only, at its hardest braking. This is reaction.well_ahead's yardstick turned round: V ahead of
  U with room to spare is not what U braked hard for; a leader with none is. Keeping that gap
  takes U down to the leader's speed and no lower: a U not yet within the gap whose slowing went
  on below the slowest its leader went, by as much as a change of speed counts from, the leader
  then beyond the gap (`_slowed_below`), was slowing for something else.
- `nearer_conflict`: a road user W whose path crosses U's where, had U kept the speed it had
  when it began to slow, U would have come within PET_MAX_S of W (W's projected gap: the
  post-encroachment time U would have had with W), and whose conflict comes before V's in one
  order (`ahead_of`): a collision course (unslowed, in the zone together) before a near miss;
  then the zone U would have reached first on its way (the driver resolves the first conflict on
  its way); at one place, the smaller gap (the more severe conflict, as SUMO names the constraint
  allowing the lowest speed). Or any such W where V's path never meets U's. Where both are
  collision courses (`both_collisions`: unslowed, U would have been in each zone with its road
  user) and V had proceeded when U began to slow, or did within a perception-reaction time
  after (`proceeding`), each on its own asked the braking, and neither excuses the other. W may be one of the
  road users on V's own approach (`Passage.same_approach`): a main-road car braking for a second
  emerger out of the same line.
- `came_between`: one emerger cutting in between U and another ahead of it on its way is the
  vehicle in front of U from then on (HC 126): U could reach the farther only behind the nearer.
  Two collision courses keep V named only where W did not come in between U and V; a road user
  ahead is not U's leader where V, on a collision course with U, came in between.

Neither answers on missing measurements: where the record cannot tell (no onset, no path, V's
zone's distance unknown), the braking stays V's to explain, as before. V itself is never among
`p.others` (others.near_users leaves it out), so V joining U's lane ahead of it is judged as V's
act (reaction.well_ahead), never as a leader of U's own.
"""
from __future__ import annotations

import math
from typing import Sequence, cast

from .conflicts import CAR_LENGTH_M, PET_MAX_S, Conflict, conflict
from .history import Junction, xy
from .history import MIN_DECEL_SPAN_S, STOPPED_MPS, Sample, position_at, speed_at
from .history import FOLLOW_M, FOLLOW_S, VEHICLE_WIDTH_M
from .history import Other, Passage
from .history import PAST_TOLERANCE_M
from .reaction import (FORCE_DECEL_MPS2, REACTION_TIME_S, SPEED_NOISE_MPS, _HasSpeed, _Placed, _Way,
                       needed_deceleration, slowing_began)

SECOND = 1_000_000_000
SAME_ZONE_M = CAR_LENGTH_M / 2  # two conflict zones this close along a road user's way are one place: a road user
                                # is in a zone while within half a car's length of it (conflicts._occupancy)


def leader(p: Passage, other: Other, extend_m: float = 0.0, mine: Conflict | None = None) -> str | None:
    """The road user ahead of `other` on its own way when it began to slow (`slowing_began`),
    heading its way (within SAME_WAY_DEG of the way's direction there) or standing, no faster
    than it, and so close that keeping the two-second gap behind it needed FORCE_DECEL_MPS2 or
    more: the one it followed. `extend_m`: its way goes on this far straight ahead of its last
    position (one whose record ends standing behind its leader). `mine`: V's conflict with it; on
    a collision course (unslowed, in their zone with V), a road user V came in front of on its way
    (`came_between`) is not the one it followed: V was then the vehicle in front (HC 126). None
    where none was, or the record cannot tell (no onset, no way, no speed)."""
    onset = slowing_began(other)
    if onset is None:
        return None
    way = _Way(_extended(other.way, extend_m), VEHICLE_WIDTH_M)
    here, _ = position_at(other.way, onset)
    speed, _ = speed_at(other.way, onset)
    if len(way.points) < 2 or here is None or speed is None:
        return None
    own = way.hit(here)
    if own is None:
        return None
    for ahead in p.others:
        if ahead.user == other.user or _walking(ahead):
            continue                    # a pedestrian on the footway leads nobody in the lane
        there, _ = position_at(ahead.samples, onset)
        its, _ = speed_at(ahead.samples, onset)
        if there is None or its is None:
            continue
        hit = way.hit(there)
        if hit is None:
            continue
        gap = hit.along_m - own.along_m
        heading = _heading_at(ahead.samples, onset)
        along = 1.0 if heading is None else heading[0] * hit.direction[0] + heading[1] * hit.direction[1]
        going = its <= STOPPED_MPS or hit.goes_along(heading)
        need = needed_deceleration(speed, its * max(along, 0.0), gap)
        below = _braked_on_behind(other, ahead, onset, gap) if math.isinf(need) else \
            _slowed_below(other, ahead, onset, gap)
        if gap > 0 and going and (its <= speed or _slowing_too(ahead, onset, its, speed)) and \
                need >= FORCE_DECEL_MPS2 and not below and \
                not (mine is not None and mine.projected_gap_s is not None and mine.projected_gap_s < 0
                     and came_between(p.samples, other, ahead.samples, onset)):
            return ahead.user
    return None


def _slowed_below(other: Other, ahead: Other, onset: int, gap: float) -> bool:
    """Whether the road user's slowing begun at `onset` (`gap` metres behind the road user ahead on
    its way) went on below the slowest the road user ahead went from then until the road user was
    at its slowest (the lowest speed before it sped up again by SPEED_NOISE_MPS), by as much as a
    change of speed counts from (FORCE_DECEL_MPS2 over MIN_DECEL_SPAN_S: a braking measured over
    its hardest second sheds that much), with the one ahead then beyond the two-second gap
    (needed_deceleration asks nothing: the gap taken on by what each travelled since the onset).
    Keeping that gap behind a vehicle (HC 126) takes the follower down to its speed, never below
    it, once the follower is not within the gap: a change of speed below it was for something
    else. The town run's
    534 braked from 13.35 to 2.55 m/s at 4.5 m/s² turning right in j4 behind 389, which came
    from the north into 534's exit lane 30 m ahead at 9.5 m/s and sped up to 13.4 m/s, 40 m ahead
    when 534 was slowest (SUMO's account: foe 496 from 515.2 s, below 8.4 m/s). A follower still
    within the gap at its slowest (a queue closing up) may be dropping back behind its leader.
    False where the record cannot tell (no speed or position of either then)."""
    low = _slowest(other.way, onset)
    if low is None:
        return False
    speeds = [s.speed_mps for s in ahead.samples if s.speed_mps is not None and onset <= s.t <= low.t]
    its, _ = speed_at(ahead.samples, low.t)
    if not speeds or its is None or low.speed_mps > min(speeds) - FORCE_DECEL_MPS2 * MIN_DECEL_SPAN_S:
        return False
    went, mine = _travelled(ahead.samples, onset, low.t), _travelled(other.way, onset, low.t)
    if went is None or mine is None:
        return False
    return needed_deceleration(low.speed_mps, its, gap + went - mine) < FORCE_DECEL_MPS2


def _braked_on_behind(other: Other, ahead: Other, onset: int, gap: float) -> bool:
    """Whether the road user, within the two-second gap behind the road user ahead when its slowing
    began at `onset` (`gap` metres behind it on its way), went on slowing by as much as a change of
    speed counts from (FORCE_DECEL_MPS2 over MIN_DECEL_SPAN_S) after it had dropped back: already
    below the slowest the road user ahead went from the onset to the follower's slowest, and two
    seconds or more behind it counted at its own speed (FOLLOW_M + FOLLOW_S × its speed: HC 126's
    "two-second gap between you and the vehicle in front", the time it would take to reach where the
    one ahead is; the gap taken on by what each travelled since the onset). One too close behind
    its leader drops back by going slower than the leader until the gap is kept (HC 126), and no
    further: a braking on below that, once the gap is kept, was for something else. The paper run's
    154 (a police car on j2's south Give Way arm, 16.8 m behind 241 turning the same way at 8.2 m/s
    and speeding up to 11.2 m/s) braked from 8.35 m/s at 378.1 s at 4.5 m/s² to a stand at its
    line as 142 turned right out of the north Stop arm into the lane 154 was turning left into; at
    379.1 s it was at 3.85 m/s, 19.5 m behind 241 (15.7 m kept its two seconds), and it went on to
    a stand (SUMO's account: foe 142, held 4.5 m/s²). A follower closing up in a queue behind a
    crawling leader stops within a change of speed of where it dropped back. False where the record
    cannot tell."""
    low = _slowest(other.way, onset)
    if low is None:
        return False
    speeds = [s.speed_mps for s in ahead.samples if s.speed_mps is not None and onset <= s.t <= low.t]
    if not speeds:
        return False
    floor = min(speeds)
    for s in other.way:
        if s.speed_mps is None or s.t < onset or s.t > low.t or s.speed_mps >= floor:
            continue
        went, mine = _travelled(ahead.samples, onset, s.t), _travelled(other.way, onset, s.t)
        if went is None or mine is None:
            continue
        if gap + went - mine >= FOLLOW_M + FOLLOW_S * s.speed_mps:
            return s.speed_mps - low.speed_mps >= FORCE_DECEL_MPS2 * MIN_DECEL_SPAN_S
    return False


def _travelled(samples: Sequence[Sample], t0: int, t1: int) -> float | None:
    """How far the road user went between t0 and t1, along its placed positions."""
    a, _ = position_at(samples, t0)
    b, _ = position_at(samples, t1)
    if a is None or b is None:
        return None
    points = [a, *(xy(s) for s in samples if s.placed and t0 < s.t < t1), b]
    return sum(math.dist(p, q) for p, q in zip(points, points[1:]))


def _slowest(samples: Sequence[Sample], onset: int) -> _HasSpeed | None:
    """The road user's slowest sample in the slowing begun at `onset`: the lowest speed from then
    on, before it went SPEED_NOISE_MPS faster again."""
    low: _HasSpeed | None = None
    for s in samples:
        if s.t < onset or s.speed_mps is None:
            continue
        if low is not None and s.speed_mps > low.speed_mps + SPEED_NOISE_MPS:
            break
        if low is None or s.speed_mps < low.speed_mps:
            low = cast(_HasSpeed, s)        # its speed is measured (the None ones are passed over)
    return low


def _slowing_too(ahead: Other, t: int, its: float, speed: float) -> bool:
    """Whether the road user ahead, going at the follower's speed at t (faster by no more than
    SPEED_NOISE_MPS, the margin within which a road user has not yet begun to slow), was itself
    slowing then: a second later it went SPEED_NOISE_MPS or more slower. Two cars 20 m apart at
    13.3 and 13.4 m/s that begin to brake at the same sample are a leader and its follower (the
    paper run's 164 behind 221, the town's 241 behind 292, which SUMO's account says braked for
    those leaders); a leader pulling away from the follower is not what it braked for."""
    later, _ = speed_at(ahead.samples, t + SECOND)
    return its - speed <= SPEED_NOISE_MPS and later is not None and later <= its - SPEED_NOISE_MPS


def _extended(samples: Sequence[Sample], extend_m: float) -> list[tuple[float, float]]:
    """The placed positions, the last segment taken on `extend_m` further straight ahead."""
    points: list[tuple[float, float]] = []
    for s in samples:
        if s.placed and (not points or (s.x, s.y) != points[-1]):
            points.append(xy(s))
    if extend_m > 0 and len(points) >= 2:
        (x0, y0), (x1, y1) = points[-2], points[-1]
        length = math.hypot(x1 - x0, y1 - y0)
        points.append((x1 + (x1 - x0) / length * extend_m, y1 + (y1 - y0) / length * extend_m))
    return points


def nearer_conflict(p: Passage, other: Other, mine: Conflict | None,
                    extend_m: float = 0.0) -> tuple[Other, Conflict] | None:
    """The road user W (not V, not `other`) whose conflict with `other`'s path explains its braking
    rather than V's conflict `mine` (derived.conflict_of): `other` would have come within
    PET_MAX_S of W at the speed it had when it began to slow (W's projected gap under PET_MAX_S),
    and W's conflict comes before V's in `ahead_of`'s order, or V's path never meets `other`'s
    (no conflict zone, `other` taken on straight ahead where its record ends short). The first
    in that order is named. W may be among V's own approach's road users (another emerger out of
    the same line after V). One behind `other` on its own way is its follower, never what it
    braked for. None where no such road user is in the record, or where V's conflict or `other`'s
    slowing is not measured (no onset; V's zone's distance or gap unknown)."""
    onset = slowing_began(other)
    if onset is None:
        return None
    if mine is not None and (mine.onset_to_zone_m is None or mine.projected_gap_s is None):
        return None                     # V's conflict is in the record but not measurable at the onset
    way = _Way.of(other.way, VEHICLE_WIDTH_M)
    here, _ = position_at(other.way, onset)
    own = way.hit(here) if here is not None and len(way.points) >= 2 else None
    best: tuple[Other, Conflict] | None = None
    for w in p.others + p.same_approach:
        if w.user == other.user or w.user == p.vehicle or _behind(w, onset, way, own):
            continue
        c = conflict(w.way, other.way, None, walker=_walking(other), onset=onset, extend_m=extend_m,
                     mine_walker=_walking(w))
        if c is None or c.projected_gap_s is None or c.onset_to_zone_m is None or c.projected_gap_s >= PET_MAX_S:
            continue
        if mine is not None and both_collisions(c, mine) and proceeding(p, onset) \
                and not came_between(w.way, other, p.samples, onset):
            continue                    # V's own collision course asked the braking whatever W did
        if waited_after(w, other, onset, p.junction, c.mine.entered):
            continue                    # W still to stand at its line: its proceeding came after the slowing
        if (mine is None or ahead_of(c, mine)) and (best is None or ahead_of(c, best[1])):
            best = (w, c)
    return best


def came_between(first: Sequence[Sample], other: Other, beyond: Sequence[Sample], onset: int) -> bool:
    """Whether a road user (`first`, its samples) came into `other`'s way after `other` began to
    slow (`onset`), going its way, ahead of `other` and behind the road user of `beyond` at one
    moment: it cut in between `other` and that one, and was then the vehicle in front of `other`
    (HC 126), which `other` met first whatever the one beyond it did. Two emergers joining a main
    road car's lane ahead of it one behind the other are a queue forming in its way: unslowed, it
    would have run into the nearer before it could reach the farther, and after it could come to
    the farther only behind the nearer. The paper run's 205 (13.4 m/s) braked at 4.5 m/s² from
    323.5 s as 266 crawled out of j2's north arm into its lane 32 m ahead, behind 279, which had
    come out of the south arm into the same lane 39 m ahead; SUMO, asked tick by tick, had 266 as
    205's leader, and 205's next speed was the same with 279 taken away and 13.41 m/s with 266
    taken away. Positions only: each position of `first` after the onset on `other`'s way
    (within a vehicle's width), heading its way, against where `other` and the one beyond were on
    that way at that moment. False where the record cannot tell."""
    way = _Way.of(other.way, VEHICLE_WIDTH_M)
    if len(way.points) < 2:
        return False
    for s in first:
        if s.t <= onset or not s.placed:
            continue
        hit = way.hit(xy(s))
        heading = _heading_at(first, s.t)
        if hit is None or not hit.goes_along(heading):
            continue
        own, _ = position_at(other.way, s.t)
        far, _ = position_at(beyond, s.t)
        own_hit = way.hit(own) if own is not None else None
        far_hit = way.hit(far) if far is not None else None
        if own_hit is not None and far_hit is not None and own_hit.along_m < hit.along_m < far_hit.along_m:
            return True
    return False


def waited_after(w: Other, other: Other, onset: int, junction: Junction, entered: int | None) -> bool:
    """Whether W, coming from another arm than the road user `other`, after `other` began to slow
    (`onset`) and before W came into their zone (`entered`, where the record shows it), stood
    still at or behind its own line (its arm's Stop, Give Way or signal line, or up to
    PAST_TOLERANCE_M past it): it was still waiting where the law asks it to, and its proceeding
    began after the slowing did, so the slowing was no reaction to its proceeding. This is V's
    rule turned to W: a road user's braking is counted against V only from when V set off from
    its standstill before its line (derived._set_off, others.since). A W on the road user's own
    arm is ahead of it in the queue to that line, and what the road user slowed for is W standing
    in its way, not W's proceeding (the paper run's 164, queued behind 293 at j2's Give Way line,
    SUMO's account: leader 293).
    The town run's 279 began to slow at 416.1 s while 108 braked to stand at its Give Way line
    (417.2-417.5 s) and 114 rode through their conflict zone; 108's projected gap (0.91 s, its
    later crossing) had named 108, where SUMO's account says 279 braked for 114 (2.55 m/s² held)."""
    line = junction.line_for(w.arm) if w.arm is not None else None
    if line is None or w.arm == other.arm:
        return False
    return any(s.t > onset and (entered is None or s.t < entered) and s.placed and s.speed_mps is not None
               and s.speed_mps <= STOPPED_MPS and line.to_line(*xy(s)) >= -PAST_TOLERANCE_M for s in w.way)


def ahead_of(c: Conflict, d: Conflict) -> bool:
    """Whether the braking is put down to conflict `c` rather than `d` (both measured at the same
    onset of the same road user's slowing):

    1. a collision course (projected gap below 0: unslowed, in the zone together) before a near
       miss (0 to PET_MAX_S: it would have passed apart): the conflict nearer an accident asks
       the lower speed, which is how SUMO's car-following model names a braking's cause (the
       constraint allowing the lowest speed), and with W's conflict a collision course and V's
       not, the road user had to brake whatever V did;
    2. then the zone it would have reached first on its way, by more than SAME_ZONE_M: the
       driver resolves the first conflict on its way, and reaches the next later and slower;
    3. zones at one place (within SAME_ZONE_M: two road users crossing its lane one after the
       other, out of the same line), the smaller projected gap: post-encroachment time is the
       severity of a conflict (Allen, Shin & Cooper 1978: the smaller, the nearer a collision).

    One order for every pair, so that two vehicles are never each excused by the other's conflict
    with the same braking."""
    if (_gap(c) < 0) != (_gap(d) < 0):
        return _gap(c) < 0
    if abs(_zone(c) - _zone(d)) > SAME_ZONE_M:
        return _zone(c) < _zone(d)
    return _gap(c) < _gap(d)


def _gap(c: Conflict) -> float:
    """The projected gap of a conflict measured at the onset: only such conflicts are compared
    (`nearer_conflict` passes over W's and V's with either measure missing)."""
    return cast(float, c.projected_gap_s)


def _zone(c: Conflict) -> float:
    """The distance to the zone of a conflict measured at the onset (as `_gap`)."""
    return cast(float, c.onset_to_zone_m)


def both_collisions(c: Conflict, mine: Conflict) -> bool:
    """Whether, unslowed, the road user would have been in W's zone with W and in V's zone with V
    (both projected gaps below 0): each emerger on its own made it brake "in order to avoid an
    accident" (TSRGD 2016 Sch 9 Pt 7 para 1; HC 172), and W's presence does not excuse V's
    proceeding, nor V's W's. The braking is then V's and W's alike, and neither is put down to
    the other: the paper run's 236 stopped as 298 (unslowed, in its zone with it: -3.36 s, 6.3 m
    on) and 182 (-1.15 s, 19.2 m on) came out of their lines together, and SUMO's account says it
    braked for 182 (9.0 m/s², held 2.1), which the first-on-its-way order had put down to 298."""
    return _gap(c) < 0 and _gap(mine) < 0


def proceeding(p: Passage, onset: int) -> bool:
    """Whether V had proceeded (crossed its line, else entered the junction) when the road user
    began to slow, or did so within REACTION_TIME_S after: only then was the braking a reaction
    to V's proceeding as much as to W. One begun earlier than a perception-reaction time before
    V moved off its line was the conflict already before it (W's), V's only anticipated: the
    paper run's 164 began to slow 2.8 s before 199 crossed its Stop line, with 293 standing in
    its way 18 m on (SUMO's account: leader 293), and 161 3.0 s before 125 crossed (SUMO: it did
    not brake for 125). None of the record (no act): not proceeding."""
    act = p.crossing.t if p.crossing else p.entered.t if p.entered else None
    return act is not None and act - onset <= REACTION_TIME_S * SECOND


def why(c: Conflict, mine: Conflict | None) -> str:
    """Which of `ahead_of`'s grounds puts the braking down to W's conflict `c` rather than V's
    (`mine`): "apart" (V's path never meets it), "collision" (W's a collision course, V's not),
    "first" (W's zone first on its way), "closer" (one place, W's gap the smaller)."""
    if mine is None:
        return "apart"
    if (_gap(c) < 0) != (_gap(mine) < 0):
        return "collision"
    if abs(_zone(c) - _zone(mine)) > SAME_ZONE_M:
        return "first"
    return "closer"


def _behind(w: Other, t: int, way: _Way, own) -> bool:
    """Whether `w` was behind the road user on its way at t, going its way: following it."""
    if own is None:
        return False
    there, _ = position_at(w.samples, t)
    hit = way.hit(there) if there is not None else None
    if hit is None or hit.along_m >= own.along_m:
        return False
    heading = _heading_at(w.samples, t)
    return hit.goes_along(heading)


def _heading_at(samples: Sequence[Sample], t: int) -> tuple[float, float] | None:
    """The road user's direction of travel at t (a unit vector): its stated heading nearest t,
    else from its positions half a second either side."""
    stated = [s for s in samples if s.heading_deg is not None and abs(s.t - t) <= SECOND // 2]
    if stated:
        angle = math.radians(cast(float, min(stated, key=lambda s: abs(s.t - t)).heading_deg))
        return math.cos(angle), math.sin(angle)
    a, _ = position_at(samples, t - SECOND // 2)
    b, _ = position_at(samples, t + SECOND // 2)
    if a is None or b is None:
        return None
    length = math.dist(a, b)
    return None if length < 0.1 else ((b[0] - a[0]) / length, (b[1] - a[1]) / length)


def _walking(other: Other) -> bool:
    return other.type == "pedestrian" or other.src.startswith("pedestrian/")


def joined_behind(p: Passage, other: Other, mine: Conflict | None, set_off: int | None) -> bool:
    """Whether V, standing at its line when the road user began to slow, came into the road
    user's way behind it: the road user's slowing began before V set off from its standstill
    (`set_off`: while V stood where the law asks it to wait, it made no one change speed), it went
    through their conflict zone first and had left it before V came in (`mine`, V's conflict with
    it: post-encroachment time above 0, the road user first), V kept on without slowing from its
    act until it came in (its own course, no giving way to the road user on the way), and V then
    went on along the road user's way, heading its way (it joined the road user's lane behind it).
    A driver ahead cannot avoid an accident with one joining behind it by braking, which only
    brings the two closer: its braking was not "in order to avoid an accident" with V (TSRGD 2016
    Sch 9 Pt 7 paras 1 and 2; HC 126 leaves the gap to the one behind). The paper run's 136 went
    through the merge of j2's south arm 0.74 s before 283 turned in behind it, braking at
    2.2 m/s² as its own leader 149 did 33 m ahead, from before 283 set off (SUMO's account:
    leader 149 held 2.3). A V that never stood is not answered here: a road user going straight on
    that braked as V came at its line without stopping may have braked for fear V would come out
    in front of it (tests/reasoner/test_conflict_scenarios.py's rolling control); one that slowed
    for a turn of its own and went through ahead of V is `derived.turned_ahead`'s. None of this is
    answered where the record cannot tell (an onset, who was first, when V came in or left, V's
    speeds or way after)."""
    began = slowing_began(other)
    if set_off is None or began is None or began >= set_off:
        return False
    return came_in_behind(p, other, mine)


def came_in_behind(p: Passage, other: Other, mine: Conflict | None) -> bool:
    """Whether V came into the road user's way behind it: the road user went through their
    conflict zone first and had left it before V came in (`mine`, V's conflict with it:
    post-encroachment time above 0, the road user first), V kept on without slowing from its act
    until it came in (its own course, no giving way to the road user on the way), and V then went
    on along the road user's way, heading its way, for two seconds (it joined the road user's lane
    behind it). What a road user ahead could meet with V there was V running into it from behind,
    which its braking could not avoid (`joined_behind`, `derived.turned_ahead`). False where the
    record cannot tell."""
    act = p.crossing.t if p.crossing else p.entered.t if p.entered else None
    if mine is None or act is None or mine.first != "theirs" or not mine.pet_s or mine.theirs is None \
            or mine.theirs.left is None or mine.mine.entered is None or mine.mine.left is None:
        return False
    speeds = [s.speed_mps for s in p.samples if act <= s.t <= mine.mine.entered and s.speed_mps is not None]
    if not speeds or any(v < max(speeds[:i + 1]) - SPEED_NOISE_MPS for i, v in enumerate(speeds)):
        return False                    # V slowed or stopped on its way in: its timing may have been the road user's
    way = _Way.of(other.way, VEHICLE_WIDTH_M)
    after = cast("list[_Placed]", [s for s in p.samples
                                   if s.placed and mine.mine.left <= s.t <= mine.mine.left + 2 * SECOND])
    if len(way.points) < 2 or not after:
        return False
    for s in after:
        hit = way.hit((s.x, s.y))
        heading = _heading_at(p.samples, s.t)
        if hit is None or not hit.goes_along(heading):
            return False
    return True
