"""Margins: how far from the line of the law a vehicle's act was, measured from its passage
(DESIGN "Margins", as quantitative monitors report robustness).

    margin(passage, action, rule=None) -> model.Margin | None

    red light (HC 176)      seconds after red the stop line was crossed ("at least" where red was
                            already showing at its signal's first report); on red-and-amber,
                            seconds into red-and-amber (TSRGD 2016 Sch 14 Pt 1 para 5(7))
    amber (HC 175)          metres from the line when amber came (with the speed, rule 126's stopping
                            distance at it, and the difference)
    Stop line (HC 171)      seconds stationary at the Stop line before crossing it, ± the sampling
                            intervals either side; where it never stood there, the slowest measured
                            speed around the line (each interval reaching from 1 m past it to 5 m
                            before it), ± down to the slowest it can have been between two samples
                            (tolerance.lowest_between): in doubt where that is a stop
    give way (HC 172)       the hardest deceleration of another road user while the vehicle passed (from
                            when it set off; none another cause explains: derived.explained), ± 2 x the
                            speed tolerance over its interval, with the threshold it is held against
                            (FORCE_DECEL_MPS2) and the conflict's measures (PET, TTC, projected gap,
                            DRAC: reasoner/conflicts.py); in doubt where the forcing rests on that
                            deceleration alone and it is within its ± of the threshold
    box junction (HC 174)   seconds stopped in the box, ± the sampling intervals either side; in doubt
                            where no still sample is still beyond the speed tolerance and inside the
                            box beyond the position tolerance
    speed limit             mph over the limit: the fastest sample of the act's own stretch over the
                            limit of the road it was on then (the stretch around the act's moment)

The rule, where given ("HC 176"), picks the quantity; without one, the action and what the passage
shows do (the light it crossed on, the junction's control). None where the passage holds nothing
to measure it by.

Every margin carries its uncertainty (reasoner/tolerance.py), from the sampling interval and the
tolerance its source states (or the defaults, which the method then says) and, where it does not
exceed it, `unproven`: why the act is not proved by it (the investigation then finds
a conviction not proven). The decisive quantity is the distance to the law's line: for red, the
seconds from the nearest lawful moment (red's onset before, green's after); for amber, the metres
beyond or short of rule 126's stopping distance; for speed, the mph over the limit.
"""
from __future__ import annotations

from typing import Callable, cast

from .conflicts import PET_MAX_S
from .derived import _course_changed, _walking, conflict_of, explained, reacting
from .reaction import FORCE_DECEL_MPS2
from .model import Margin
from .history import MAX_DECEL_MPS2, MPH_PER_MPS, STOPPED_MPS, Sample, between, xy
from .history import Passage
from .history import PAST_TOLERANCE_M, STOP_ZONE_M
from .stopping import SOURCE as RULE_126, stopping_distance_m
from .stretches import speeding_margin
from .tolerance import (beyond_stopping, deceleration, lowest_between, moment_between, place_between, sensor_of,
                        still_between)
from .verdicts import HC_171, HC_172, HC_174, HC_175, HC_176
from .when import format_time

SECOND = 1_000_000_000
SPEEDING = "exceed the speed limit"
BOX = "enter the box junction"
ToLine = Callable[[float, float], float]    # metres from a position to the Stop line (negative: past it)
BY_RULE: dict[str, str] = {HC_176: "red", HC_175: "amber", HC_171: "stop", HC_172: "give way", HC_174: "box"}


def _v(s: Sample) -> float:
    """The speed of a sample kept for having one (`s.speed_mps is not None` where it was chosen)."""
    return cast(float, s.speed_mps)


def margin(passage: Passage, action: str, rule: str | None = None, at: int | None = None) -> Margin | None:
    """The margin of `action` (e.g. "enter the junction") under `rule` (e.g. "HC 176"); `at`: the
    act's moment (a speeding act is the stretch around it)."""
    kind = _kind(passage, action, rule)
    if kind is None:
        return None
    return _speed(passage, at) if kind == "speed" else _MEASURES[kind](passage)


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
    bound = "at least" if p.first_report is not None and onset.ref == p.first_report else None
    sensor = sensor_of(p, c.moment.used[0] if c.moment.used else None)
    u = round(moment_between(c.moment.used[0], c.moment.used[-1], c.t, c.speed_mps, sensor), 3)
    since = (f"red from {'at least as early as ' if bound else ''}{format_time(onset.t)} ({onset.ref.src} "
             f"#{onset.ref.seq}{', its first report: red began at or before it' if bound else ''})")
    method = (f"crossed at {format_time(c.t)} ({c.moment.method}); {since}; ± {u:g} s ({_HOW_MOMENT}; "
              f"sensor tolerance {sensor.said})")
    doubt = "; ".join(filter(None, [c.moment.uncertain, c.light_uncertain])) or None
    figures: list[tuple[str, float, str]] = [("speed at the line", round((c.speed_mps or 0) * MPH_PER_MPS, 1), "mph")]
    quantity, value, lawful = "seconds after red the stop line was crossed", lag, lag
    if c.light.colour == "red_amber":
        into = (c.t - c.light.t) / SECOND
        green = next((x for x in p.lights if x.t > c.t and x.colour == "green"), None)
        quantity, value = "seconds into red-and-amber the stop line was crossed", into
        figures.append(("seconds after red began" + (" (at least)" if bound else ""), round(lag, 3), "s"))
        method += (f"; red-and-amber from {format_time(c.light.t)} ({c.light.ref.src} #{c.light.ref.seq}), which "
                   "conveys the prohibition of red (TSRGD 2016 Sch 14 Pt 1 para 5(7))")
        if green is not None:
            lawful = min(lag, (green.t - c.t) / SECOND)
            figures.append(("seconds before green", round((green.t - c.t) / SECOND, 3), "s"))
        bound = None if c.light.ref != p.first_report else bound
    unproven = None if lawful > u else (
        f"the crossing is {lawful:.2f} s from the nearest lawful moment, within its uncertainty of ± {u:g} s")
    if unproven and lawful == lag and _could_stop_at_amber(p):
        unproven = None          # on amber it would have been an offence too: HC 175, it could have stopped
        method += (f"; {lag:.2f} s is within ± {u:g} s of red's onset, but when amber came it could have stopped "
                   "(rule 126), so crossing on amber would have been unlawful too (HC 175)")
    return Margin(quantity, round(value, 3), "s", c.moment.refs + (onset.ref,), method, tuple(figures), doubt,
                  u, bound, unproven)


def _could_stop_at_amber(p: Passage) -> bool:
    """Whether, when the amber before the crossing came, the vehicle was beyond rule 126's
    stopping distance by more than that figure's uncertainty."""
    amber = _amber(p)
    if amber is None:
        return False
    beyond = next((v for q, v, _ in amber.figures if q == "distance beyond what stopping takes"), None)
    spread = next((v for q, v, _ in amber.figures if q == "uncertainty of that distance"), None)
    return beyond is not None and spread is not None and beyond > spread


_HOW_MOMENT = "the crossing lies between its two samples, and each position is known to within its tolerance"


def _amber(p: Passage) -> Margin | None:
    end = p.crossing.t if p.crossing else p.end
    ambers = [c for c in p.changes if c.light.colour == "amber" and c.light.t <= end and c.to_line_m is not None]
    if not ambers:
        return None
    a = ambers[-1]
    placed = [s for s in a.used if s.placed]
    sensor = sensor_of(p, a.used[0] if a.used else None)
    u_place = place_between(placed[0], placed[-1], a.light.t, sensor) if placed else None
    figures: tuple[tuple[str, float, str], ...] = ()
    u, unproven = (round(u_place, 2) if u_place is not None else None), None
    weighed = beyond_stopping(a, sensor)
    if weighed is not None and a.speed_mps is not None:     # (beyond_stopping is None without a speed)
        speed = a.speed_mps * MPH_PER_MPS
        needed = stopping_distance_m(speed)
        beyond, u_beyond = weighed[0], round(weighed[1], 2)
        figures = (("speed when amber came", round(speed, 1), "mph"),
                   ("stopping distance at that speed (rule 126)", round(needed, 1), "m"),
                   ("distance beyond what stopping takes", round(beyond, 1), "m"),
                   ("uncertainty of that distance", u_beyond, "m"))
        if abs(beyond) <= u_beyond and a.speed_mps > STOPPED_MPS:     # one standing still could stop: it had
            unproven = (f"{a.to_line_m:.2f} m from the line against {needed:.2f} m needed to stop: {beyond:+.2f} m, "
                        f"within its uncertainty of ± {u_beyond:g} m")
    method = (f"amber from {format_time(a.light.t)} ({a.light.ref.src} #{a.light.ref.seq}); {a.method}; {RULE_126}; "
              f"± the travel to the farther of the two samples and the sensors' tolerance ({sensor.said}; "
              "reasoner/tolerance.py)")
    c = p.crossing           # what the record leaves open about the light it crossed on is open here too
    doubt = "; ".join(filter(None, [c.moment.uncertain, c.light_uncertain])) or None if c else None
    return Margin("metres from the stop line when amber came", round(cast(float, a.to_line_m), 2), "m",
                  tuple(s.ref for s in a.used) + (a.light.ref,), method, figures, doubt, u, None, unproven)


def _stop(p: Passage) -> Margin | None:
    if p.line is None:
        return None
    end = p.crossing.t if p.crossing else p.end
    stops = [s for s in p.standstills if s.at_line and s.first.t <= end]
    if not stops:
        return _rolled(p, p.line.to_line, end)
    s = max(stops, key=lambda s: s.duration_s)
    u = round(still_between(s, p.samples), 3)
    return Margin("seconds stationary at the Stop line", round(s.duration_s, 3), "s", (s.first.ref, s.last.ref),
                  f"{s.samples} samples below 0.5 mph from {s.first.label} to {s.last.label}, {s.to_line_m:.1f} m "
                  f"before the line (a lower bound: between the first and the last of them; ± {u:g} s: it may have "
                  "stood from the sample before the first to the one after the last)" + _second_limb(p),
                  uncertainty=u, bound="at least")


def _rolled(p: Passage, to_line: ToLine, end: int) -> Margin:
    """A vehicle that never stood at its Stop line: the slowest it was measured before the line,
    and whether the record rules out a stop between two samples (tolerance.lowest_between, with the
    speed tolerance its source states). Para 1 asks it to stop; the prosecution must prove it did
    not, so a stop the samples cannot exclude leaves the act unproven."""
    placed = [s for s in p.samples if s.speed_mps is not None and s.placed]
    sensor = sensor_of(p, placed[0] if placed else None)
    timed = [s for s in placed if s.t <= end]
    for s in placed[len(timed):]:       # past the line by no more than its position tolerance: may be on it
        if to_line(*xy(s)) < -sensor.position_m:
            break
        timed.append(s)
    pairs = [(a, b) for a, b in zip(timed, timed[1:]) if _at_line(to_line, a, b)]
    refs = p.crossing.moment.refs if p.crossing else ()
    if not pairs:
        doubt = next((n for n in p.uncertain if "could have stopped unseen" in n), None)
        return Margin("seconds stationary at the Stop line", 0.0, "s", refs,
                      "no sample at the line below 0.5 mph before the crossing", (), doubt)
    slowest = min((s for pair in pairs for s in pair), key=_v)
    a, b = min(pairs, key=lambda ab: lowest_between(ab[0], ab[1], sensor))
    lowest = lowest_between(a, b, sensor)
    value = round(_v(slowest) * MPH_PER_MPS, 2)
    u = round(value - lowest * MPH_PER_MPS, 2)
    stopped = round(STOPPED_MPS * MPH_PER_MPS, 2)
    past = -to_line(*xy(slowest))
    unproven = None if lowest > STOPPED_MPS else (
        f"it was measured standing still at {slowest.label}, {past:.2f} m past the Stop line: within the position "
        f"tolerance of {sensor.position_m:g} m of it, so it may have stopped at the line"
        if _v(slowest) <= STOPPED_MPS else
        f"its slowest measured speed before the line, {value:g} mph, is within its uncertainty of ± {u:g} mph of a "
        f"stop (under {stopped:g} mph): between {a.label} ({a.speed_mps:.2f} m/s) and {b.label} ({b.speed_mps:.2f} "
        f"m/s), {(b.t - a.t) / SECOND:g} s apart, it could have stood still unseen")
    figures = (("speed at the line", round((p.crossing.speed_mps or 0) * MPH_PER_MPS, 1), "mph"),) if p.crossing else ()
    return Margin("slowest measured speed before the Stop line", value, "mph", (slowest.ref, a.ref, b.ref) + refs,
                  f"{slowest.label}, the slowest of the {len({s for pair in pairs for s in pair})} samples around the "
                  f"line before it crossed (each interval that reaches from {PAST_TOLERANCE_M:g} m past it to "
                  f"{STOP_ZONE_M:g} m before it, where a stop is at the line; a sample past it by no more than the "
                  "position tolerance may be on it), none below 0.5 mph before the line; ± down to the slowest it "
                  f"can have been between two of them, braking and pulling away at {MAX_DECEL_MPS2:g} m/s², each speed "
                  f"less its tolerance ({sensor.said}): {lowest * MPH_PER_MPS:.2f} mph between {a.label} and "
                  f"{b.label}" + _second_limb(p),
                  figures, None, u, None, unproven)


def _at_line(to_line: ToLine, a: Sample, b: Sample) -> bool:
    """Whether the way between two samples reaches the stretch where a stop is a stop at the line
    (from PAST_TOLERANCE_M past it to STOP_ZONE_M before it: rebuild's standstill "at the line")."""
    da, db = to_line(*xy(a)), to_line(*xy(b))
    return min(da, db) <= STOP_ZONE_M and max(da, db) >= -PAST_TOLERANCE_M


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
    braked = [(o, o.braking) for o in reacting(p) if o.braking is not None and not explained(p, o) and not _walking(o)]
    if not braked:
        return None
    o, b = max(braked, key=lambda ob: ob[1].decel_mps2)
    sensor = sensor_of(p, b.first)
    u = round(deceleration(b, sensor), 2)
    span = (b.last.t - b.first.t) / SECOND
    unproven = None
    if _forced_only_within(p, o, u):
        unproven = (f"{o.user}'s deceleration, {b.decel_mps2:.2f} m/s², is within its uncertainty of ± {u:g} m/s² of "
                    f"the {FORCE_DECEL_MPS2:g} m/s² from which a change of speed counts as forced, and nothing else "
                    "measured shows a road user forced or endangered")
    return Margin("deceleration of the other road user", round(b.decel_mps2, 2), "m/s²", (b.first.ref, b.last.ref),
                  f"{o.user}: {b.first.speed_mps:.1f} m/s at {b.first.label} to {b.last.speed_mps:.1f} m/s at "
                  f"{b.last.label}, while {p.vehicle} passed; a change of speed counts as forced from "
                  f"FORCE_DECEL_MPS2 = {FORCE_DECEL_MPS2:g} m/s² (Hupfer 1997); ± {u:g} m/s²: each speed to within its "
                  f"tolerance ({sensor.said}), so the drop to within twice that over the {span:g} s between them (the "
                  "moments are the producer's clock; a harder peak between the samples is not recorded and not "
                  "assumed: the sampling can hide a harder braking, never make a softer one look harder)",
                  (("its closest to the centre", round(o.closest_m, 1), "m"), *_conflict_figures(p, o)),
                  uncertainty=u, unproven=unproven)


def _forced_only_within(p: Passage, hardest, u: float) -> bool:
    """Whether the only measured ground for "would force" or "would endanger" is a braking at
    FORCE_DECEL_MPS2 or more that lies within its uncertainty of it: then the deciding fact is in
    doubt. Another road user that came to a stop, changed course, braked beyond doubt, or a
    pedestrian or cyclist in or entering the path, proves the act whatever this braking shows."""
    from .derived import _entering
    doubtful = False
    for o in reacting(p):
        if explained(p, o):
            continue
        if (_walking(o) or o.type == "cyclist") and _entering(p, o) is not None:
            return False
        if _walking(o):
            continue
        if o.stopped is not None or _course_changed(p, o) is not None:
            return False
        b = o.braking
        if b is None or b.decel_mps2 < FORCE_DECEL_MPS2:
            continue
        spread = u if o is hardest else deceleration(b, sensor_of(p, b.first))
        if b.decel_mps2 - spread > FORCE_DECEL_MPS2:
            return False
        doubtful = True
    return doubtful


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
    inside = [s for s in p.samples if s.placed and s.speed_mps is not None and p.junction.in_box(*xy(s))]
    still = [s for s in inside if _v(s) <= STOPPED_MPS]
    if not still:
        return None
    sensor = sensor_of(p, still[0])
    timed = [s.t for s in p.samples if s.speed_mps is not None]
    before = max((t for t in timed if t < still[0].t), default=still[0].t)
    after = min((t for t in timed if t > still[-1].t), default=still[-1].t)
    u = round((still[0].t - before + after - still[-1].t) / SECOND, 3)
    best = max(still, key=lambda s: (_v(s) + sensor.speed_mps <= STOPPED_MPS and _depth(p, s) > sensor.position_m,
                                     -_v(s), _depth(p, s)))
    depth = _depth(p, best)
    unproven = None
    if _v(best) + sensor.speed_mps > STOPPED_MPS or depth <= sensor.position_m:
        unproven = (f"no sample shows it still in the box beyond the sensors' tolerance: the best, {best.label}, "
                    f"{best.speed_mps:.2f} m/s (± {sensor.speed_mps:g}; still is under {STOPPED_MPS:.2f} m/s) "
                    f"{depth:.2f} m inside the box's edge (± {sensor.position_m:g} m)")
    return Margin("seconds stopped in the box junction", round((still[-1].t - still[0].t) / SECOND, 3), "s",
                  (still[0].ref, still[-1].ref), f"{len(still)} samples in the box below 0.5 mph, from "
                  f"{still[0].label} to {still[-1].label} (a lower bound; ± {u:g} s: it may have stood from the sample "
                  f"before the first to the one after the last); sensor tolerance {sensor.said}",
                  (("slowest speed in the box", round(_v(best) * MPH_PER_MPS, 2), "mph"),
                   ("distance inside the box's edge then", round(depth, 2), "m")),
                  uncertainty=u, bound="at least", unproven=unproven)


def _depth(p: Passage, s: Sample) -> float:
    """Metres a position lies inside the yellow box's edge (the junction's area where the box is
    the whole of it; 0 outside)."""
    j = p.junction
    if not j.in_box(*xy(s)):
        return 0.0
    if j.box is None:
        return max(0.0, -j.edge(*xy(s)))
    pts = list(j.box) + [j.box[0]]
    return min(_to_segment(*xy(s), a, b) for a, b in zip(pts, pts[1:]))


def _to_segment(x: float, y: float, a, b) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    f = 0.0 if length2 == 0 else max(0.0, min(1.0, ((x - a[0]) * dx + (y - a[1]) * dy) / length2))
    return ((x - a[0] - f * dx) ** 2 + (y - a[1] - f * dy) ** 2) ** 0.5


def _speed(p: Passage, at: int | None = None) -> Margin | None:
    """The fastest sample of the act's own stretch: the samples on the road the vehicle was on at
    the act, around it, over that road's limit (the nearest such run of samples to the act where
    it was not over at that very moment); the limit is that road's."""
    timed = sorted((s for s in p.lead + p.samples + p.trail if s.speed_mps is not None), key=lambda s: s.t)
    if not timed:
        return None
    at = at if at is not None else max(timed, key=_v).t
    road, limit, t_from, t_to = _road_at(p, at)
    if limit is None:
        return None
    on_road = [s for s in timed if t_from <= s.t < t_to]
    stretch = _stretch(on_road, at, limit) or on_road
    if not stretch:
        return None
    fastest = max(stretch, key=lambda s: s.speed_mps)
    return speeding_margin(_v(fastest), limit, (fastest.ref,) + ((p.map_ref,) if p.map_ref else ()),
                           sensor_of(p, fastest), stretch[0] is timed[0] or stretch[-1] is timed[-1],
                           f"fastest {fastest.speed_mps:.2f} m/s ({between((fastest,), fastest.t)}) of {len(stretch)} "
                           f"samples from {format_time(stretch[0].t)} to {format_time(stretch[-1].t)} on road {road}, "
                           f"against its {limit:g} mph")


def _road_at(p: Passage, at: int) -> tuple[str | None, float | None, int, int]:
    """The road the vehicle was on at `at`, its limit, and the span of time it was on it (the
    passage's approach road where the samples name none)."""
    first = p.lead[0].t if p.lead else p.start
    last = p.trail[-1].t if p.trail else p.end
    if not p.roads:
        return p.limit_road, p.limit_mph, first - SECOND, last + SECOND
    i = max((n for n, (t, _, _) in enumerate(p.roads) if t <= at), default=0)
    _, road, limit = p.roads[i]
    t_from = p.roads[i][0] if i > 0 else first - SECOND
    t_to = p.roads[i + 1][0] if i + 1 < len(p.roads) else last + SECOND
    return road, limit, t_from, t_to


def _stretch(samples: list, at: int, limit: float) -> list:
    """The run of consecutive samples over `limit` containing the act's moment, or else the one
    nearest to it in time."""
    runs: list[list] = []
    over_before = False
    for s in samples:
        over = s.speed_mps * MPH_PER_MPS > limit
        if over and over_before:
            runs[-1].append(s)
        elif over:
            runs.append([s])
        over_before = over
    if not runs:
        return []
    return min(runs, key=lambda r: 0 if r[0].t <= at <= r[-1].t else min(abs(r[0].t - at), abs(r[-1].t - at)))


_MEASURES = {"red": _red, "amber": _amber, "stop": _stop, "give way": _give_way, "box": _box, "speed": _speed}
