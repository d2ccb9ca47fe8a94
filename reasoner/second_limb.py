"""Why the second limb does not reach a road user, from the measurements (issue 35).

For each road user about the vehicle V's act (`derived.reacting`: near V's passage, its braking
counted from when V set off), this gives what the record shows and why V did not force or
endanger it. It asks the same questions the derived facts are decided by, and only those:
`derived._forced` and `derived._entering` say whether the limb applies, and `derived.explained`
says whether something else explains a braking. It decides nothing itself. The reasons are
named in the order `explained` weighs them: a cause of the road user's own (its light, its Stop
or Give Way line, the road user it followed), paths that never met, slowing begun too late to be
for V, V well ahead of it, a conflict zone it would have passed well apart from V anyway, a zone
it had already gone through, its leader, another road user whose conflict came first on its way,
its own turn (behind V, or ahead of V with V coming in behind it).
For a braking nothing else explains, the reason is that it does not exceed FORCE_DECEL_MPS2 by
more than its uncertainty. For one that did not brake, stop or swerve at all, the reason is that
it changed neither speed nor course. A reason `explained` holds that none of these names is
"other": something else the record shows.

The figures come from the record: where the road user was and how fast at V's act, its hardest
braking with its ± (reasoner/tolerance.py), and the post-encroachment time and unslowed gap
where their paths meet (reasoner/conflicts.py). The words cite the threshold each is held
against.
"""
from __future__ import annotations

from typing import cast

from .attribution import joined_behind, leader
from .derived import (ENDANGER_S, _clear_of, _entering, _extend, _forced, _line_no_excuse, _nearer, _out_first,
                      _set_off_t, _walking, conflict_of, conflict_words, explained, reacting, stood_on,
                      turned_ahead, turned_behind)
from .history import position_at, speed_at
from .history import FOLLOW_M, FOLLOW_S, VEHICLE_WIDTH_M, own_cause, paths_within
from .history import Other, Passage
from .reaction import FORCE_DECEL_MPS2, REACTION_TIME_S, SAME_WAY_DEG, reacted_after_clearing, slowing_began, well_ahead
from .tolerance import deceleration, sensor_of
from .unforced import Unforced
from .when import format_time

__all__ = ["second_limb"]


def second_limb(p: Passage) -> tuple[Unforced, ...]:
    """The road users about V's act (its crossing of its line, else its entry into the junction)
    that V neither forced nor endangered, each with its figures and the reason. Empty where the
    passage has no act."""
    act = p.crossing.t if p.crossing else p.entered.t if p.entered else None
    if act is None:
        return ()
    out = []
    for o in reacting(p):
        if o.user == p.vehicle:
            continue
        walker = _walking(o) or o.type == "cyclist"
        if (walker and _entering(p, o) is not None) or (not _walking(o) and _forced(p, o) is not None):
            continue                                    # the limb reaches it: not this module's to clear
        out.append(_cleared(p, o, act, walker))
    return tuple(out)


def _cleared(p: Passage, o: Other, act: int, walker: bool) -> Unforced:
    v, j = p.vehicle, p.junction
    where, used = position_at(o.samples, act)
    speed, used_speed = speed_at(o.samples, act)
    distance = j.distance(*where) if where is not None else None
    b = o.braking
    u = deceleration(b, sensor_of(p, b.first)) if b is not None else None
    c = conflict_of(p, o)
    moment = "crossed its line" if p.crossing else "entered the junction"
    said = [f"{o.user}{f' ({o.type})' if o.type else ''} was "
            + (f"{distance:.1f} m from the centre of {j.id}" if distance is not None else "not placed in the record")
            + (f" at {speed:.1f} m/s" if speed is not None else "") + f" when {v} {moment} ({format_time(act)})"]
    if b is not None:
        said.append(f"its hardest braking while {v} passed was {b.decel_mps2:.1f} ± {u:.1f} m/s² "
                    f"({b.first.speed_mps:.1f} m/s at {b.first.label} to {b.last.speed_mps:.1f} m/s at {b.last.label})")
    elif not walker:
        said.append(f"it did not brake while {v} passed")
    if o.stopped is not None:
        said.append(f"it came to a stop ({o.stopped.label}, {format_time(o.stopped.t)})")
    reason, why = _walker_reason(p, o) if walker and _walking(o) else _reason(p, o)
    if walker and not _walking(o) and _entering(p, o) is None and reason != "own control":
        why += f"; nor was it in or entering {v}'s path within {ENDANGER_S:g} s of {v} being there"
    words = "; ".join(said) + conflict_words(p, o.user, c) + f": not {'endangered' if _walking(o) else 'forced'} " \
        f"by {v}, because {why}"
    refs = tuple(s.ref for s in (*used, *used_speed)) + ((b.first.ref, b.last.ref) if b is not None else ()) \
        + ((o.stopped.ref,) if o.stopped is not None else ())
    return Unforced(v, o.user, o.type, reason, words, _r(distance, 1), _r(speed, 2),
                    _r(b.decel_mps2 if b is not None else None, 2), _r(u, 2),
                    _r(c.pet_s if c is not None else None, 2), c.first if c is not None else None,
                    _r(c.projected_gap_s if c is not None else None, 2), tuple(dict.fromkeys(refs)))


def _walker_reason(p: Passage, o: Other) -> tuple[str, str]:
    return "walking clear", (f"it was not in or entering {p.vehicle}'s path within {ENDANGER_S:g} s of {p.vehicle} "
                             "being there (SUMO SSM device's PET threshold; derived.ENDANGER_S)")


def _reason(p: Passage, o: Other) -> tuple[str, str]:
    """The first reason the record gives, in `explained`'s order, that V did not force o."""
    v = p.vehicle
    if explained(p, o):
        if own_cause(o) and not _line_no_excuse(p, o):
            if o.light is not None and o.light.colour != "green":
                return "own control", f"its own light was {o.light.colour}"
            if o.followed is not None:
                return "own control", f"it followed {o.followed}, ahead of it on its own arm"
            return "own control", "it slowed for a line of its own (its arm's Stop or Give Way line)"
        if paths_within(p.samples, o.way, p.junction, VEHICLE_WIDTH_M) is False:
            return "paths apart", f"its path never came within {VEHICLE_WIDTH_M:g} m (a vehicle's width) of {v}'s"
        if reacted_after_clearing(p.samples, o):
            return "after clearing", f"it began to slow more than a perception-reaction time after {v} was out of its way"
        if well_ahead(p.samples, o):
            return "well ahead", f"{v} was well ahead of it on its way, going its way (the two-second rule's gap kept " \
                                 f"by braking under {FORCE_DECEL_MPS2:g} m/s²)"
        if _clear_of(p, o):
            return "clear of the zone", f"unslowed it would still have passed the conflict zone 2 s or more apart " \
                                        f"from {v}: no accident to avoid"
        if _out_first(p, o, slowing_began(o)) is not None:
            return "through first", f"it had gone through the conflict zone ahead of {v} and left it before " \
                                    "it changed speed or course"
        ahead = leader(p, o, _extend(p, o), conflict_of(p, o))
        if ahead is not None:
            return "leader", f"it slowed behind its own leader {ahead}, ahead of it on its way"
        nearer = _nearer(p, o)
        if nearer is not None:
            return "nearer conflict", f"it slowed for {nearer[0].user}, whose conflict with it came first on its way"
        held = stood_on(p, o)
        if held is not None:
            c, moved = held
            left = cast(int, c.mine.left)       # stood_on holds only a conflict zone the vehicle left
            return "stood on", (f"it came to a stop only after {v} had left the zone where their paths meet "
                                f"({format_time(left)}) and moved off {(moved - left) / 1e9:.1f} s after "
                                f"{v} had left it, more than a perception-reaction time ({REACTION_TIME_S:g} s, AASHTO): "
                                f"what held it was not {v}")
        if joined_behind(p, o, conflict_of(p, o), _set_off_t(p)):
            return "joined behind", (f"it went through the zone where their paths meet ahead of {v}, which came in "
                                     f"behind it without slowing and went on along its way: braking could not keep it "
                                     f"from an accident with {v} behind it")
        turned = turned_behind(p, o)
        if turned is not None:
            c, degrees, turn = turned
            left = cast(int, c.mine.left)       # turned_behind too holds only a conflict zone the vehicle left
            behind = "" if turn is None else (
                f"; {v} went on ahead of it down the road it turned into, and at the speed it took its turn, "
                f"{turn.speed_mps:.2f} m/s (its own record, {format_time(turn.t)}), it kept the two-second gap "
                f"behind {v} ({FOLLOW_M:g} m + {FOLLOW_S:g} s at that speed, HC 126) with {v} pulling away")
            return "own turn", (f"it turned {degrees:.0f}° there (more than {SAME_WAY_DEG:g}°) and did not stop: unslowed, "
                                f"it would have come into the zone where their paths meet {c.projected_gap_s:.2f} s after "
                                f"{v} had left it ({format_time(left)}){behind}, so it slowed for its own turn, "
                                f"with no accident with {v} to avoid")
        ahead_of = turned_ahead(p, o)
        if ahead_of is not None:
            c, degrees, turn = ahead_of
            return "turned ahead", (f"it turned {degrees:.0f}° there (more than {SAME_WAY_DEG:g}°), did not stop, and "
                                    f"slowed no lower than the speed it took its turn at, {turn.speed_mps:.2f} m/s (its "
                                    f"own record, {format_time(turn.t)}); it went through the zone where their paths "
                                    f"meet ahead of {v} and left it {c.pet_s:.2f} s before {v} came in (unslowed, "
                                    f"{c.projected_gap_s:.2f} s), and {v} came in behind it without slowing and went on "
                                    f"along its way: it slowed for its own turn, and braking could not keep it from an "
                                    f"accident with {v} behind it")
        return "other", "something else the record shows explains its slowing (reasoner/derived.explained)"
    b = o.braking
    if b is not None and b.decel_mps2 >= FORCE_DECEL_MPS2:
        return "in doubt", (f"its braking, {b.decel_mps2:.1f} ± {deceleration(b, sensor_of(p, b.first)):.1f} m/s², "
                            f"does not exceed {FORCE_DECEL_MPS2:g} m/s² by more than its uncertainty: a considerable "
                            "change of speed is not proven (FORCE_DECEL_MPS2, Hupfer 1997)")
    if b is not None:
        return "no change", (f"its braking, {b.decel_mps2:.1f} ± {deceleration(b, sensor_of(p, b.first)):.1f} m/s², is "
                             f"under the {FORCE_DECEL_MPS2:g} m/s² from which a change of speed counts (FORCE_DECEL_MPS2, "
                             "Hupfer 1997), and it neither stopped nor changed course")
    return "no change", f"it neither braked at {FORCE_DECEL_MPS2:g} m/s² or more, nor stopped, nor changed course"


def _r(value: float | None, digits: int) -> float | None:
    return round(value, digits) if value is not None else None
