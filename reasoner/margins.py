"""Margins: how far from the line of the law a vehicle's act was, measured from its passage
(DESIGN "Margins", as quantitative monitors report robustness).

    margin(passage, action, rule=None) -> model.Margin | None

    red light (HC 176)      seconds after red the stop line was crossed
    amber (HC 175)          metres from the line when amber came (with the speed, rule 126's stopping
                            distance at it, and the difference)
    Stop line (HC 171)      seconds stationary at the Stop line before crossing it (0 when it never stood)
    give way (HC 172)       the hardest deceleration of another road user while the vehicle passed (from
                            when it set off; none another cause explains: derived.explained), with the
                            threshold it is held against (FORCE_DECEL_MPS2) and the conflict's measures
                            (PET, TTC, projected gap, DRAC: reasoner/conflicts.py)
    box junction (HC 174)   seconds stopped in the box
    speed limit             mph over the limit (the fastest sample of the passage)

The rule, where given ("HC 176"), picks the quantity; without one, the action and what the passage
shows do (the light it crossed on, the junction's control). None where the passage holds nothing
to measure it by.
"""
from __future__ import annotations

from .conflicts import PET_MAX_S
from .derived import _walking, conflict_of, explained, reacting
from .reaction import FORCE_DECEL_MPS2
from .model import Margin
from .motion import MPH_PER_MPS, STOPPED_MPS, between
from .passage import Passage
from .stopping import SOURCE as RULE_126, stopping_distance_m
from .when import format_time

SECOND = 1_000_000_000
SPEEDING = "exceed the speed limit"
BOX = "enter the box junction"
BY_RULE = {"HC 176": "red", "HC 175": "amber", "HC 171": "stop", "HC 172": "give way", "HC 174": "box"}


def margin(passage: Passage, action: str, rule: str | None = None) -> Margin | None:
    """The margin of `action` (e.g. "enter the junction") under `rule` (e.g. "HC 176")."""
    kind = _kind(passage, action, rule)
    return _MEASURES[kind](passage) if kind else None


def _kind(p: Passage, action: str, rule: str | None) -> str | None:
    if action == SPEEDING:
        return "speed"
    if rule is not None and rule.strip().upper() in BY_RULE:
        return BY_RULE[rule.strip().upper()]
    if action == BOX:
        return "box"
    colour = p.crossing.light.colour if p.crossing and p.crossing.light else None
    if colour in ("red", "red_amber"):
        return "red"
    if colour == "amber":
        return "amber"
    control = p.junction.control_from(p.approach)
    return {"stop": "stop", "give_way": "give way"}.get(control)


def _red(p: Passage) -> Margin | None:
    c = p.crossing
    if c is None or c.light is None or c.light.colour not in ("red", "red_amber"):
        return None
    onset = c.light
    for light in reversed([x for x in p.lights if x.t <= c.light.t]):
        if light.colour not in ("red", "red_amber"):
            break
        onset = light
    lag = (c.t - onset.t) / SECOND
    method = (f"crossed at {format_time(c.t)} ({c.moment.method}); red from {format_time(onset.t)} "
              f"({onset.ref.src} #{onset.ref.seq})")
    doubt = "; ".join(filter(None, [c.moment.uncertain, c.light_uncertain])) or None
    return Margin("seconds after red the stop line was crossed", round(lag, 3), "s", c.moment.refs + (onset.ref,),
                  method, (("speed at the line", round((c.speed_mps or 0) * MPH_PER_MPS, 1), "mph"),), doubt)


def _amber(p: Passage) -> Margin | None:
    end = p.crossing.t if p.crossing else p.end
    ambers = [c for c in p.changes if c.light.colour == "amber" and c.light.t <= end and c.to_line_m is not None]
    if not ambers:
        return None
    a = ambers[-1]
    figures: tuple[tuple[str, float, str], ...] = ()
    if a.speed_mps is not None:
        speed = a.speed_mps * MPH_PER_MPS
        needed = stopping_distance_m(speed)
        figures = (("speed when amber came", round(speed, 1), "mph"),
                   ("stopping distance at that speed (rule 126)", round(needed, 1), "m"),
                   ("distance beyond what stopping takes", round(a.to_line_m - needed, 1), "m"))
    method = f"amber from {format_time(a.light.t)} ({a.light.ref.src} #{a.light.ref.seq}); {a.method}; {RULE_126}"
    c = p.crossing           # what the record leaves open about the light it crossed on is open here too
    doubt = "; ".join(filter(None, [c.moment.uncertain, c.light_uncertain])) or None if c else None
    return Margin("metres from the stop line when amber came", round(a.to_line_m, 2), "m",
                  tuple(s.ref for s in a.used) + (a.light.ref,), method, figures, doubt)


def _stop(p: Passage) -> Margin | None:
    if p.line is None:
        return None
    end = p.crossing.t if p.crossing else p.end
    stops = [s for s in p.standstills if s.at_line and s.first.t <= end]
    if not stops:
        doubt = next((n for n in p.uncertain if "could have stopped unseen" in n), None)
        return Margin("seconds stationary at the Stop line", 0.0, "s", p.crossing.moment.refs if p.crossing else (),
                      "no sample at the line below 0.5 mph before the crossing", (), doubt)
    s = max(stops, key=lambda s: s.duration_s)
    return Margin("seconds stationary at the Stop line", round(s.duration_s, 3), "s", (s.first.ref, s.last.ref),
                  f"{s.samples} samples below 0.5 mph from {s.first.label} to {s.last.label}, {s.to_line_m:.1f} m "
                  "before the line (a lower bound: between the first and the last of them)" + _second_limb(p))


def _second_limb(p: Passage) -> str:
    """Para 1's second limb, in words: who was forced or endangered, or why nobody was."""
    from .derived import _entering, _forced
    if p.crossing is None and p.entered is None:
        return ""
    shown = [f for o in reacting(p) for f in (_forced(p, o), _entering(p, o) if _walking(o) or o.type == "cyclist"
                                               else None) if f is not None]
    if shown:
        return "; the second limb: " + "; ".join(f"{f.sentence} ({f.method})" for f in shown)
    return (f"; the second limb (TSRGD 2016 Sch 9 Pt 7 para 1): in the measured record no road user changed speed at {FORCE_DECEL_MPS2:g} "
            f"m/s² or more for {p.vehicle}, or came within {PET_MAX_S:g} s of it where their paths meet, and no "
            f"pedestrian or cyclist was in or entering its path within {PET_MAX_S:g} s of it (FORCE_DECEL_MPS2, "
            "Hupfer 1997; PET_MAX_S, SUMO SSM device)")


def _give_way(p: Passage) -> Margin | None:
    braked = [o for o in reacting(p) if o.braking is not None and not explained(p, o) and not _walking(o)]
    if not braked:
        return None
    o = max(braked, key=lambda o: o.braking.decel_mps2)
    b = o.braking
    return Margin("deceleration of the other road user", round(b.decel_mps2, 2), "m/s²", (b.first.ref, b.last.ref),
                  f"{o.user}: {b.first.speed_mps:.1f} m/s at {b.first.label} to {b.last.speed_mps:.1f} m/s at "
                  f"{b.last.label}, while {p.vehicle} passed; a change of speed counts as forced from "
                  f"FORCE_DECEL_MPS2 = {FORCE_DECEL_MPS2:g} m/s² (Hupfer 1997)",
                  (("its closest to the centre", round(o.closest_m, 1), "m"), *_conflict_figures(p, o)))


def _conflict_figures(p: Passage, other) -> tuple[tuple[str, float, str], ...]:
    """The measures of the road user's conflict with the vehicle, with the threshold of a conflict."""
    c = conflict_of(p, other)
    if c is None:
        return ()
    out = []
    if c.pet_s is not None:
        out.append(("post-encroachment time", round(c.pet_s, 2), "s"))
    if c.ttc_s is not None:
        out.append(("time to collision at the act", round(c.ttc_s, 2), "s"))
    if c.projected_gap_s is not None and c.projected_gap_s != float("inf"):
        out.append(("gap had it not slowed (a conflict under PET_MAX_S = %g s, SUMO SSM)" % PET_MAX_S,
                    round(c.projected_gap_s, 2), "s"))
    if c.drac_mps2 is not None:
        out.append(("deceleration it needed (DRAC)", round(c.drac_mps2, 2), "m/s²"))
    return tuple(out)


def _box(p: Passage) -> Margin | None:
    inside = [s for s in p.samples if s.placed and s.speed_mps is not None and p.junction.in_box(s.x, s.y)]
    still = [s for s in inside if s.speed_mps <= STOPPED_MPS]
    if not still:
        return None
    return Margin("seconds stopped in the box junction", round((still[-1].t - still[0].t) / SECOND, 3), "s",
                  (still[0].ref, still[-1].ref), f"{len(still)} samples in the box below 0.5 mph, from "
                  f"{still[0].label} to {still[-1].label}")


def _speed(p: Passage) -> Margin | None:
    timed = [s for s in p.samples if s.speed_mps is not None]
    if not timed or p.limit_mph is None:
        return None
    fastest = max(timed, key=lambda s: s.speed_mps)
    over = round(fastest.speed_mps * MPH_PER_MPS - p.limit_mph, 1) or 0.0    # never "-0"
    return Margin("mph over the speed limit", over, "mph", (fastest.ref,) + ((p.map_ref,) if p.map_ref else ()),
                  f"fastest {fastest.speed_mps:.2f} m/s ({between((fastest,), fastest.t)}) against road "
                  f"{p.limit_road}'s {p.limit_mph:g} mph")


_MEASURES = {"red": _red, "amber": _amber, "stop": _stop, "give way": _give_way, "box": _box, "speed": _speed}
