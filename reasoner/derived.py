"""Facts derived from a passage at a moment: the sentences the rulebooks use, each with the method
that produced it and the measurements it rests on (DESIGN "Reasoning").

    facts(passage, at)                    -> tuple[DerivedFact, ...]
    checked(passage, at, stated)          -> (derived facts, contradictions)

The sentences (core vocabulary, docs/vocabulary.md, and the time-dependent "V crossed the stop
line on C light") and how each is derived, with its thresholds and their sources, are listed in
docs/history.md. In short: the light a signal shows governs traffic up to its stop line (TSRGD
2016 Sch 14 Pt 1 para 5(3): "shall not proceed beyond the stop line"), so `V has C light` is
stated until V crosses it, and from then on `V crossed the stop line on C light`. Open texture
is measured against published yardsticks: rule 126's stopping distances for "too close to stop
safely", a deceleration of FORCE_DECEL_MPS2 for "would force U to change speed or course", with the
paths' conflict and its surrogate safety measures (reasoner/conflicts.py: PET_MAX_S) for whether
the change was made "in order to avoid an accident" with V, and for whether a pedestrian or
cyclist was in or entering V's path (ENDANGER_S) rather than merely near the junction.

A derived fact never overrides a stated one: `checked` holds back every derived fact that
disagrees with what a producer stated and reports the disagreement as a `Contradiction` (a
finding candidate, `to_finding()`), leaving the decision to whoever weighs the evidence.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from typing import Any, Callable, Iterable, cast

from store import EventRef

from .history import UNIT, Junction, Sample, sector, xy
from .model import DerivedFact, Finding
from .history import MIN_DECEL_SPAN_S, MPH_PER_MPS, STOPPED_MPS, Braking, between, mph, peak_deceleration, position_at, speed_at
from .attribution import SAME_ZONE_M, came_in_behind, joined_behind, leader, nearer_conflict, why
from .conflicts import PET_MAX_S, SWERVE_M, TTC_MAX_S, Conflict, conflict, exit_gap, has_path, swerve
from .history import FOLLOW_M, FOLLOW_S, VEHICLE_WIDTH_M, braking_into, own_cause, paths_within, since, through
from .reaction import (FORCE_DECEL_MPS2, REACTION_TIME_S, SAME_WAY_DEG, Turn, behind_at_turn, braked_afresh, cleared_at,
                       reacted_after_clearing, slowing_began, stop_apart, turn_deg, turn_seen, turn_taken,
                       well_ahead)
from .history import ANTICIPATION_S
from .history import Other, Passage, Standstill
from .history import WORDS, Light, shown
from .stopping import SOURCE as RULE_126, stopping_distance_m
from .tolerance import beyond_stopping, deceleration, sensor_of
from .vocabulary import (CROSSED_THE_STOP_LINE_ON, EXIT_OF_THE_BOX_JUNCTION_IS_CLEAR, HAS_CROSSED_THE_STOP_LINE, HAS_LIGHT,
                         HAS_SIGN, HAS_SPEED_OF, HAS_STOPPED_AT_THE_STOP_LINE,
                         HAS_STOPPED_BEFORE_ENTERING_THE_MAJOR_ROAD, IS_APPROACHING, IS_AT_A_BOX_JUNCTION, IS_IN_THE_JUNCTION,
                         IS_OF_TYPE, IS_ON_AN_EMERGENCY_CALL, IS_ON_THE_MAIN_ROAD, IS_STOPPED, IS_STOPPED_IN_THE_BOX_JUNCTION,
                         IS_TOO_CLOSE_TO_STOP, SPEED_LIMIT_IS, WOULD_ENDANGER, WOULD_FORCE, Sentence)
from .when import format_time

SECOND = 1_000_000_000

# Thresholds (docs/history.md gives the reasoning)
APPROACH_M = 50.0         # "approaching": outside the junction, within this distance of its centre, getting closer
APPROACH_DT_S = 0.5       # ... by comparing its distance now with this long before
EXIT_ZONE_M = 12.0        # a box junction's exit: this far beyond the junction's edge on the exit arm (a car, a gap)
QUEUED_MPS = 2.0          # a road user in the exit zone at or below this speed blocks it (4.5 mph: crawling)
MOVING_MPS = 1.0          # "V is stopped" is contradicted from this speed on (2.2 mph: beyond measurement noise)
SPEED_TOLERANCE_MPH = 3   # a stated speed this far from the measured one is a contradiction
PLACE_TOLERANCE_M = 2.0   # "has crossed the stop line" / "is in the junction" contradicted this far short of it
CLOCK_TOLERANCE_S = 0.5   # a light changing this close to the moment is not a contradiction either way
ENDANGER_S = PET_MAX_S    # a pedestrian or cyclist in or entering V's path within this of V being there (PET or
                          # TTC at the act) is endangered: SUMO's SSM device counts an encounter under it a conflict
EXTEND_M = 30.0           # a road user whose record ends short of V's path is taken on straight ahead this far
                          # (30 mph covers it in about 2 s, the conflict window): the way it was going


@dataclass(frozen=True)
class Contradiction:
    """A stated fact the measurements contradict: a finding candidate, never a silent override."""

    stated: str
    stated_by: EventRef
    measured: str           # what the measurements show, in words
    method: str
    evidence: tuple[EventRef, ...]
    shown: tuple[str, ...] = ()     # the derived sentences that show it, held back (weighing asks the
                                    # rules on them in the claim's place)

    @property
    def detail(self) -> str:
        return f"\"{self.stated}\" was stated ({self.stated_by.src} #{self.stated_by.seq}), but {self.measured}"

    def to_finding(self) -> Finding:
        return Finding("contradiction", self.detail, (self.stated_by, *self.evidence), fact=self.stated)

    def to_json(self) -> dict[str, Any]:
        return {"stated": self.stated, "stated_by": self.stated_by.to_json(), "measured": self.measured,
                "method": self.method, "evidence": [r.to_json() for r in self.evidence], "detail": self.detail}


# --- the facts ------------------------------------------------------------------------------------

def facts(passage: Passage, at: int) -> tuple[DerivedFact, ...]:
    """Every sentence the passage shows at `at` (ns), each with its method and evidence."""
    out: list[DerivedFact] = []
    for derive in _DERIVERS:
        out += derive(passage, at)
    return tuple(out)


def _light(p: Passage, at: int) -> list[DerivedFact]:
    """`V has C light`: the light facing its approach, until it crosses its stop line (or, with
    no line on the map, until it enters the junction)."""
    over = p.crossing.t if p.crossing else (p.entered.t if p.entered and p.line is None else None)
    if not p.lights or (over is not None and at >= over) or p.past_line_at_start or at > p.end \
            or at < p.start - SECOND:
        return []
    light = shown(p.lights, at)
    if light is None:
        return []
    method = f"{_showed(light, p)}, still before its stop line at {format_time(at)}"
    return [DerivedFact(HAS_LIGHT.text(p.vehicle, word), method, (light.ref,)) for word in WORDS[light.colour]]


def _speed(p: Passage, at: int) -> list[DerivedFact]:
    """`V has speed of N` (mph, whole, half up) and `V is stopped` (a speed that rounds to 0 mph)."""
    speed, used = speed_at(p.samples, at)
    if speed is None:
        return []
    how = f"{speed:.2f} m/s ({speed * MPH_PER_MPS:.1f} mph): {between(used, at)}"
    refs = tuple(s.ref for s in used)
    out = [DerivedFact(HAS_SPEED_OF.text(p.vehicle, mph(speed)), how, refs)]
    if speed <= STOPPED_MPS:
        out.append(DerivedFact(IS_STOPPED.text(p.vehicle), f"{how}; stopped: below 0.5 mph, a speed of 0 mph", refs))
    return out


def _limit(p: Passage, at: int) -> list[DerivedFact]:
    if p.limit_mph is None or p.map_ref is None:
        return []
    limit = int(p.limit_mph) if float(p.limit_mph).is_integer() else p.limit_mph
    return [DerivedFact(SPEED_LIMIT_IS.text(limit), f"speed_limit_mph of road {p.limit_road} in the run's map, "
                        "the road the vehicle approached on", (p.map_ref,))]


def _crossed(p: Passage, at: int) -> list[DerivedFact]:
    """`V has crossed the stop line` once it did; `V crossed the stop line on C light` with it."""
    c = p.crossing
    if c is None or at < c.t:
        if p.past_line_at_start and at >= p.start and p.samples:
            first = next(s for s in p.samples if s.placed)
            return [DerivedFact(HAS_CROSSED_THE_STOP_LINE.text(p.vehicle),
                                f"first seen already past the stop line ({first.label})", (first.ref,),
                                "when it crossed is not in the record")]
        return []
    out = [DerivedFact(HAS_CROSSED_THE_STOP_LINE.text(p.vehicle), f"crossed at {format_time(c.t)}: {c.moment.method}",
                       c.moment.refs, c.moment.uncertain)]
    if c.light is not None:
        doubt = "; ".join(filter(None, [c.moment.uncertain, c.light_uncertain])) or None
        method = f"crossed at {format_time(c.t)} ({c.moment.method}); {_showed(c.light, p)}"
        refs = c.moment.refs + (c.light.ref,) + tuple(x.ref for x in c.light_changed)
        out += [DerivedFact(CROSSED_THE_STOP_LINE_ON.text(p.vehicle, word), method, refs, doubt)
                for word in WORDS[c.light.colour]]
    return out


def _in_junction(p: Passage, at: int) -> list[DerivedFact]:
    inside_from = p.entered.t if p.entered else (p.start if p.samples and _first_inside(p) else None)
    if inside_from is None or at < inside_from or (p.left is not None and at >= p.left.t) or at > p.end:
        return []
    how = p.entered.method if p.entered else "first seen inside the junction"
    extent = f"the junction's area: {p.junction.extent_m:g} m ({p.junction.extent_source})"
    refs = p.entered.refs if p.entered else (p.samples[0].ref,)
    return [DerivedFact(IS_IN_THE_JUNCTION.text(p.vehicle), f"entered at {format_time(inside_from)}: {how}; {extent}",
                        refs, p.entered.uncertain if p.entered else "its entry is not in the record")]


def _emergency(p: Passage, at: int) -> list[DerivedFact]:
    marks = [m for m in p.emergency if m[0] <= at]
    if not marks or not marks[-1][1]:
        return []
    t, _, ref = marks[-1]
    return [DerivedFact(IS_ON_AN_EMERGENCY_CALL.text(p.vehicle),
                        f"{ref.kind} #{ref.seq} ({format_time(t)}) records emergency: true, not withdrawn since", (ref,))]


def _stopped_at_line(p: Passage, at: int) -> list[DerivedFact]:
    """`V has stopped at the stop line`: it stood still at a Stop line (HC 171) before crossing it."""
    line = p.line
    if line is None or not _stop_line(p):   # (a Stop line is a line: _sign_of)
        return []
    limit = min(at, p.crossing.t) if p.crossing else at
    stops = [s for s in p.standstills if s.at_line and s.first.t <= limit]
    if not stops:
        return []
    s = stops[-1]
    how = (f"stood still for {s.duration_s:.1f} s ({s.samples} samples from {s.first.label} to {s.last.label} below "
           f"0.5 mph), {s.to_line_m:.1f} m before the Stop line ({line.source})")
    return [DerivedFact(HAS_STOPPED_AT_THE_STOP_LINE.text(p.vehicle), how, (s.first.ref, s.last.ref))]


def _sign(p: Passage, at: int) -> list[DerivedFact]:
    """`V has a stop sign` / `V has a give way sign`: the map's line across V's approach is a Stop
    or Give Way line (its kind; without one, the junction's control). DESIGN's map states where
    the signs are, so a producer that draws the map need not state the sign at every frame."""
    sign, line = _sign_of(p), p.line
    if sign is None or line is None or p.map_ref is None or at < p.start - SECOND or at > p.end:
        return []                       # (a sign is a line's: _sign_of)
    how = (f"the {p.approach} approach of {p.junction.id} has a {sign} line in the run's map "
           f"({'kind ' + repr(line.kind) if line.kind else 'junction control ' + repr(p.junction.control)}, "
           f"{line.source}{'; ' + line.reading if line.reading else ''})")
    return [DerivedFact(HAS_SIGN.text(p.vehicle, sign), how, (p.map_ref,))]


def _stopped_before_major_road(p: Passage, at: int) -> list[DerivedFact]:
    """`V has stopped before entering the major road`: at a Stop line, V stood still outside the
    junction's area before it entered it (TSRGD 2016 Sch 9 Pt 7 para 1: where the line "is not
    clearly visible", the stop is owed "before entering the major road"). A stop at the line is
    one (highway_code.le says so too); one past a worn line, short of the junction, is one."""
    if not _stop_line(p):
        return []
    limit = min(at, p.entered.t) if p.entered else at
    stops = [s for s in p.standstills if s.last.t <= limit and s.first.placed and s.last.placed
             and not p.junction.inside(*xy(s.first)) and not p.junction.inside(*xy(s.last))]
    if not stops:
        return []
    s = stops[-1]
    edge = p.junction.edge(*xy(s.last))
    how = (f"stood still for {s.duration_s:.1f} s ({s.samples} samples from {s.first.label} to {s.last.label} below "
           f"0.5 mph), {edge:.1f} m outside {p.junction.id}'s area ({p.junction.extent_source}), before entering it")
    return [DerivedFact(HAS_STOPPED_BEFORE_ENTERING_THE_MAJOR_ROAD.text(p.vehicle), how, (s.first.ref, s.last.ref))]


def _too_close(p: Passage, at: int) -> list[DerivedFact]:
    """`V is too close to the stop line to stop safely`: when amber came, the distance to the line
    was less than rule 126's stopping distance at V's speed then."""
    amber = _amber(p, at)
    if amber is None or amber.to_line_m is None or amber.speed_mps is None or amber.to_line_m <= 0 \
            or _stopped_after(p, amber.light.t, at):
        return []
    speed_mph = amber.speed_mps * MPH_PER_MPS
    needed = stopping_distance_m(speed_mph)
    if amber.to_line_m >= needed:
        return []
    how = (f"when amber came ({format_time(amber.light.t)}, {amber.light.ref.src} #{amber.light.ref.seq}) it was "
           f"{amber.to_line_m:.1f} m before the line at {amber.speed_mps:.1f} m/s ({speed_mph:.0f} mph), "
           f"{amber.method}; stopping takes {needed:.1f} m at that speed ({RULE_126}, interpolated)")
    return [DerivedFact(IS_TOO_CLOSE_TO_STOP.text(p.vehicle), how, tuple(s.ref for s in amber.used) + (amber.light.ref,))]


def _others(p: Passage, at: int) -> list[DerivedFact]:
    """`U is approaching V`, `V would force U to change speed or course`, `U is on the main road`."""
    out: list[DerivedFact] = []
    went = p.crossing is not None or p.entered is not None
    for other in reacting(p):
        approaching = _approaching(p, other, at)
        forced = _forced(p, other) if went and p.start <= at <= p.end + 5 * SECOND else None
        endangered = _endangered(p, other)
        if approaching is not None:
            out.append(approaching)
        if endangered is not None:
            out.append(endangered)
        if forced is not None:
            out.append(forced)
        if other.type and other.spawn is not None and any(f is not None for f in (approaching, forced, endangered)):
            out.append(DerivedFact(IS_OF_TYPE.text(other.user, other.type),
                                   f"{other.spawn.src} #{other.spawn.seq} (entity.spawn) gives type {other.type}",
                                   (other.spawn,)))
        if other.main_road and not _walking(other) and (approaching is not None or forced is not None):
            first = other.samples[0]
            out.append(DerivedFact(IS_ON_THE_MAIN_ROAD.text(other.user),
                                   f"first seen on the {other.arm} arm of {p.junction.id} ({first.label}); "
                                   f"{p.junction.major_source}: major {', '.join(sorted(p.junction.major or ()))}",
                                   tuple(r for r in (first.ref, p.map_ref) if r is not None)))
    return out


def _box(p: Passage, at: int) -> list[DerivedFact]:
    """The box junction sentences (HC 174), from the map's yellow box and the positions at `at`."""
    j = p.junction
    if not j.boxed or p.map_ref is None or at < p.start or at > p.end or (p.left and at >= p.left.t):
        return []
    marked = f"the map marks a yellow box at {j.id} (run.start, box)"
    out = [DerivedFact(IS_AT_A_BOX_JUNCTION.text(p.vehicle), f"{marked}; the vehicle is on its way through it",
                       (p.map_ref,))]
    position, placed = position_at(p.samples, at)
    speed, timed = speed_at(p.samples, at)
    if position and speed is not None and j.in_box(*position) and speed <= STOPPED_MPS:
        out.append(DerivedFact(IS_STOPPED_IN_THE_BOX_JUNCTION.text(p.vehicle),
                               f"{marked}; at {format_time(at)} inside it ({between(placed, at)}) at {speed:.2f} m/s",
                               tuple(s.ref for s in placed + timed) + (p.map_ref,)))
    clear = _exit_clear(p, at)
    if clear is not None:
        out.append(clear)
    return out


_DERIVERS: tuple[Callable[[Passage, int], list[DerivedFact]], ...] = (
    _light, _sign, _crossed, _in_junction, _speed, _limit, _emergency, _stopped_at_line, _stopped_before_major_road,
    _too_close, _others, _box)


# --- pieces -----------------------------------------------------------------------------------------

def _showed(light: Light, p: Passage) -> str:
    return (f"{light.ref.src} showed {light.colour} to the {p.approach} approach from {format_time(light.t)} "
            f"({light.ref.src} #{light.ref.seq})")


def _first_inside(p: Passage) -> bool:
    first = next((s for s in p.samples if s.placed), None)
    return first is not None and p.junction.inside(*xy(first))


def _stop_line(p: Passage) -> bool:
    return _sign_of(p) == "stop"


def _sign_of(p: Passage) -> str | None:
    """The sign of V's line: "stop" or "give way", by its kind (DESIGN: stop_sign, give_way;
    junctions.py reads a producer's other words), or without one by the junction's control."""
    if p.line is None:
        return None
    if p.line.kind:
        return {"stop_sign": "stop", "give_way": "give way"}.get(p.line.kind)
    return {"stop": "stop", "give_way": "give way"}.get(p.junction.control)


def _amber(p: Passage, at: int):
    """The last change from green to amber before the crossing (and before `at`)."""
    end = min(at, p.crossing.t) if p.crossing else at
    found = [c for c in p.changes if c.light.colour == "amber" and c.previous in ("green", None) and c.light.t <= end]
    return found[-1] if found else None


def _stopped_after(p: Passage, t: int, at: int):
    """A standstill before the line (or at it) from t on, before crossing and by `at`: the
    vehicle showed it could stop, whatever the typical figures say."""
    end = min(at, p.crossing.t) if p.crossing else at
    return next((s for s in p.standstills if t <= s.last.t and s.first.t <= end and
                 (s.to_line_m is None or s.to_line_m >= -1.0)), None)


def _walking(other: Other) -> bool:
    """A pedestrian: traffic on the main road, whose drivers a Give Way or Stop line protects
    (TSRGD 2016 Sch 9 Pts 7 and 8: "the driver of ... a vehicle on the major road"), is vehicles; a
    pedestrian on its pavement is no such traffic (HC 170 and para 5(5)'s "endanger" speak for them)."""
    return other.type == "pedestrian" or other.src.startswith("pedestrian/")


def _approaching(p: Passage, other: Other, at: int) -> DerivedFact | None:
    """U closing on the centre at `at`; or, for a road user that came to a stop or braked at
    FORCE_DECEL_MPS2 or harder while V passed (one V may have forced), when it did: it was
    approaching V then, whether or not it was yet in view, or near enough, at the moment asked
    about. Gentler braking is no sign of V: a main-road car easing off as it went through the
    junction ahead of V is not one V emerged in front of; nor is braking something else explains
    (its own light, its own Stop line, the road user it followed: `explained`). A pedestrian is
    no traffic: it `is approaching V` only in or entering V's path (`_entering`). A cyclist is the
    driver of a vehicle (HC 172's traffic on the major road): it approaches as a car does, and
    whether V endangered it is `_endangered`'s, measured, never its approach."""
    if _walking(other):
        return _entering(p, other)
    found = _approaching_at(p, other, at)
    if explained(p, other):
        return found
    hard = other.braking if other.braking and (other.stopped or other.braking.decel_mps2 >= FORCE_DECEL_MPS2) \
        else None
    reacted = hard.first.t if hard else other.stopped.t if other.stopped else None
    if found is None and reacted is not None and reacted != at:
        found = _approaching_at(p, other, reacted, within=math.inf)
    if found is None and reacted is not None:
        found = _in_the_way(p, other, reacted)
    return found


def _in_the_way(p: Passage, other: Other, reacted: int) -> DerivedFact | None:
    """U, braking hard or stopping inside the junction (`_toward_zone`), was approaching V when it
    did if it was then on its way through the conflict zone it shared with V and left it only
    after V came into it: traffic going through the junction that V came out in front of, as much
    as traffic still on the arm (HC 172's "traffic on the major road")."""
    c = conflict_of(p, other)
    if c is None or c.theirs is None or c.mine.entered is None:
        return None
    left = c.theirs.left
    if (left is not None and left <= c.mine.entered) or (left is not None and left <= reacted):
        return None
    where, used = position_at(other.samples, reacted)
    if where is None:
        return None
    j = p.junction
    how = (f"{other.user} was in {j.id}, {j.distance(*where):.0f} m from its centre, on its way through the zone where "
           f"its path meets {p.vehicle}'s when it braked ({format_time(reacted)}, {between(used, reacted)}), and left "
           f"that zone only after {p.vehicle} came into it{conflict_words(p, other.user, c)}")
    return DerivedFact(IS_APPROACHING.text(other.user, p.vehicle), how, tuple(s.ref for s in used) + _conflict_refs(c))


def _endangered(p: Passage, other: Other) -> DerivedFact | None:
    """`V would endanger P` of a pedestrian or cyclist, from the measured conflict alone: P was in
    or entering V's path within ENDANGER_S of V being there (`_entering`). Approaching the junction,
    or riding on the main road towards it, is not being endangered."""
    if not (_walking(other) or other.type == "cyclist"):
        return None
    entering = _entering(p, other)
    if entering is None:
        return None
    return DerivedFact(WOULD_ENDANGER.text(p.vehicle, other.user), entering.method, entering.evidence)


def _entering(p: Passage, other: Other) -> DerivedFact | None:
    """A pedestrian or cyclist `is approaching V` when it was in or entering V's path within
    ENDANGER_S of V being there: their paths meet (reasoner/conflicts.py) and both were in the
    conflict zone at once, or it entered the zone less than ENDANGER_S after V left it (V passing
    just in front of it), or at V's act the two were on course to be in it together within
    ENDANGER_S (TTC). One that had crossed V's path and left it before V got there is out of
    its way: V following it across is not likely to endanger it. One on the
    far footway, or crossing well before or after V, is near the junction, not coming at V: para
    5(5) and Sch 9 Pt 7 para 1 ask whether V was likely to endanger them, and walking towards a
    junction V leaves does not make it so."""
    c = conflict_of(p, other)
    if c is None:
        return None
    pet = c.pet_s is not None and (c.pet_s == 0 or (c.first == "mine" and c.pet_s < ENDANGER_S))
    ttc = c.ttc_s is not None and c.ttc_s < ENDANGER_S
    if not (pet or ttc):
        return None
    how = (f"{other.user} was in or entering {p.vehicle}'s path within {ENDANGER_S:g} s of {p.vehicle} being there "
           f"(SUMO SSM device's PET threshold){conflict_words(p, other.user, c)}")
    return DerivedFact(IS_APPROACHING.text(other.user, p.vehicle), how, _conflict_refs(c))


def _approaching_at(p: Passage, other: Other, at: int, within: float = APPROACH_M) -> DerivedFact | None:
    """U closing on the centre at `at`, from outside the junction and `within` metres of it: a road
    user is approaching within APPROACH_M; one that braked hard or stopped while V passed, with
    nothing else to explain it, was approaching V when it did, however far off (near_users has
    already kept only those that came within CONFLICT_M): a main-road car braking at 3.3 m/s² 71 m
    out as V turned into its lane was approaching V."""
    now, used = position_at(other.samples, at)
    before, used_before = position_at(other.samples, at - int(APPROACH_DT_S * SECOND))
    if now is None or before is None:
        return None
    j = p.junction
    d_now, d_before = j.distance(*now), j.distance(*before)
    if j.edge(*now) <= 0 or d_now > within or d_before - d_now < 0.1:
        return None
    how = (f"{other.user} was {d_now:.0f} m from the centre of {j.id} on the {other.arm} arm at {format_time(at)} and "
           f"{d_before - d_now:.1f} m closer than {APPROACH_DT_S:g} s before ({between(used, at)})")
    return DerivedFact(IS_APPROACHING.text(other.user, p.vehicle), how, tuple(s.ref for s in used_before + used))


class _ByIdentity:
    """The answers of a pure function of immutable values (a passage, a road user of it), kept by
    the values' identity: one measurement asks the same questions of the same passage again (its
    facts ask `explained` of each road user twice, its margins once or twice more). An answer is
    kept with its arguments, so that no id is reused while it is held; the newest `size` are kept
    (a measurement's, not a run's: each holds its passage)."""

    def __init__(self, fn: Callable[..., Any], size: int) -> None:
        self._fn, self._size = fn, size
        self._kept: dict[tuple[int, ...], tuple[tuple[Any, ...], Any]] = {}

    def __call__(self, *args: Any) -> Any:
        key = tuple(id(a) for a in args)
        hit = self._kept.get(key)
        if hit is not None:
            return hit[1]
        value = self._fn(*args)
        if len(self._kept) >= self._size:
            del self._kept[next(iter(self._kept))]
        self._kept[key] = (args, value)
        return value


def reacting(p: Passage) -> tuple[Other, ...]:
    """The road users near V's passage with their braking and stops counted while V passed: from
    when V set off, if it stood before its line (_set_off). Every sentence and margin about a
    reaction to V reads these, so that a main-road car braking while V still waited at its line
    (for a turn, a queue, its own light) is neither "forced" by V nor "approaching" V because of
    that braking."""
    return _reacting(p)


def _reacting_afresh(p: Passage) -> tuple[Other, ...]:
    off = _set_off(p)
    found = p.others if off is None else tuple(since(o, p.others, p.junction, off.last.t) for o in p.others)
    act = p.crossing.t if p.crossing else p.entered.t if p.entered else None
    if act is None:
        return found
    start = off.last.t if off is not None else act - int(ANTICIPATION_S * SECOND)
    found = tuple(_own_stop(p, _toward_zone(p, o, start)) for o in found)
    found = found if off is None else tuple(_braked_afresh(p, o, off.last.t) for o in found)
    return tuple(caused_stretch(p, o) for o in found)


def caused_stretch(p: Passage, other: Other) -> Other:
    """The road user with its braking measured over the stretch of its slowing V is held to have
    caused: from the onset attribution reads (reaction.slowing_began) to where a later, harder
    braking begins that something else explains (reaction.braked_afresh read from each of its
    samples on: harder, by FORCE_DECEL_MPS2 or more, than the second before, and `explained` at
    its own onset: another road user it then braked for, its own line, V already out of its way;
    the stretch ends where that braking begins).
    TSRGD 2016 Sch 9 Pt 7 para 1 asks of each change of speed whether V caused it; the figure that
    decides (braked_hard: FORCE_DECEL_MPS2 over MIN_DECEL_SPAN_S, less its uncertainty) and the
    figure cited are the hardest second of that stretch, and a stop after it is the next cause's.
    The paper run's 205 braked at 4.5 m/s² for 266 coming into its lane from 323.4 s and at
    5.5 m/s² from 325.3 s for 253, which came out between them (SUMO's account: foe 266, then foe
    253); 266's Stop cited the 5.5. Unchanged where V's braking is not at issue (explained, no
    onset), where no such later braking is in the record, or where the record cannot tell."""
    b = other.braking
    if b is None or _walking(other) or explained(p, other):
        return other
    onset = slowing_began(other)
    if onset is None or b.first.t <= onset:
        return other
    end = _next_cause(p, other, onset, b.first.t)
    if end is None:
        return other
    stretch = braking_into(other.samples, p.junction, (onset, end))
    stopped = other.stopped if other.stopped is not None and other.stopped.t < end else None
    return replace(other, braking=stretch, stopped=stopped)


def _next_cause(p: Passage, other: Other, onset: int, until: int) -> int | None:
    """Where, after `onset` and by `until` (its hardest braking's start), the road user's slowing
    became another cause's: the start of the first fresh braking (reaction.braked_afresh, counted
    from one of its samples: harder than the second before it, by FORCE_DECEL_MPS2 or more) that
    `explained` puts down to something other than V at its own onset, begun MIN_DECEL_SPAN_S or
    more after `onset` (a second of the slowing before it, the measure a braking is taken over:
    one begun sooner is the slowing itself, as attribution read it at its onset). None where there
    is none."""
    for s in other.samples:
        if s.t <= onset or s.t > until:
            continue
        fresh = braked_afresh(since(other, p.others, p.junction, s.t), s.t)
        if fresh is None or fresh.braking is None or fresh.braking.first.t - onset < MIN_DECEL_SPAN_S * SECOND:
            continue
        if explained(p, fresh):
            return fresh.braking.first.t
    return None


def _braked_afresh(p: Passage, other: Other, set_off: int) -> Other:
    """The road user with its braking after V set off read as a change of speed of its own
    (reaction.braked_afresh: harder, by FORCE_DECEL_MPS2 or more, than the slowing it was already
    making) where the slowing it began before V set off is explained and that braking, taken from
    where and how fast the road user was when V set off, is not: TSRGD 2016 Sch 9 Pt 7 para 1 asks
    of each change of speed whether V caused it, and slowing for another road user does not make a
    later, harder braking for V that road user's. Not where the road user was by then already in
    another road user's conflict zone with that one about to come in (`inside_another`): a
    braking begun there is that one's to explain, whatever lay ahead. Where the braking is V's to
    answer for as read, or the fresh reading is explained too, the reading stays as it was."""
    fresh = braked_afresh(other, set_off)
    if fresh is None or not explained(p, other) or explained(p, fresh) or inside_another(p, fresh) is not None:
        return other
    return fresh


def inside_another(p: Passage, other: Other) -> tuple[str, float] | None:
    """The road user W (not V) in whose conflict zone with it the road user already was when it
    began to slow, and the time from its leaving that zone, had it kept its speed, to W's coming in
    (conflicts.exit_gap), where that was under PET_MAX_S: W was about to come in, or was there
    already, and the road user braking inside W's zone was resolving W's conflict, the first on its
    way (attribution.ahead_of's order: a zone it was in comes before one ahead of it). The
    projected gap is not defined for a road user already in the zone; this is the occupancy at the
    onset that stands for it. The town run's 279, turning right at j2, slowed for the cyclist 114,
    sped up again and braked anew at 4.5 m/s² from 418.6 s, inside the zone it shared with 108
    coming out of its Give Way line (unslowed, it would have left it 0.22 s after 108 came in;
    SUMO's account: foe 108 from 419.0 s), 0.8 s after 170 set off from its Stop line on the north
    arm. None where it was in no such zone, or the record cannot tell."""
    onset = slowing_began(other)
    if onset is None or _walking(other):
        return None
    best: tuple[str, float] | None = None
    for w in p.others + p.same_approach:
        if w.user in (other.user, p.vehicle) or _walking(w):
            continue
        gap = exit_gap(w.way, other.way, onset, _extend(p, other))
        if gap is not None and gap < PET_MAX_S and (best is None or gap < best[1]):
            best = (w.user, gap)
    return best


def _own_stop(p: Passage, other: Other) -> Other:
    """The road user, or its stop alone where that was a reaction of its own (others.stop_apart)
    that nothing else explains while its braking before it is explained: one change of speed for
    its leader, a second, later, for V (TSRGD 2016 Sch 9 Pt 7 para 1 asks of each change of speed
    whether V caused it). Where the braking is V's to answer for, it stays the one read."""
    apart = stop_apart(other, p.others, p.junction)
    if apart is None or not explained(p, other) or explained(p, apart):
        return other
    return apart


def _toward_zone(p: Passage, other: Other, start: int) -> Other:
    """The road user with its braking on its way into, or in, the conflict zone it shared with V
    (reasoner/conflicts.py), once V set off (or from ANTICIPATION_S before V's act), where that
    was harder than the braking counted outside the junction (others.py counts braking only
    there, heading in): a main-road car turning across the arm V emerges from, braking at 4.5
    m/s² inside the junction as V pulls into its way, changed speed for V as much as one braking
    before it. Attribution (`explained`) then asks what the braking was for, as for any other."""
    if _walking(other) or not has_path(other.way):
        return other
    c = conflict(p.samples, other.way, None)
    if c is None or c.theirs is None or (c.theirs.left is not None and c.theirs.left <= start):
        return other
    until = c.theirs.left if c.theirs.left is not None else max(s.t for s in other.way)
    b = peak_deceleration(other.way, start, until)
    if b is None or b.decel_mps2 <= 0 or (other.braking is not None and b.decel_mps2 <= other.braking.decel_mps2):
        return other
    return replace(other, braking=b)


_reacting = _ByIdentity(_reacting_afresh, 8)


def _forced(p: Passage, other: Other) -> DerivedFact | None:
    """U (counted from when V set off: `reacting`) braked harder than FORCE_DECEL_MPS2 beyond the
    braking's uncertainty (`braked_hard`: a braking within it is in doubt, not proven), or came to
    a stop, or changed course, while V passed, and not for something else (`explained`: a light,
    Stop or Give Way line of its own, a road user it followed or whose conflict it resolved)."""
    if other.user == p.vehicle:
        return None                          # nobody forces itself (a record under two sources' names)
    off = _set_off(p)
    after = ""
    if off is not None:
        after = f" after {p.vehicle} set off from its standstill ({off.last.label}, {format_time(off.last.t)})"
    if explained(p, other):
        return None
    b, stop = other.braking, other.stopped
    if stop is not None:
        how = f"{other.user} came to a stop ({stop.label}, {format_time(stop.t)}) while {p.vehicle} passed{after}"
        refs: tuple[EventRef, ...] = (stop.ref,)
    elif b is not None and braked_hard(p, b):
        how = (f"{other.user} braked at {braking_words(p, b)} ({b.first.speed_mps:.1f} m/s at {b.first.label} to "
               f"{b.last.speed_mps:.1f} m/s at {b.last.label}) while {p.vehicle} passed{after}; from {FORCE_DECEL_MPS2:g} m/s² "
               "a change of speed is a considerable reaction (Hupfer 1997), and this braking exceeds it by more than "
               f"its uncertainty (reasoner/tolerance.py: the two speeds' tolerance over the span, {sensor_of(p, b.first).said})")
        refs = (b.first.ref, b.last.ref)
    else:
        swerved = _course_changed(p, other, after)
        if swerved is None:
            return None
        how, refs = swerved
    own = f"; its own light was {other.light.colour}" if other.light else ""
    c = conflict_of(p, other)
    return DerivedFact(WOULD_FORCE.text(p.vehicle, other.user),
                       f"{how}, {other.closest_m:.0f} m from the centre{own}{conflict_words(p, other.user, c)}",
                       refs + ((other.light.ref,) if other.light else ()) + _conflict_refs(c))


def braked_hard(p: Passage, b: Braking) -> bool:
    """Whether a braking proves a change of speed: its measured deceleration less its uncertainty
    (tolerance.deceleration: the two speeds' tolerance, its source's stated one or the default,
    over the span) exceeds FORCE_DECEL_MPS2. One within its uncertainty of the threshold is in
    doubt, and a ground in doubt is not proven (issue 36; margins._give_way says so of the margin)."""
    return b.decel_mps2 - deceleration(b, sensor_of(p, b.first)) > FORCE_DECEL_MPS2


def braking_words(p: Passage, b: Braking) -> str:
    """"3.5 ± 0.2 m/s² against 2 m/s²": the figure, its uncertainty and the threshold."""
    return f"{b.decel_mps2:.1f} ± {deceleration(b, sensor_of(p, b.first)):.1f} m/s² against {FORCE_DECEL_MPS2:g} m/s²"


def _out_first(p: Passage, other: Other, t: int | None) -> Conflict | None:
    """V's conflict with the road user where the road user was in their conflict zone first and
    out of it before V came in (post-encroachment time above 0, the road user first), and its
    change of speed or course began at `t`, after it had left the zone: nothing it did then
    avoided an accident with V there, which it had already passed (a lane change down the road
    after it went through ahead of V). None otherwise, or where the record cannot tell."""
    c = conflict_of(p, other)
    if t is None or c is None or c.first != "theirs" or not c.pet_s or c.theirs is None or c.theirs.left is None:
        return None
    return c if t >= c.theirs.left else None


def _course_changed(p: Passage, other: Other, after: str = "") -> tuple[str, tuple[EventRef, ...]] | None:
    """A change of course V caused (para 1 and 5(5): "change its speed or course"): U, a vehicle
    going on its way, moved SWERVE_M or more to the side of the line it was on at V's act while V
    passed, and had it kept to that line it would have met V in their conflict zone within
    PET_MAX_S (conflicts.swerve). A pedestrian's steps are judged as danger, not as this."""
    act = p.crossing.t if p.crossing else p.entered.t if p.entered else None
    if act is None or _walking(other):
        return None
    until = (p.left.t if p.left else p.end) + int(PET_MAX_S * SECOND)
    sw = swerve(p.samples, other.samples, act, until)
    if sw is None or sw.kept_pet_s is None or sw.kept_pet_s >= PET_MAX_S:
        return None
    if _out_first(p, other, sw.departed.t if sw.departed else None) is not None:
        return None                         # it had gone through the zone ahead of V before it moved over
    a, b = sw.before
    kept = f"{p.vehicle} first" if sw.kept_first == "mine" else f"{other.user} first"
    how = (f"{other.user} changed course while {p.vehicle} passed{after}: {sw.offset_m:.1f} m to the side of the line it "
           f"was on at {p.vehicle}'s act ({a.label} to {b.label}), widest at {sw.widest.label} "
           f"({format_time(sw.widest.t)}), going on its way, at {sw.widest.speed_mps or 0:.1f} m/s; a sideways "
           f"departure counts from {SWERVE_M:g} m (a car centred in a 3.65 m lane has 0.9 m either side); had it "
           f"kept to its line, post-encroachment time {sw.kept_pet_s:.2f} s with {p.vehicle} ({kept}; under "
           f"{PET_MAX_S:g} s is a conflict: SUMO SSM device's PET threshold)")
    return how, (a.ref, b.ref, sw.widest.ref)


def conflict_words(p: Passage, user: str, c: Conflict | None) -> str:
    """The conflict's measures in words, for a method: where the paths meet, the gaps in time and
    the deceleration needed, each with the threshold it is held against and its source."""
    if c is None:
        other = next((o for o in p.others if o.user == user), None)
        if other is not None and has_path(p.samples) and has_path(other.way):
            return f"; {user}'s path and {p.vehicle}'s never meet: no conflict zone"
        return f"; {user}'s path and {p.vehicle}'s are not both in the record: no conflict measured"
    j = p.junction
    out = [f"; their paths meet {j.distance(c.x, c.y):.1f} m from the centre of {j.id} ({c.x:.1f}, {c.y:.1f})"]
    if c.pet_s is not None:
        order = f"{p.vehicle} first" if c.first == "mine" else f"{user} first"
        out.append(f"post-encroachment time {c.pet_s:.2f} s ({order})")
    if c.ttc_s is not None:
        out.append(f"time to collision at the act {c.ttc_s:.2f} s (under {TTC_MAX_S:g} s is a conflict)")
    if c.projected_gap_s is not None and c.onset_to_zone_m is not None and c.onset_speed_mps is not None \
            and c.onset is not None:    # (a projected gap is taken at the onset: conflicts.conflict)
        gap = "it would have been in the zone with it" if c.projected_gap_s <= 0 else \
            f"{c.projected_gap_s:.2f} s from {p.vehicle} there"
        out.append(f"when {user} began to slow ({format_time(c.onset)}) it was {c.onset_to_zone_m:.1f} m from the "
                   f"conflict zone at {c.onset_speed_mps:.1f} m/s: unslowed, {gap} (a gap under {PET_MAX_S:g} s "
                   f"is a conflict: SUMO SSM device's PET threshold)")
    if c.drac_mps2 is not None:
        out.append(f"deceleration needed to reach the zone only once {p.vehicle} had left it {c.drac_mps2:.1f} m/s²")
    return "; ".join(out)


def _conflict_refs(c: Conflict | None) -> tuple[EventRef, ...]:
    if c is None:
        return ()
    return tuple(dict.fromkeys(s.ref for o in (c.mine, c.theirs) if o is not None for s in o.samples))


def explained(p: Passage, other: Other) -> bool:
    """Whether something other than the vehicle passing explains the road user's braking or stop:
    a red or amber light of its own, a Stop line of its own, a road user it followed (others.py),
    a path through the junction that never came within a vehicle's width of V's (others.paths_within:
    no conflict point, so it slowed for its own manoeuvre), slowing that began more than a
    perception-reaction time after V was out of its way, or V well ahead of it on its way, going
    its way (reasoner/reaction.py), or another road user it was resolving: its leader on its way,
    or one whose conflict zone with it came before V's on its way within PET_MAX_S
    (reasoner/attribution.py); or a turn of its own (`turned_behind`, `turned_ahead`)."""
    return _explained(p, other)


def _explained_afresh(p: Passage, other: Other) -> bool:
    if own_cause(other) and not _line_no_excuse(p, other):
        return True
    if other.braking is None and other.stopped is None:
        return False
    return paths_within(p.samples, other.way, p.junction, VEHICLE_WIDTH_M) is False \
        or reacted_after_clearing(p.samples, other) or well_ahead(p.samples, other) or _clear_of(p, other) \
        or _out_first(p, other, slowing_began(other)) is not None or _went_first(p, other) is not None \
        or leader(p, other, _extend(p, other), conflict_of(p, other)) is not None or _nearer(p, other) is not None \
        or stood_on(p, other) is not None or joined_behind(p, other, conflict_of(p, other), _set_off_t(p)) \
        or turned_behind(p, other) is not None or turned_ahead(p, other) is not None


def stood_on(p: Passage, other: Other) -> tuple[Conflict, int] | None:
    """V's conflict with the road user, and when the road user moved off again, where, unslowed,
    it would have come into their conflict zone only after V had left it (projected gap 0 or
    more: no collision course), it came to a stop only after V had left (V first), and it stood on
    more than REACTION_TIME_S after V had left: a driver V made stop moves off once V is out of
    its way, within a perception-reaction time (AASHTO's 2.5 s, above the 90th percentile); one
    that would not have met V had it kept on, came to a standstill with V already gone, and still
    stood well after, was held by something else (oncoming traffic or pedestrians its own turn
    gives way to, HC 170 and 180), and that it stopped "in order to avoid an accident" with V is
    not shown (TSRGD 2016 Sch 9 Pt 7 para 1; a ground in doubt is not proven). The paper run's 139
    braked as 273 crossed the arm it was to turn into (unslowed, 0.93 s behind 273), stopped at its
    right-turn waiting place 2.2 s after 273 had left their zone, and stood 4.7 s after it had
    (SUMO's account: pedestrians p7 and p6 on the crossings of its way). One on a collision course
    that braked hard to a stop just as V cleared, and then stood shaken, was forced whatever it
    did after. None otherwise, or where the record cannot tell (no stop, no projected gap, V's
    leaving unknown, the record ending while it stands)."""
    c = conflict_of(p, other)
    stop = other.stopped
    if stop is None or c is None or c.first != "mine" or c.mine.left is None or stop.t < c.mine.left \
            or c.projected_gap_s is None or c.projected_gap_s < 0:
        return None
    moved = next((s.t for s in other.way if s.t > stop.t and s.speed_mps is not None and s.speed_mps > STOPPED_MPS),
                 None)
    if moved is None or moved - c.mine.left <= REACTION_TIME_S * SECOND:
        return None
    return c, moved


def turned_behind(p: Passage, other: Other) -> tuple[Conflict, float, Turn | None] | None:
    """V's conflict with the road user and how far (degrees) the road user turned, where it slowed
    for a turn of its own behind V: its way out of the junction was more than SAME_WAY_DEG off its
    way in (it turned there); V was in their conflict zone first, left it, and was out of the road
    user's way again (reaction.cleared_at: it crossed that way) or went on ahead of it down the
    road it turned into with the gap kept at the speed of its turn (below); the road user did not
    stop; and, unslowed, it would have come into the zone
    only after V had left it (projected gap 0 or more: no collision course). The projection keeps
    the speed it had when it began to slow, faster than any turn is taken, so it arrives no later
    than a turning road user could: one that even so would have found V gone had no accident with
    V to avoid, and its slowing was for its own turn (issue 35: "not for its own control (... its
    own turn ...)"; TSRGD 2016 Sch 9 Pt 7 para 1 and HC 172 ask for a change of speed "in order to
    avoid an accident"). The town run's 279 slowed from 13.4 to 6.4 m/s as it came to its right
    turn across oncoming traffic, 114 crossing its way out of j2's Give Way line ahead of it
    (unslowed, 1.02 s after 114 had left their zone), and turned without stopping (SUMO's account:
    its own minor link's approach). Where V did go on ahead of it down the road it turned into
    (the following case), the two-second gap behind V is asked at the speed the road user took its
    turn at, read from its own record (reaction.turn_taken: it slowed no lower than that), not
    at the speed it came in at, which no turn is taken at (reaction.behind_at_turn: from where it
    began to slow, at that speed, V was HC 126's gap or more ahead of it at each of V's positions
    on its way, and V pulling away, faster than that by a change of speed); the third item is
    that turn, None where V crossed its way. The paper run's 228 (13.03 to 6.28 m/s, its turn
    into j2's south arm 28.8 m behind 116 going on at 9.6 to 13.4 m/s; SUMO's account: its own
    minor link's approach). One on a collision course with V (a negative projected gap), or that
    stopped, is not answered here, turning or not. None where the record cannot tell (no way in
    and out of the junction, no projected gap, V's leaving unknown)."""
    c = conflict_of(p, other)
    if other.stopped is not None or c is None or c.first != "mine" or c.mine.left is None \
            or c.projected_gap_s is None or c.projected_gap_s < 0:
        return None
    turned = turn_deg(through(other.way, p.junction))
    if turned is None or turned <= SAME_WAY_DEG:
        return None
    if cleared_at(p.samples, other.way) is not None:
        return c, turned, None
    turn = turn_taken(other, p.junction)
    return (c, turned, turn) if turn is not None and behind_at_turn(p.samples, other, turn) else None


def turned_ahead(p: Passage, other: Other) -> tuple[Conflict, float, Turn] | None:
    """V's conflict with the road user, how far (degrees) the road user turned, and the speed it
    took its turn at, where it slowed for a turn of its own and went through ahead of V, V coming
    in behind it: its way out of the junction was more than SAME_WAY_DEG off its way in, as far as
    its record shows it (reaction.turn_seen); it did not stop, and slowed no lower than the speed
    it took its turn at (reaction.turn_taken: the slowest it went in the junction's area, nowhere
    slower from when it began to slow until it left the area); it went through their conflict zone
    first and left it before V came in, and unslowed it would have too (projected gap 0 or more:
    no collision course); and V came in behind it without slowing and went on along its way
    (attribution.came_in_behind). A turn is taken slower than the road it leaves, whoever comes,
    and the issue counts a road user's "own turn" among its own control; going through ahead of V
    with V coming on behind it, what it could meet with V was V running into it from behind, which
    its slowing could not avoid and only brought nearer. Its change of speed was for its turn, not
    "in order to avoid an accident" with V (TSRGD 2016 Sch 9 Pt 7 para 1; HC 172; HC 126 leaves
    the gap to the one behind). A road user going straight on is not answered here: braking as V
    came at its line without stopping, it may have braked for fear V would come out in front of it
    (attribution.joined_behind asks V to have stood). The town run's 411, turning right from j19's
    east arm into the north arm 236 was coming up to from the south Give Way line at 13.4 m/s: in
    the junction, in its turn, from 9.6 to 6.47 m/s (the speed it had entered the junction at) and
    away at 2.6 m/s², through their zone 0.78 s ahead of 236 (unslowed, 0.96 s); SUMO's account:
    its own exit link's approach, its speeds the same without 236. None where the record cannot
    tell (no way out of the junction, no projected gap, who was first, V's speeds or way after)."""
    c = conflict_of(p, other)
    if other.stopped is not None or c is None or c.first != "theirs" or c.projected_gap_s is None \
            or c.projected_gap_s < 0:
        return None
    turned = turn_seen(other.way, p.junction)
    if turned is None or turned <= SAME_WAY_DEG:
        return None
    turn = turn_taken(other, p.junction)
    if turn is None or not came_in_behind(p, other, c):
        return None
    return c, turned, turn


def _went_first(p: Passage, other: Other) -> Conflict | None:
    """V's conflict with the road user where it came to a stop and afterwards went into their
    conflict zone (reasoner/conflicts.py) ahead of V: it did not wait for V to pass, so what it
    stopped for is not shown to be V (a ground in doubt is not proven; SUMO's account names the
    leaders of the paper run's 224 and the town's 424, which did so). A road user that slowed and
    went on through ahead of V without a stop is not answered here: it may have braked so as to
    clear V's way in time (the town's 386 braking at 4.5 m/s² as 265 came out of its Give Way
    line, which SUMO says was for 265). None otherwise, or where the record cannot tell (who was
    in the zone first, or when)."""
    c = conflict_of(p, other)
    if other.stopped is None or c is None or c.first != "theirs" or c.theirs is None or c.theirs.entered is None \
            or c.mine.entered is None or not other.stopped.t < c.theirs.entered < c.mine.entered:
        return None
    return c


def _nearer_afresh(p: Passage, other: Other) -> tuple[Other, Conflict] | None:
    """The road user whose conflict with `other`'s path it would have met first, within PET_MAX_S
    (reasoner/attribution.py): its braking was for that one, not for V."""
    return nearer_conflict(p, other, conflict_of(p, other), _extend(p, other))


def _own_give_way(p: Passage, other: Other) -> bool:
    return p.junction.control_from(other.arm) == "give_way"


def _line_no_excuse(p: Passage, other: Other) -> bool:
    """Whether the road user's own line, the only cause of its own, leaves its braking V's to
    explain: a Give Way line (not a Stop line, which it must stop at whoever passes) where,
    unslowed, it would have been in V's conflict zone with V (a collision course: projected gap
    below 0). A Give Way line asks it to give way to the major road's traffic, not to stop: had
    it gone on, it would have run into V beyond its line, so its braking was V's to answer for
    (the paper run's 152 for 102, 207 for 196, which SUMO's account says braked for V)."""
    if not other.own_stop_line or other.followed is not None or \
            (other.light is not None and other.light.colour != "green") or not _own_give_way(p, other):
        return False
    c = conflict_of(p, other)
    return c is not None and c.projected_gap_s is not None and c.projected_gap_s < 0


def _clear_of(p: Passage, other: Other) -> bool:
    """Whether the conflict measures show the road user slowed with no accident to avoid with V:
    their paths never meet (each path in the record), or, had it kept the speed it had when it
    began to slow, it would still have passed V's conflict zone PET_MAX_S or more apart from V
    (the projected gap: reasoner/conflicts.py). A car easing for its own turn 2.9 s clear of the
    conflict point slowed for its turn; one that would have met V there slowed for V."""
    c = conflict_of(p, other)
    if c is None:
        return has_path(p.samples) and has_path(other.way) and not _walking(other) \
            and (bool(through(other.way, p.junction)) or _came_in(other, p.junction))
    if c.projected_gap_s is None:
        gap = _inside_gap(p, other)
        return gap is not None and gap >= PET_MAX_S
    return c.projected_gap_s >= PET_MAX_S


def _inside_gap(p: Passage, other: Other) -> float | None:
    """For a vehicle already in its conflict zone with V when it began to slow (the projected gap
    is for one on its way to the zone): had it kept its speed, the time from its leaving the zone
    to V's coming in (conflicts.exit_gap). PET_MAX_S or more: it would have been gone, and slowed
    for something else (the paper run's 238, turning behind 268 in j2 5 s before 265 came in,
    which SUMO says braked for 268); under it, V was about to come in while it was there (the
    golden run's 143, stopping as 145 crossed in front of it)."""
    onset = slowing_began(other)
    if onset is None or _walking(other):
        return None
    return exit_gap(p.samples, other.way, onset, _extend(p, other))


def _came_in(other: Other, j: Junction) -> bool:
    """Whether the road user's record shows it in the junction's area: one that stopped there
    (waiting to turn across oncoming traffic) and whose way, so far and taken on straight ahead
    (EXTEND_M), never meets V's path is not shown in V's way; a way cut short before the junction
    may yet have been heading for V's path, and stays V's to explain."""
    return any(j.edge(*xy(s)) <= 0 for s in other.way if s.placed)


def conflict_of(p: Passage, other: Other) -> Conflict | None:
    """The conflict of V's path with the road user's (reasoner/conflicts.py), its TTC taken at V's
    act (its crossing, else its entry) and its projected gap and DRAC at the moment the road user
    began to slow; a road user whose record ends short of the junction is taken on straight ahead."""
    return _conflict_of(p, other)


def _conflict_afresh(p: Passage, other: Other) -> Conflict | None:
    act = p.crossing.t if p.crossing else p.entered.t if p.entered else None
    return conflict(p.samples, other.way, act, walker=_walking(other), onset=slowing_began(other),
                    extend_m=_extend(p, other), rider=other.type == "cyclist")


def _extend(p: Passage, other: Other) -> float:
    """How far the road user's way is taken on straight ahead: EXTEND_M where its record ends
    short of its way through the junction, else not at all."""
    return 0.0 if through(other.way, p.junction) else EXTEND_M


_explained = _ByIdentity(_explained_afresh, 128)   # a passage's road users (MAX_OTHERS) and more
_nearer = _ByIdentity(_nearer_afresh, 128)
_conflict_of = _ByIdentity(_conflict_afresh, 128)


def _set_off(p: Passage) -> Standstill | None:
    """V's last standstill before it crossed its line (or, with no line, entered the junction),
    when it ended after the road users' reactions began to be counted: V's act began when it set
    off. Standing where the law asks it to wait, V made no one change speed; a road user already
    slowing then (behind a queue, for another road user) was slowing for something else."""
    act = p.crossing.t if p.crossing else p.entered.t if p.entered else None
    if act is None:
        return None
    before = [s for s in p.standstills if act - ANTICIPATION_S * SECOND < s.last.t <= act]
    return before[-1] if before else None


def _set_off_t(p: Passage) -> int | None:
    """When V set off from its standstill before its act (`_set_off`), or None where it never stood."""
    off = _set_off(p)
    return off.last.t if off is not None else None


def _exit_clear(p: Passage, at: int) -> DerivedFact | None:
    """`the exit of the box junction is clear for V`: no road user at QUEUED_MPS or slower in the
    EXIT_ZONE_M beyond the junction's edge on V's exit arm at `at`, on the way out (HC 174: "your
    exit road or lane"; the queue waiting at that arm's own line faces the other way)."""
    j = p.junction
    arm, doubt = p.exit, None
    if arm is None and p.approach in _OPPOSITE:
        arm, doubt = _OPPOSITE[p.approach], "the vehicle's exit is not in the record: taken as straight on"
    if arm is None:
        return None
    seen: list[EventRef] = []
    for other in p.others:
        if other.type == "pedestrian" or other.src.startswith("pedestrian/"):
            continue        # on the pavement or a crossing: no vehicle in the exit lane
        where, used = position_at(other.samples, at)
        speed, _ = speed_at(other.samples, at)
        if where is None:
            continue
        seen += [s.ref for s in used]
        on_exit = sector(where[0] - j.x, where[1] - j.y) == arm and 0 < j.edge(*where) <= EXIT_ZONE_M
        if on_exit and (speed is None or speed <= QUEUED_MPS) and _outbound(other, at, arm, where, j):
            return None
    refs = (p.map_ref,) + ((p.left.refs if p.left else ()) + tuple(seen))
    how = (f"at {format_time(at)} no road user recorded at {QUEUED_MPS:g} m/s or slower within {EXIT_ZONE_M:g} m beyond "
           f"the junction on its {arm} exit")
    return DerivedFact(EXIT_OF_THE_BOX_JUNCTION_IS_CLEAR.text(p.vehicle), how, tuple(r for r in refs if r), doubt)


_OPPOSITE = {"west": "east", "east": "west", "north": "south", "south": "north"}


def _outbound(other: Other, at: int, arm: str, where: tuple[float, float], j: Junction) -> bool:
    """Whether a road user on an exit arm is on the way out of the junction (in the exit lane),
    not queued towards it: its heading points away from the centre; with no heading recorded, it
    stands on the left of the way out (the map's traffic keeps left, as on UK roads)."""
    ux, uy = UNIT[arm]
    before = [s for s in other.samples if s.t <= at and s.heading_deg is not None]
    if before:
        rad = math.radians(cast(float, before[-1].heading_deg))
        return math.cos(rad) * ux + math.sin(rad) * uy > 0.0
    return (where[0] - j.x) * -uy + (where[1] - j.y) * ux > 0.0


# --- stated facts against derived ones ------------------------------------------------------------

def checked(passage: Passage, at: int, stated: Iterable[tuple[Any, EventRef]],
            derived: tuple[DerivedFact, ...] | None = None
            ) -> tuple[tuple[DerivedFact, ...], tuple[Contradiction, ...]]:
    """The derived facts that agree with what was stated, and a Contradiction for each stated
    fact the measurements contradict (the derived facts showing it are held back). `derived`:
    facts(passage, at), where the caller has it already (one measurement checks the Monitor
    Scenario's facts and then each perceived one against the same facts)."""
    if derived is None:
        derived = facts(passage, at)
    contradictions: list[Contradiction] = []
    held: set[str] = set()
    for sentence, ref in stated:
        if not isinstance(sentence, str):
            continue
        text = sentence.strip().rstrip(".").strip()
        for check in _CHECKS:
            found = check(passage, at, text, ref, derived)
            if found is not None:
                contradiction, withheld = found
                contradictions.append(contradiction)
                held |= withheld
    return tuple(f for f in derived if f.sentence not in held), tuple(contradictions)


def _match(sentence: Sentence, text: str) -> tuple[str, ...] | None:
    pattern = _PATTERNS.get(sentence.template)
    if pattern is None:
        pattern = _PATTERNS[sentence.template] = re.compile(
            re.escape(sentence.pattern).replace(re.escape("{}"), "(.+?)") + r"\Z")
    found = pattern.match(text)
    return found.groups() if found else None


_PATTERNS: dict[str, re.Pattern] = {}


def _derived_of(derived: tuple[DerivedFact, ...], *sentences: Sentence) -> list[DerivedFact]:
    return [f for f in derived if any(_match(s, f.sentence) for s in sentences)]


def _contradiction(text: str, ref: EventRef, measured: str, shown: list[DerivedFact],
                   method: str = "", evidence: tuple[EventRef, ...] = ()) -> tuple[Contradiction, set[str]]:
    """The contradiction, and the derived sentences to hold back (those that show it)."""
    how = "; ".join(filter(None, [method, *(f.method for f in shown)])) or "the passage's measurements"
    refs = tuple(dict.fromkeys(evidence + tuple(r for f in shown for r in f.evidence)))
    return Contradiction(text, ref, measured, how, refs, tuple(f.sentence for f in shown)), {f.sentence for f in shown}


def _check_stopped(p: Passage, at: int, text: str, ref: EventRef, derived):
    if _match(IS_STOPPED, text) != (p.vehicle,):
        return None
    speed, _ = speed_at(p.samples, at)
    if speed is None or speed < MOVING_MPS:
        return None
    return _contradiction(text, ref, f"it was measured moving at {speed:.1f} m/s ({mph(speed)} mph) then",
                          _derived_of(derived, HAS_SPEED_OF))


def _check_speed(p: Passage, at: int, text: str, ref: EventRef, derived):
    args = _match(HAS_SPEED_OF, text)
    if not args or args[0] != p.vehicle or not args[1].lstrip("-").isdigit():
        return None
    speed, _ = speed_at(p.samples, at)
    if speed is None or abs(int(args[1]) - speed * MPH_PER_MPS) <= SPEED_TOLERANCE_MPH:
        return None
    return _contradiction(text, ref, f"it was measured at {speed * MPH_PER_MPS:.1f} mph then",
                          _derived_of(derived, HAS_SPEED_OF, IS_STOPPED))


def _check_light(p: Passage, at: int, text: str, ref: EventRef, derived):
    args = _match(HAS_LIGHT, text)
    if not args or args[0] != p.vehicle or not p.lights or at > p.end:
        return None
    colour = args[1]
    near = [c for c in p.lights if abs(c.t - at) <= CLOCK_TOLERANCE_S * SECOND]
    now = shown(p.lights, at)
    possible = {w for light in [now, *near] if light for w in WORDS[light.colour]}
    if p.crossing and p.crossing.t <= at and p.crossing.light:
        possible |= set(WORDS[p.crossing.light.colour])      # "has red light" for the light it entered on
    if now is None or colour in possible or colour not in ("red", "amber", "green"):
        return None
    return _contradiction(text, ref, f"the signal facing its {p.approach} approach showed {now.colour} then",
                          _derived_of(derived, HAS_LIGHT, CROSSED_THE_STOP_LINE_ON), _showed(now, p), (now.ref,))


def _check_crossed_on(p: Passage, at: int, text: str, ref: EventRef, derived):
    args = _match(CROSSED_THE_STOP_LINE_ON, text)
    c = p.crossing
    if not args or args[0] != p.vehicle or c is None or c.light is None or c.light_uncertain or c.t > at:
        return None
    if args[1] in WORDS[c.light.colour]:
        return None
    return _contradiction(text, ref, f"it crossed the stop line on {c.light.colour}",
                          _derived_of(derived, CROSSED_THE_STOP_LINE_ON))


def _check_crossed(p: Passage, at: int, text: str, ref: EventRef, derived):
    if _match(HAS_CROSSED_THE_STOP_LINE, text) != (p.vehicle,) or p.line is None:
        return None
    if (p.crossing and p.crossing.t <= at) or p.past_line_at_start:
        return None
    where, used = position_at(p.samples, at)
    if where is None or p.line.to_line(*where) <= PLACE_TOLERANCE_M:
        return None
    return _contradiction(text, ref, f"it was {p.line.to_line(*where):.1f} m before its stop line then", [],
                          between(used, at), tuple(s.ref for s in used))


def _check_in_junction(p: Passage, at: int, text: str, ref: EventRef, derived):
    if _match(IS_IN_THE_JUNCTION, text) != (p.vehicle,):
        return None
    where, used = position_at(p.samples, at)
    if where is None or p.junction.edge(*where) <= PLACE_TOLERANCE_M:
        return None
    return _contradiction(text, ref, f"it was {p.junction.edge(*where):.1f} m outside the junction's area then", [],
                          between(used, at), tuple(s.ref for s in used))


def _check_stopped_at_line(p: Passage, at: int, text: str, ref: EventRef, derived):
    if _match(HAS_STOPPED_AT_THE_STOP_LINE, text) != (p.vehicle,) or not _stop_line(p):
        return None
    c = p.crossing
    if c is None or c.t > at or _stopped_at_line(p, at) or any("could have stopped unseen" in n for n in p.uncertain):
        return None
    slowest = min((s for s in p.samples if s.speed_mps is not None and s.t <= c.t), key=lambda s: cast(float, s.speed_mps),
                  default=None)
    if slowest is None:
        return None
    return _contradiction(text, ref, f"it crossed the Stop line without standing still (slowest "
                          f"{slowest.speed_mps:.1f} m/s, {slowest.label})", [], c.moment.method,
                          (slowest.ref,) + c.moment.refs)


def _check_emergency(p: Passage, at: int, text: str, ref: EventRef, derived):
    if _match(IS_ON_AN_EMERGENCY_CALL, text) != (p.vehicle,):
        return None
    marks = [m for m in p.emergency if m[0] <= at]
    if not marks or marks[-1][1]:
        return None
    t, _, mark = marks[-1]
    return _contradiction(text, ref, f"its own record says it was not on an emergency call from {format_time(t)}",
                          [], f"{mark.kind} #{mark.seq} records emergency: false", (mark,))


def _check_limit(p: Passage, at: int, text: str, ref: EventRef, derived):
    args = _match(SPEED_LIMIT_IS, text)
    if not args or p.limit_mph is None:
        return None
    try:
        if abs(float(args[0]) - p.limit_mph) < 0.5:
            return None
    except ValueError:
        return None
    return _contradiction(text, ref, f"the map gives {p.limit_mph:g} mph for road {p.limit_road}",
                          _derived_of(derived, SPEED_LIMIT_IS))


def _check_too_close(p: Passage, at: int, text: str, ref: EventRef, derived):
    if _match(IS_TOO_CLOSE_TO_STOP, text) != (p.vehicle,) or _too_close(p, at):
        return None
    amber = _amber(p, at)
    if amber is None or amber.to_line_m is None or amber.speed_mps is None or amber.to_line_m <= 0:
        return None
    stop = _stopped_after(p, amber.light.t, at)
    if stop is not None:
        return _contradiction(text, ref, f"it stood still {stop.to_line_m or 0:.1f} m before the line after amber came "
                              f"({stop.first.label})", [], amber.method, (stop.first.ref, amber.light.ref))
    needed = stopping_distance_m(amber.speed_mps * MPH_PER_MPS)
    measured = beyond_stopping(amber, sensor_of(p, amber.used[0] if amber.used else None))
    if measured is None:        # (never: amber's place and speed are known, above)
        return None
    beyond, u = measured
    if beyond <= u:         # within the measurements' tolerance: they do not contradict it
        return None
    return _contradiction(text, ref, f"when amber came it was {amber.to_line_m:.1f} m before the line, and stopping "
                          f"takes {needed:.1f} m at {amber.speed_mps:.1f} m/s ({RULE_126}): {beyond:.1f} m to spare, "
                          f"beyond the measurements' tolerance of ± {u:.1f} m", [], amber.method,
                          tuple(s.ref for s in amber.used) + (amber.light.ref,))


def _check_forced(p: Passage, at: int, text: str, ref: EventRef, derived):
    """A stated "V would force U to change speed or course" or "V would endanger U" is a prediction
    (a vehicle's own, a camera's reading): evidence of what its maker believed, not of the act.
    Where U's movement about V's act is in the record (`measured`), the act is judged from it: a
    statement the measurements do not bear out is contradicted, with what they show."""
    args = _match(WOULD_FORCE, text)
    endanger = args is None
    if endanger:
        args = _match(WOULD_ENDANGER, text)
    if not args:
        return _check_walker_approaching(p, text, ref)
    if args[0] != p.vehicle:
        return None
    other = next((o for o in reacting(p) if o.user == args[1]), None)
    if other is None or not measured(p, other):
        return None
    shown = {f.sentence for f in derived}
    if WOULD_FORCE.text(p.vehicle, other.user) in shown:
        return None
    if endanger and WOULD_ENDANGER.text(p.vehicle, other.user) in shown:
        return None
    return _contradiction(text, ref, _unforced(p, other), [], "", _conflict_refs(conflict_of(p, other)))


def _check_walker_approaching(p: Passage, text: str, ref: EventRef):
    """A stated "P is approaching V" of a pedestrian is read by the rules as P likely to be
    endangered (para 5(5)); a pedestrian is no main-road traffic (HC 172), so that is all it is
    read for. Where P's path about V's act is in the record and P was never in or
    entering V's path within ENDANGER_S of V (`_entering`), the measurements contradict it: a
    pedestrian walking towards the junction on the far footway is not coming at V."""
    args = _match(IS_APPROACHING, text)
    if not args or args[1] != p.vehicle:
        return None
    other = next((o for o in reacting(p) if o.user == args[0]), None)
    if other is None or not _walking(other) or not measured(p, other) or _entering(p, other) is not None:
        return None             # (a cyclist is traffic too: its approach on the main road is HC 172's)
    c = conflict_of(p, other)
    how = (f"{other.user}'s own record shows it never in or entering {p.vehicle}'s path within {ENDANGER_S:g} s of "
           f"{p.vehicle} being there (closest {other.closest_m:.0f} m from the centre)"
           + (conflict_words(p, other.user, c) if c else f"; their paths never meet"))
    return _contradiction(text, ref, how, [], "", _conflict_refs(c))


def unmeasured(p: Passage, text: str) -> str | None:
    """For a stated "V would force U ..." or "V would endanger U" about this passage's vehicle, the
    road user U when nothing of U about V's act is in the record (not near V's passage, or no path
    from before the act until V left): the statement then stands alone, and the explanation says
    so. None for any other sentence, or where U was measured."""
    args = _match(WOULD_FORCE, text) or _match(WOULD_ENDANGER, text)
    if not args or args[0] != p.vehicle:
        return None
    other = next((o for o in reacting(p) if o.user == args[1]), None)
    return args[1] if other is None or not measured(p, other) else None


def measured(p: Passage, other: Other) -> bool:
    """Whether the road user's movement about V's act is in the record: its path, and samples from
    before V's act to after V left the junction (or its record's end)."""
    act = p.crossing.t if p.crossing else p.entered.t if p.entered else None
    if act is None or not has_path(other.way):
        return False
    end = p.left.t if p.left else p.end
    times = [s.t for s in other.samples if s.placed]
    return bool(times) and times[0] <= act and times[-1] >= min(end, act + SECOND)


def _unforced(p: Passage, other: Other) -> str:
    """What the record shows of a road user V is not shown to have forced or endangered."""
    b = other.braking
    if other.stopped is None and (b is None or not braked_hard(p, b)):
        hardest = "it did not slow" if b is None else f"its hardest braking was {braking_words(p, b)}" + (
            ": within its uncertainty of the threshold, in doubt, so not proven" if b.decel_mps2 >= FORCE_DECEL_MPS2
            else "")
        how = (f"{other.user}'s own record shows no change of speed V caused: {hardest} (a change of speed counts "
               f"from {FORCE_DECEL_MPS2:g} m/s², Hupfer 1997, beyond the measurement's uncertainty)")
    elif explained(p, other):
        how = f"{other.user}'s own record shows it slowed for something else ({_cause(p, other)})"
    else:
        how = f"{other.user}'s own record does not show it endangered"
    return how.replace("V caused", f"{p.vehicle} caused") + conflict_words(p, other.user, conflict_of(p, other))


def _cause(p: Passage, other: Other) -> str:
    """What else the road user slowed for, in words, for a stated "V would force U" the record
    contradicts. Not one wording with second_limb._reason, though both word what `explained`
    found: the two name the first ground in different orders (here an own line before a road user
    followed, a zone gone through first, a first go and a leader before a zone passed clear; no
    stood-on, joined-behind or turned-ahead ground: those fall to the last line), so one function
    would change recorded words (golden-sim's 135: its finding says 137 slowed for "its own Stop
    line", its second limb that 137 "followed 122"). Which order the law asks is a question of
    its own (issue 38 keeps the words as they are)."""
    if other.light is not None and other.light.colour != "green":
        return f"its own {other.light.colour} light"
    if other.own_stop_line and not _line_no_excuse(p, other):
        return f"its own {'Give Way' if _own_give_way(p, other) else 'Stop'} line"
    if other.followed:
        return f"{other.followed} ahead of it"
    if paths_within(p.samples, other.way, p.junction, VEHICLE_WIDTH_M) is False:
        return f"its own way: its path through the junction never came within {VEHICLE_WIDTH_M:g} m of {p.vehicle}'s"
    if reacted_after_clearing(p.samples, other):
        return f"it began to slow more than a reaction time after {p.vehicle} was out of its way"
    if well_ahead(p.samples, other):
        return f"{p.vehicle} was well ahead of it on its way, going its way"
    through = _out_first(p, other, slowing_began(other))
    if through is not None:
        return (f"it began to slow after it had gone through its conflict zone with {p.vehicle} ahead of it (out "
                f"{through.pet_s:.2f} s before {p.vehicle} came in)")
    first, stopped = _went_first(p, other), other.stopped
    if first is not None and stopped is not None and first.theirs is not None and first.theirs.entered is not None \
            and first.mine.entered is not None:     # (all of them known where it went first: _went_first)
        return (f"it stopped ({stopped.label}, {format_time(stopped.t)}) and then went into its conflict "
                f"zone with {p.vehicle} ahead of {p.vehicle} ({p.vehicle} came in "
                f"{(first.mine.entered - first.theirs.entered) / SECOND:.2f} s after it): it did not wait for "
                f"{p.vehicle} to pass, so its stop is not shown to be for {p.vehicle}")
    ahead = leader(p, other, _extend(p, other), conflict_of(p, other))
    if ahead is not None:
        return (f"{ahead} ahead of it on its way when it began to slow, going its way or standing: keeping the "
                f"two-second gap behind it (HC 126) took {FORCE_DECEL_MPS2:g} m/s² or more")
    if conflict_of(p, other) is None and _clear_of(p, other):
        return (f"its own way: its path, as far as the record shows it into {p.junction.id} and taken on "
                f"{EXTEND_M:g} m straight ahead, never meets {p.vehicle}'s: no conflict zone with {p.vehicle}")
    if not _clear_of(p, other):
        nearer = _nearer(p, other)
        if nearer is not None:
            w, c = nearer
            mine = conflict_of(p, other)
            gap = f"in it with {w.user}" if c.projected_gap_s <= 0 else f"{c.projected_gap_s:.2f} s from {w.user} there"
            ground = why(c, mine)
            if ground == "apart" or mine is None:   # one and the same: why's "apart" is V's path never meeting it
                return (f"{w.user}, whose path it would have met where it never met {p.vehicle}'s: when it began to "
                        f"slow ({format_time(c.onset)}) it was {c.onset_to_zone_m:.1f} m from their conflict zone at "
                        f"{c.onset_speed_mps:.1f} m/s; unslowed, {gap} (a gap under {PET_MAX_S:g} s is a conflict: "
                        "SUMO SSM device's PET threshold)")
            theirs = (f"in {p.vehicle}'s with {p.vehicle}" if cast(float, mine.projected_gap_s) < 0 else
                      f"{mine.projected_gap_s:.2f} s from {p.vehicle} at its zone")
            reason = {"collision": f"a collision course with {w.user}, only a near miss with {p.vehicle}: the conflict "
                                   f"nearer an accident asks the lower speed",
                      "first": f"{w.user}'s zone the first on its way: the driver resolves the first conflict on its "
                               f"way",
                      "closer": f"the two zones one place (within {SAME_ZONE_M:g} m), and the smaller post-encroachment "
                                "time the more severe conflict (Allen, Shin & Cooper 1978)"}[ground]
            return (f"{w.user}, whose conflict it braked for: when it began to slow ({format_time(c.onset)}) at "
                    f"{c.onset_speed_mps:.1f} m/s it was {c.onset_to_zone_m:.1f} m from their conflict zone and "
                    f"{mine.onset_to_zone_m:.1f} m from {p.vehicle}'s; unslowed, {gap}, and {theirs} ({reason}; a "
                    f"gap under {PET_MAX_S:g} s is a conflict: SUMO SSM device's PET threshold)")
    mine = conflict_of(p, other)
    inside = _inside_gap(p, other) if mine is not None and mine.projected_gap_s is None else None
    if inside is not None:      # (a gap inside is taken at the onset: _inside_gap)
        return (f"it began to slow ({format_time(cast(int, slowing_began(other)))}) already in its conflict zone with "
                f"{p.vehicle}, and unslowed it would have left it {inside:.2f} s before {p.vehicle} came in (a gap "
                f"under {PET_MAX_S:g} s is a conflict: SUMO SSM device's PET threshold)")
    turned = turned_behind(p, other)
    if turned is not None:
        c, degrees, turn = turned
        if turn is not None:
            return (f"its own turn ({degrees:.0f}°, taken at {turn.speed_mps:.2f} m/s, from its own record): unslowed it "
                    f"would have come into their zone {c.projected_gap_s:.2f} s after {p.vehicle} had left it, and at the "
                    f"speed it took its turn it kept the two-second gap (HC 126: {FOLLOW_M:g} m + {FOLLOW_S:g} s at "
                    f"that speed) behind {p.vehicle} going on down the road it turned into")
    return f"unslowed, it would have passed {p.vehicle}'s conflict zone {PET_MAX_S:g} s or more apart from it"


_CHECKS = (_check_stopped, _check_speed, _check_light, _check_crossed_on, _check_crossed, _check_in_junction,
           _check_stopped_at_line, _check_emergency, _check_limit, _check_too_close, _check_forced)


# --- derived facts beside stated ones ---------------------------------------------------------------

_ONE_VALUE = (HAS_SPEED_OF, HAS_LIGHT, SPEED_LIMIT_IS, CROSSED_THE_STOP_LINE_ON)


def beside(derived: Iterable[DerivedFact], stated: Iterable[Any]) -> tuple[DerivedFact, ...]:
    """The derived facts that add to what producers stated: none that repeats a stated sentence,
    and none of a kind that has one value (a speed, a light, the limit, the light at the line)
    where a producer stated that kind for the same road user. A stated fact the measurements
    contradict is a finding (`checked`); one they agree with is kept in the producer's words."""
    said = {s.strip().rstrip(".").strip() for s in stated if isinstance(s, str)}
    kinds = {(i, args[0] if args else None) for s in said for i, kind in enumerate(_ONE_VALUE)
             if (args := _match(kind, s)) is not None}
    out = []
    for f in derived:
        if f.sentence in said:
            continue
        if any((args := _match(kind, f.sentence)) is not None and (i, args[0] if args else None) in kinds
               for i, kind in enumerate(_ONE_VALUE)):
            continue
        out.append(f)
    return tuple(out)
