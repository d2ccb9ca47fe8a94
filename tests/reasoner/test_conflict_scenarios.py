"""Issue 35: forcing and endangering judged from measured conflicts, in scenarios written as a
foreign producer writes them (tests/helpers/foreign.py: positions at 2-5 Hz, core sentences
only). Each test gives the law's answer beside the motion it builds:

- TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): at a Stop line no vehicle may proceed past it "so as to
  be likely to endanger any person or to cause the driver of another vehicle to change its speed
  or course in order to avoid an accident";
- a change of speed counts from 2 m/s² (reaction.FORCE_DECEL_MPS2, Hupfer 1997), and is made "to
  avoid an accident" with the vehicle only where, unslowed, the other would have come within 2 s
  of it where their paths meet (conflicts.PET_MAX_S, SUMO's SSM device default PET threshold);
- a pedestrian is endangered when in or entering the vehicle's path within 2 s of it
  (derived.ENDANGER_S), not for walking towards the junction.

The shared Stop-line run: 7 stops at the west Stop line (major road north-south), waits 2 s and
pulls away at 2 m/s², going straight on east along y = +1.75 (test_foreign_scenarios).
"""
from __future__ import annotations

import math
import re

from tests.helpers.foreign import LINE_M, Foreign, Motion, crossroads, ns, rate
from tests.reasoner.test_foreign_scenarios import (AMBULANCE_LAG, START, STOPS_THEN_GOES, _OUT_OF_C2S_WAY, _SET_OFF,
                                                   judge, margin, mps, no_violation, of, one, runner_run,
                                                   stated_stop_camera, stop_then_go_run, unseen_main_road_run, verdict)


def walk(run: Foreign, who: str, start: tuple[float, float], velocity: tuple[float, float], until: float,
         *, watched: bool = False) -> None:
    """A pedestrian's own positions at 2 Hz, walking straight at a constant velocity from START;
    `watched`: the camera m1 measures it too (its x, y and speed at 5 Hz), as it measures vehicles."""
    run.spawn(who, "pedestrian", role="pedestrian")
    speed = math.hypot(*velocity)
    heading = math.degrees(math.atan2(velocity[1], velocity[0])) % 360.0
    for at in rate(2, START, until):
        dt = at - START
        run.emit(f"pedestrian/{who}", ns(at), "entity.state",
                 {"x": round(start[0] + velocity[0] * dt, 3), "y": round(start[1] + velocity[1] * dt, 3),
                  "heading_deg": heading, "speed_mps": round(speed, 3)})
    for at in rate(5, START, until) if watched else ():
        dt = at - START
        run.emit("monitor/m1", ns(at), "monitor.observation",
                 {"vehicle": who, "facts": [], "speed_mps": round(speed, 3),
                  "x": round(start[0] + velocity[0] * dt, 3), "y": round(start[1] + velocity[1] * dt, 3)})


def _passage_of_7(run: Foreign):
    """7's passage that crosses its line, as the reasoner reads it from the run's events."""
    from reasoner import history

    return next(p for p in history.from_events(run.events, "7") if p.crossing is not None)


def _second_limb_of_7(run: Foreign):
    """Each road user's reason in the second limb of 7's act (reasoner.second_limb): what the
    explanation says of why it was, or was not, forced."""
    from reasoner.second_limb import second_limb

    return second_limb(_passage_of_7(run))


def _lawful_not_forcing_c2(path, run: Foreign):
    """The run judged: 7's act is no violation and nothing of 7's says it forced c2."""
    found = judge(path, run)
    assert not any("would force c2" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")
    return found


def _punishable_forcing_c2(path, run: Foreign, v: str = "7"):
    """The run judged: v's one incident is punishable under HC 171 for forcing c2."""
    inc = one(judge(path, run), v)
    verdict(inc, "punishable", "HC 171")
    assert any(f.sentence == f"{v} would force c2 to change speed or course" for f in inc.derived)
    return inc


# 7 is at x = 8 (its exit, beyond the junction) 4.5 s after setting off (s = t² - 12.5 from its line); s from START
_AT_X8 = _SET_OFF + math.sqrt(12.5 + 8.0)


def test_a_lawful_stop_with_traffic_far_away_and_a_pedestrian_on_the_far_footway_is_no_offence(tmp_path):
    """7 stops at its Stop line, waits and pulls out, watched by a camera down its own (west) arm
    that states its sign and its stop (the main road is in no camera's view, so the act is looked
    at from the road users' own records); the main road's c2 is 250 m off and keeps its speed; p9
    walks west along the far (south) footway of the east arm, 8 m from the lane 7 leaves by, towards
    the junction, and never comes near 7's path. Nobody changed speed and nobody was in or entering
    7's path: para 1's second limb does not apply, and the Stop is lawful (the demo's vehicle 134;
    on main p9 "approaching" within 50 m made it a £100 offence). The camera flags 7 on line with
    "p9 is approaching 7": weighed against p9's own record, that reading shows no danger."""
    run = unseen_main_road_run("stop", STOPS_THEN_GOES, stated_stop_camera())
    run.drive("c2", Motion(-251.0, 13.4), "north", rate(5, START, START + 25.0), t_start=START)
    walk(run, "p9", (40.0, -6.5), (-1.4, 0.0), START + 25.0)
    # the camera flags 7 on line, on what it saw: its sign, over the line, a pedestrian coming
    run.violation("7", START + _SET_OFF + 1.0, "enter the junction",
                  ["7 has a stop sign", "7 has crossed the stop line", "p9 is approaching 7", "p9 is of type pedestrian"])
    found = judge(tmp_path, run)
    assert of(found, "7"), "the camera's flag is judged"
    no_violation(found, "7")
    assert not any("p9 is approaching 7" in f.sentence or "endanger" in f.sentence
                   for i in of(found, "7") for f in i.derived)
    stop = next((i for i in of(found, "7")), None)
    if stop is not None and stop.margin is not None:       # the Stop's margin says why no second limb applies
        assert "no road user changed speed" in stop.margin.method


def test_a_pedestrian_stepping_into_the_path_as_the_vehicle_pulls_out_is_endangered():
    """The control: p9 walks north across 7's exit (x = +8) and reaches 7's lane as 7 gets there:
    in 7's path as it comes, likely to be endangered (para 1): the passage shows "7 would endanger
    p9", with the pedestrian named and the post-encroachment time measured. (Judged at the
    sentence: no camera sentence nor sweep candidate raises a Stop that was kept; see the report.)"""
    from reasoner import derived

    run = stop_then_go_run()
    walk(run, "p9", (8.0, 1.75 - 1.4 * _AT_X8), (0.0, 1.4), START + 25.0)
    p = _passage_of_7(run)
    shown = {f.sentence: f for f in derived.facts(p, p.crossing.t)}
    assert "7 would endanger p9" in shown and "p9 is approaching 7" in shown
    method = shown["7 would endanger p9"].method
    assert "in or entering 7's path" in method and "post-encroachment time 0.00 s" in method


def test_a_main_road_car_slowing_for_its_own_turn_well_clear_of_the_conflict_zone_was_not_forced(tmp_path):
    """c2 on the main road begins to slow at 3 m/s² to 6 m/s (for a turn of its own) 1 s after 7 is
    out of its lane, 40 m from the centre: within a perception-reaction time (so main's reaction
    test did not clear it) but, unslowed, it would have reached the zone where their paths meet
    more than 3 s after 7 had left it: no accident to avoid, so not caused by 7 to change speed.
    A lawful Stop: no violation, no sentence that 7 forced c2 (issue 35's car slowing for its own
    turn, 2.9 s or more clear of the conflict point)."""
    begins = _OUT_OF_C2S_WAY + 1.0
    c2 = Motion(-40.0 - 13.4 * begins, 13.4, [(begins, 0.0), ((13.4 - 6.0) / 3.0, -3.0)])
    found = judge(tmp_path, stop_then_go_run(("c2", c2, "north")))
    assert not any("would force c2" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_main_road_braking_for_a_later_emerger_is_not_blamed_on_the_first(tmp_path):
    """7 stops and pulls out; 2 s after 7 is out of c2's lane, 8 rolls out of the opposite (east)
    Stop line without stopping, across c2's lane, and c2 (12.5 m from the centre) brakes at 5 m/s²
    to a stop for it. Unslowed, c2 would have passed 7's conflict zone more than 2 s after 7 left it:
    c2 braked for 8, not 7. 7: no violation (a lawful Stop); 8: a Stop-line run, punishable HC 171."""
    begins = _OUT_OF_C2S_WAY + 2.0
    c2 = Motion(-12.5 - 13.4 * begins, 13.4, [(begins, 0.0), (13.4 / 5.0, -5.0), (6.0, 0.0)])
    # 8 from the east along y = -1.75 at 6 m/s, its centre on c2's lane (x = +1.75, s = -1.75) 0.8 s
    # after c2 began to brake: where c2, unslowed, would have been then
    eight = Motion(-1.75 - 6.0 * (begins + 0.8), 6.0)
    run = stop_then_go_run(("c2", c2, "north"), ("8", eight, "east"))
    found = judge(tmp_path, run)
    assert not any("7 would force c2" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")
    assert any(i.verdict == "punishable" and i.rule == "HC 171" for i in of(found, "8"))


def test_a_camera_saying_a_pedestrian_on_the_far_footway_approaches_an_ambulance_is_weighed_against_its_path(tmp_path):
    """TSRGD 2016 Sch 14 Pt 1 para 5(5): an ambulance on a call may cross red, but not "in such a
    manner or at such a time as to be likely to endanger any person". 253 crosses 2 s after red at
    28 mph; the camera states "p1 is approaching 253" and "p1 is of type pedestrian" of p1, whose
    own record and the camera's measurements show it walking along the far (south) footway, 6.5 m
    from 253's lane, never in or entering its path. The camera's sentence is a reading of p1 near the junction; p1's record
    shows no danger: mitigated, HC 176, with the contradiction found. (Where nothing of p1 is
    measured, the same sentence stands alone and is punishable: test_foreign_scenarios'
    test_emergency_vehicle_with_a_pedestrian_stated_approaching_by_the_camera.)"""
    v = "253"
    run, _, crossing, _ = runner_run(v, mps(28), AMBULANCE_LAG, "5 Hz", "camera", type="ambulance", emergency=True,
                                     also=(f"p1 is approaching {v}", "p1 is of type pedestrian"))
    walk(run, "p1", (-25.0, -6.5), (1.4, 0.0), crossing + 8.0, watched=True)
    inc = one(judge(tmp_path, run), v)
    verdict(inc, "mitigated", "HC 176")
    said = [f for f in inc.findings if f.kind == "contradiction" and "p1 is approaching 253" in f.detail]
    assert said and "never in or entering 253's path" in said[0].detail


def test_the_headline_names_the_ground_the_verdict_rests_on(tmp_path):
    """7 stops and pulls out; c2 on the main road brakes at 5 m/s² from 0.9 s after 7 crossed its
    line (forced, para 1), and p9 steps into 7's exit as 7 gets there (endangered, para 1). The
    Stop is raised by the monitor rules on one limb and punished by the validator's prohibition on
    whichever it proves; the explanation's first sentence names that one, with its measured figures
    in the derived facts (issue 35: "the headline ground is the deciding ground")."""
    from explain.explanation_doc import document
    from explain.explanation_formats import render
    from reasoner.investigation import Investigation
    from store import Store

    c2 = Motion(-164.0, 13.4, [(_SET_OFF + 0.9 + 0.71, 0.0), (13.4 / 5.0, -5.0), (4.0, 0.0), (8.0, 2.0)])
    run = stop_then_go_run(("c2", c2, "north"))
    walk(run, "p9", (8.0, 1.75 - 1.4 * _AT_X8), (0.0, 1.4), START + 25.0, watched=True)
    run.end(START + 26.0)
    with Store(tmp_path / "s.db") as store:
        store.append(run.events)
        inv = Investigation(store)
        (inc,) = [i for i in inv.incidents(run.run) if i.vehicle == "7"]
        verdict(inc, "punishable", "HC 171")
        text = render(document(inc, inv.explanation(inc), store), "text", "standard")
    headline = text.split("\n\n")[0].replace("\n", " ")
    prohibition = next(line for line in text.splitlines() if "must not enter the junction [HC 171" in line)
    grounds = text[text.index(prohibition):].splitlines()[1:4]
    deciding = next(g for g in grounds if "would force" in g or "would endanger" in g).strip()
    deciding = deciding.removeprefix("and ").split(" [")[0]
    assert deciding in headline, (headline, deciding)


def test_a_main_road_car_braking_hard_inside_the_junction_as_the_vehicle_pulls_out_was_forced(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): no vehicle may proceed past a Stop line "so as to ...
    cause the driver of another vehicle to change its speed or course in order to avoid an
    accident". 7 stops at its Stop line and pulls out; c2 comes down the main road from the north at
    9 m/s, and only once it is inside the junction (11.5 m from the centre, the junction's area
    reaching to the stop lines at 12 m) does it brake, at 6.5 m/s² for 1.1 s, to a crawl
    (1.85 m/s) short of 7's path while 7 crosses in front of it, then goes on; unslowed, c2 would
    have been where their paths meet while 7 was (the simulation's 241 braking at 4.5 m/s² in j2
    as 237 came out of its Give Way line, a braking SUMO's account puts down to 237). A change of
    speed to avoid an accident, wherever it began: punishable, HC 171, naming c2. (Counting
    braking only outside the junction, c2's record showed none, no stop either, and the Stop was
    lawful.)"""
    begins = _SET_OFF + 2.2                                  # c2 at s = -11.5 (y = +11.5), inside the junction
    c2 = Motion(-11.5 - 9.0 * begins, 9.0, [(begins, 0.0), (1.1, -6.5), (1.5, 0.0), (6.0, 2.0)])
    found = judge(tmp_path, stop_then_go_run(("c2", c2, "north")))
    inc = one(found, "7")
    verdict(inc, "punishable", "HC 171")
    forced = [f for f in inc.derived if f.sentence == "7 would force c2 to change speed or course"]
    braked = re.search(r"c2 braked at (\d+\.\d)(?: ± \d+\.\d)? m/s²", forced[0].method) if forced else None
    assert braked and float(braked[1]) >= 5.0, [f.method for f in forced]


def test_a_kept_stop_that_pulls_out_as_a_pedestrian_steps_into_its_path_is_judged_and_punishable(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1: no vehicle may proceed past a Stop line "so as to be likely to
    endanger any person"; having stopped does not excuse it. 7 stops at its line, waits and pulls
    out, watched by a camera that sees the whole junction and writes 7's sign, its measurements and,
    once it has stood, "7 has stopped at the stop line" (no sentence about anyone else); nobody brakes; p9 walks north across 7's exit and is in 7's lane
    as 7 gets there (post-encroachment time 0: both where their paths meet at once), measured by
    the camera and in its own record. No sentence raises the act, nor braking on the main road: the sweep of the
    measurements must (a pedestrian in the junction's area as 7 entered it), and the history shows
    "7 would endanger p9": punishable, HC 171 (the simulation's kept Stops with a pedestrian on a
    crossing of their path that raised no incident at all). The far-footway pedestrian of
    test_a_lawful_stop_with_traffic_far_away... raises the same candidate and is no offence."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop", "east": "stop"})])
    run.spawn("7")
    run.drive("7", STOPS_THEN_GOES, "west", rate(5, START, START + 25.0), t_start=START)
    run.watch("7", STOPS_THEN_GOES, "west", rate(5, START, START + 25.0), t_start=START, facts=stated_stop_camera())
    walk(run, "p9", (8.0, 1.75 - 1.4 * _AT_X8), (0.0, 1.4), START + 25.0, watched=True)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    assert any(f.sentence == "7 would endanger p9" for f in inc.derived)


def test_a_cyclist_braking_behind_the_vehicle_on_its_own_approach_was_not_forced(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 asks whether 7, proceeding past its Stop line, caused the
    driver of another vehicle to change speed or course "in order to avoid an accident" with it;
    HC 126 leaves the gap to the vehicle in front to the one behind. cy rides up 7's own (west)
    arm at 6 m/s behind it and brakes at 3 m/s² to a stand 6.5 m behind 7 while 7 waits at its
    line, then waits there: a change of speed behind its leader on its own way, not one 7's
    crossing caused (SUMO's account of such a pair: a leader that did not join its road, its SSM
    device "following"). A lawful Stop: no violation, and cy is not said to be forced."""
    run = stop_then_go_run()
    run.spawn("cy", "cyclist")
    cy = Motion(-60.0, 6.0, [(5.83, 0.0), (2.0, -3.0)])
    run.drive("cy", cy, "west", rate(5, START, START + 25.0), t_start=START)
    run.watch("cy", cy, "west", rate(5, START, START + 25.0), t_start=START)
    found = judge(tmp_path, run)
    assert not any("force cy" in f.sentence or "endanger cy" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_a_give_way_pull_out_making_a_main_road_car_stop_inside_the_junction_is_punishable(tmp_path):
    """HC 172 (RTA 1988 s.36, TSRGD 2016 Sch 9 Pts 7 and 8): at a Give Way line, give way to traffic
    on the major road. 7 waits at its Give Way line (west arm) and pulls out while c2, on the main
    road, is already inside the junction (11 m from the centre at 4 m/s as 7 crosses its line);
    c2 brakes at 4 m/s² to a stand short of 7's path and waits while 7 crosses in front of it.
    c2 was traffic on the major road coming through the junction 7 came out into: punishable,
    HC 172 (the town's 265 and 386, 543 and 124: "V would force U" shown, but U, inside the
    junction, was never read as approaching V, which the Give Way rule asks: no incident)."""
    c2 = Motion(-11.0 - 4.0 * (_SET_OFF + 0.7), 4.0, [(_SET_OFF + 1.5, 0.0), (1.0, -4.0), (2.0, 0.0), (6.0, 2.0)])
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds={"west": "give_way", "east": "give_way"})])
    run.spawn("7")
    run.drive("7", STOPS_THEN_GOES, "west", rate(5, START, START + 25.0), t_start=START)
    run.watch("7", STOPS_THEN_GOES, "west", rate(5, START, START + 25.0), t_start=START,
              facts=["7 has a give way sign"])
    run.spawn("c2")
    run.drive("c2", c2, "north", rate(5, START, START + 25.0), t_start=START)
    run.watch("c2", c2, "north", rate(5, START, START + 25.0), t_start=START)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 172")
    assert any(f.sentence == "c2 is approaching 7" for f in inc.derived)


def test_a_pedestrian_who_crossed_in_front_of_a_car_waiting_at_its_line_and_left_its_path_was_not_endangered():
    """HC 170 and 172, TSRGD 2016 Sch 9 Pt 7 para 1: a vehicle endangers a pedestrian only where
    the pedestrian is in or entering its path within 2 s of it being there (derived.ENDANGER_S),
    and positions are the road user's front (DESIGN: entity.state). 7 waits 6 s at its Give Way
    line (west arm), its front 12.5 m from the centre; p9 walks north at 1.8 m/s across 7's arm 1.7 m ahead of
    7's front and is out of 7's lane 0.3 s before 7 moves off: 7 waited for it and followed it
    over, its front reaching p9's way about 1.5 s after p9 had left 7's. p9 was never in 7's path
    with 7 there, nor entering it after 7 had passed: not endangered (the paper run's 249 and p9,
    where a car standing at its line, its front short of the pedestrian's way, was read as in
    the zone with it: post-encroachment time 0, "249 would endanger p9")."""
    from reasoner import derived

    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds={"west": "give_way", "east": "give_way"})])
    run.spawn("7")
    waits = Motion.stopping_at(-40.0, 8.0, -LINE_M - 0.5, wait=6.0, then=10.0)   # stands 6.87 to 12.87 s
    run.drive("7", waits, "west", rate(5, START, START + 25.0), t_start=START)
    run.watch("7", waits, "west", rate(5, START, START + 25.0), t_start=START, facts=["7 has a give way sign"])
    # p9's centre leaves 7's swept lane (y 0.475 to 3.025, a 2.55 m vehicle on y = 1.75) with its
    # half width and half its length (0.24 + 0.11 m) at y = 3.135, 0.3 s before 7 sets off
    leaves = 6.87 + 6.0 - 0.3
    walk(run, "p9", (-10.8, 3.135 - 1.8 * leaves), (0.0, 1.8), START + 25.0, watched=True)
    p = _passage_of_7(run)
    shown = {f.sentence for f in derived.facts(p, p.crossing.t)}
    assert "7 would endanger p9" not in shown and "p9 is approaching 7" not in shown, shown


def test_two_emergers_each_on_a_collision_course_with_the_main_road_car_both_forced_it(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1: no vehicle may proceed past a Stop line "so as to be likely ...
    to cause the driver of another vehicle to change its speed or course in order to avoid an
    accident"; another driver doing the same at the same moment does not excuse it. 7 stops and
    pulls out east (y = +1.75); 8 rolls west out of the opposite Stop line at 6 m/s without
    stopping (y = -1.75). c2 comes north up the main road (x = -1.75) at 13.4 m/s and brakes at
    5 m/s² to a stop 1.7 s after 7 set off: unslowed, it would have been in 8's zone (first on its
    way, 3.5 m before 7's) with 8 and in 7's zone with 7 (both its projected gaps below 0). Each
    pull-out on its own made c2 brake to avoid an accident: 7 and 8 are each punishable, HC 171,
    each with "would force c2" (the paper run's 236, which stopped as 298 and 182 came out of their
    lines together; SUMO's account says it braked for 182, which the first conflict on its way,
    298's, had excused)."""
    meets_8 = _SET_OFF + 3.19              # unslowed, c2's front on 8's path (y = -1.75) then, on 7's 0.26 s later,
    begins = _SET_OFF + 1.68               # while 7 is in their zone (3.08 to 3.81 s after it set off)
    c2 = Motion(-1.75 - 13.4 * meets_8, 13.4, [(begins, 0.0), (13.4 / 5.0, -5.0), (6.0, 0.0)])
    eight = Motion(1.75 - 6.0 * meets_8, 6.0)   # its front on c2's lane (x = -1.75) as c2 would have been
    found = judge(tmp_path, stop_then_go_run(("c2", c2, "south"), ("8", eight, "east")))
    for v in ("7", "8"):
        inc = one(found, v)
        verdict(inc, "punishable", "HC 171")
        assert any(f.sentence == f"{v} would force c2 to change speed or course" for f in inc.derived), v


def _cyclist_passing_alongside(lag: float):
    """7 stops and pulls out east along y = +1.75; cy, a cyclist, comes south down the north arm
    (x = +1.75) at 5 m/s, turns right across 7's lane at x = +1.75 and rides west along
    y = -1.75, the lane beside 7's, reaching x = -2 when 7's front is at x = -1.5 plus `lag` s.
    The passage of 7's act."""
    meets = _SET_OFF + math.sqrt(12.5 - 1.5) + lag      # 7 at x = -1.5 (s = t² - 12.5 after it set off)
    cy = Motion(5.5 - 5.0 * meets, 5.0)                  # along "north>west": s = 5.5 is x = -2, y = -1.75
    run = stop_then_go_run()
    run.spawn("cy", "cyclist")
    run.drive("cy", cy, "north>west", rate(5, START, START + 25.0), t_start=START)
    run.watch("cy", cy, "north>west", rate(5, START, START + 25.0), t_start=START)
    return _passage_of_7(run)


def test_a_cyclist_that_crossed_ahead_and_rides_past_in_the_other_lane_is_not_endangered():
    """TSRGD 2016 Sch 9 Pt 7 para 1: no vehicle may proceed past a Stop line "so as to be likely to
    endanger any person"; a pedestrian or cyclist is endangered when in or entering the vehicle's
    path within 2 s of it being there (derived.ENDANGER_S), not for riding past it in the lane
    beside. cy crossed 7's lane ahead of 7 and its body (SUMO's default bicycle, 0.65 m wide and
    1.6 m long) was out of 7's way 0.6 s before 7's front got there; it rides past 7 in the
    opposite lane, 3.5 m from 7's centre line. Not endangered: the paper run's 182 and cyclist
    223, read as a 2.55 m by 5 m vehicle whose swept path reached into 182's (post-encroachment
    time 0, "182 would endanger 223"); SUMO's account has the two pass each other. The control,
    cy a second later, is in 7's path as 7 comes (HC 170: give way to those crossing the road you
    turn into; para 1's "endanger")."""
    from reasoner import derived

    p = _cyclist_passing_alongside(0.5)
    shown = {f.sentence for f in derived.facts(p, p.crossing.t)}
    assert "7 would endanger cy" not in shown and "cy is approaching 7" not in shown, shown
    late = _cyclist_passing_alongside(1.5)
    assert "7 would endanger cy" in {f.sentence for f in derived.facts(late, late.crossing.t)}


# 7 (STOPS_THEN_GOES) along y = +1.75 is within half a car's length (2.5 m) of the zone it shares with
# a road user coming down x = +1.75 (a square of a vehicle's width, 2.55 m, about (1.75, 1.75)) from
# x = -2.025 to x = 5.525: it has left that zone sqrt(12.5 + 5.525) s after it set off
_7_LEFT_C2S_ZONE = _SET_OFF + math.sqrt(12.5 + 5.525)


def _turning_in(stops_after: float, stands: float, lasts: float = 25.0) -> Foreign:
    """c2 comes south down the main road (x = +1.75) at 13.4 m/s to turn right into 7's (west)
    arm, and brakes at 4.5 m/s² to stand at its turning place 8 m north of the centre (2.5 m short
    of the zone where its path crosses 7's) `stops_after` s after 7 has left that zone; it stands
    `stands` s, then turns in at 2 m/s² (the run: `lasts` s)."""
    stop = _7_LEFT_C2S_ZONE + stops_after
    braking = 13.4 / 4.5
    begins = stop - braking
    c2 = Motion(-8.0 - 13.4 * braking / 2 - 13.4 * begins, 13.4,
                [(begins, 0.0), (braking, -4.5), (stands, 0.0), (10.0, 2.0)])
    return stop_then_go_run(("c2", c2, "north>west"), lasts=lasts)


def test_a_main_road_car_that_stopped_to_turn_in_after_the_vehicle_had_gone_and_stood_on_was_not_forced(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 asks whether 7, proceeding past its Stop line, caused the
    driver of another vehicle to change its speed or course "in order to avoid an accident" with it.
    c2 begins to brake 0.8 s before 7 has left the zone where their paths cross (unslowed, it would
    have come in 0.9 s after 7 left: a near miss), stands at its turning place 2.2 s after 7 has
    left and stands on 4.7 s after 7 has gone (a right-turner waiting on oncoming traffic or those
    crossing the road it turns into, HC 170 and 180). A driver 7 made stop moves off once 7 is
    out of its way, within a perception-reaction time (2.5 s, AASHTO); c2 came to its standstill
    with 7 gone and stood well after: what held it was not 7, and "to avoid an accident" with 7
    is not shown. A lawful Stop: no violation, c2 not said to be forced (the paper run's 139,
    which stopped 2.2 s after 273 had left their zone and stood 4.7 s after; SUMO's account:
    the pedestrians on the crossings of its way). The control: c2 stops while 7 is still in
    their zone and turns in 1 s after 7 has gone: forced, punishable HC 171 (and so is one on a
    collision course that brakes hard to a stop as 7 clears and stands shaken: test_foreign_scenarios'
    test_a_stop_then_a_pull_out_that_makes_main_road_traffic_brake_is_punishable)."""
    (tmp_path / "on").mkdir()
    (tmp_path / "control").mkdir()
    run = _turning_in(2.2, 2.5)
    assert [(u.user, u.reason) for u in _second_limb_of_7(run)] == [("c2", "stood on")]     # the explanation's reason
    _lawful_not_forcing_c2(tmp_path / "on", run)
    _punishable_forcing_c2(tmp_path / "control", _turning_in(-0.8, 1.8))


def test_a_main_road_car_that_stood_on_long_after_the_vehicle_had_gone_was_not_forced(tmp_path):
    """The same law as above (TSRGD 2016 Sch 9 Pt 7 para 1, "in order to avoid an accident"), the
    wait longer: c2 stands at its turning place from 2.8 s after 7 has left their zone (unslowed
    it would have come in after 7 had left) and stands 14.5 s, waiting on oncoming traffic (HC
    170), far past a perception-reaction time (2.5 s, AASHTO) after 7 had gone, and past the 8 s
    the passage reads a braking road user on (the town run's 188, which stopped 6.3 m from j11's
    centre 2.8 s after 247 had left their zone and stood 14.5 s while oncoming 150 passed; SUMO's
    account: its own minor link's approach). What held it was not 7: a lawful Stop, no violation,
    c2 not said to be forced. The reason is read only once the record shows when c2 moved off."""
    run = _turning_in(2.8, 14.5, lasts=45.0)
    assert [(u.user, u.reason) for u in _second_limb_of_7(run)] == [("c2", "stood on")]     # the explanation's reason
    _lawful_not_forcing_c2(tmp_path, run)


def _joining_behind(ahead_s: float, *, rolls: bool = False) -> Foreign:
    """7 stops at its Stop line (west arm), pulls away at 2 m/s² up to 8 m/s and turns left into
    the main road's northbound lane (x = -1.75), its front reaching that lane 3.28 s after it set
    off (`rolls`: it comes to that lane at the same moment at a steady 6.5 m/s, never standing);
    c2 comes north up that lane at 13.4 m/s and, 14 m short of the centre, brakes at 2.5 m/s²
    for 2.2 s (to 7.9 m/s, then holds it), passing where 7 turns in `ahead_s` s before 7's front
    gets there."""
    from tests.reasoner.test_foreign_scenarios import camera

    joins = _SET_OFF + math.sqrt(12.5 - 1.75)
    seven = Motion(-1.75 - 6.5 * joins, 6.5) if rolls else \
        Motion.stopping_at(-40.0, 8.0, -LINE_M - 0.5, wait=2.0, then=4.0)           # sets off at _SET_OFF
    braking_to_merge = (13.4 - math.sqrt(13.4 ** 2 - 2 * 2.5 * 15.75)) / 2.5        # y = -14 to y = +1.75
    begins = joins - ahead_s - braking_to_merge
    c2 = Motion(-14.0 - 13.4 * begins, 13.4, [(begins, 0.0), (2.2, -2.5), (20.0, 0.0)])
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop", "east": "stop"})])
    times = rate(5, START, START + 25.0)
    for user, motion, arm in (("7", seven, "west>north"), ("c2", c2, "south")):
        run.spawn(user)
        run.drive(user, motion, arm, times, t_start=START)
        run.watch(user, motion, arm, times, t_start=START, facts=camera("7", sign="stop") if user == "7" else None)
    return run


def test_a_main_road_car_the_vehicle_turned_in_behind_was_not_forced_by_it(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1: no vehicle may proceed past a Stop line "so as to be likely ...
    to cause the driver of another vehicle to change its speed or course in order to avoid an
    accident". c2 goes through the place where 7 turns into its lane 2.5 s before 7's front gets
    there (out of their zone 1.0 s before 7 comes in; unslowed, 1.4 s) and brakes at 2.5 m/s² as
    it does (for something of its own ahead); 7 pulls away steadily, never slowing, and joins the
    lane behind c2. Braking could not keep c2 from an
    accident with a car joining behind it (it only brings the two closer; HC 126 leaves the gap to
    the one behind): a lawful Stop, c2 not said to be forced (the paper run's 136, through the
    merge 0.74 s before 283 turned in behind it, braking as its leader 149 did; SUMO's account:
    leader 149). c2 began to slow while 7 still stood at its line, where it made no one change
    speed. The controls: 7 rolling through its line at 6.5 m/s as c2, going straight on, brakes
    the same (it may have braked for fear 7 would come out in front of it; the town run's 236 ->
    411, first read as this, is a turner's: `_turning_ahead` below), and c2 a second behind 7's
    front, which 7 pulls out in front of: forced, punishable HC 171."""
    (tmp_path / "behind").mkdir()
    (tmp_path / "control").mkdir()
    (tmp_path / "rolls").mkdir()
    rolled = judge(tmp_path / "rolls", _joining_behind(2.5, rolls=True))
    assert any(f.sentence == "7 would force c2 to change speed or course" for i in of(rolled, "7") for f in i.derived)
    run = _joining_behind(2.5)
    assert [(u.user, u.reason) for u in _second_limb_of_7(run)] == [("c2", "joined behind")]   # the explanation's reason
    _lawful_not_forcing_c2(tmp_path / "behind", run)
    _punishable_forcing_c2(tmp_path / "control", _joining_behind(-1.0))


def _turning_through(ends_after: float, braking: float) -> Foreign:
    """c2 comes south down the main road at 13.4 m/s to turn right into 7's (west) arm and brakes
    at 4.5 m/s² for `braking` s, its braking ending 8 m north of the centre `ends_after` s after 7
    has left the zone where their paths cross; it takes its turn at the speed it braked to, for
    3 s, and then pulls away at 2 m/s², never stopping."""
    low = 13.4 - 4.5 * braking
    begins = _7_LEFT_C2S_ZONE + ends_after - braking
    c2 = Motion(-8.0 - (13.4 + low) / 2 * braking - 13.4 * begins, 13.4,
                [(begins, 0.0), (braking, -4.5), (3.0, 0.0), (10.0, 2.0)])
    return stop_then_go_run(("c2", c2, "north>west"))


def test_a_main_road_car_slowing_for_its_own_turn_behind_the_vehicle_was_not_forced(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171) asks whether 7, proceeding past its Stop line, caused
    the driver of another vehicle to change its speed or course "in order to avoid an accident";
    issue 35: not for its own control ("its own turn"). c2 brakes at 4.5 m/s² from 13.4 to 6.2 m/s
    as it comes to its right turn across 7's way, its braking ending 0.5 s after 7 has left their
    zone, and takes the turn at 6.2 m/s without stopping. Unslowed (13.4 m/s, faster than any
    right turn is taken) it would still have come into the zone 0.25 s after 7 had left it: no
    collision course with 7, and the slowing is the one its own turn asks (the town run's 279,
    13.4 to 6.4 m/s for its right turn across 114's way, unslowed 1.02 s after 114 had left; SUMO's
    account: its own minor link's approach). (One turning into the lane 7 went down, behind 7, is
    test_foreign_scenarios' following case, not this.) A lawful
    Stop: no violation, c2 not said to be forced. The control: the same turn with 7 cutting across
    c2 1.5 s ahead of where c2, unslowed, would have been in their zone, and c2 braking harder and
    longer than its turn asks (2.5 s, to 2.2 m/s, ending 0.6 s before 7 has left): forced,
    punishable HC 171."""
    (tmp_path / "turn").mkdir()
    (tmp_path / "control").mkdir()
    run = _turning_through(0.5, 1.6)
    assert [(u.user, u.reason) for u in _second_limb_of_7(run)] == [("c2", "own turn")]      # the explanation's reason
    _lawful_not_forcing_c2(tmp_path / "turn", run)
    _punishable_forcing_c2(tmp_path / "control", _turning_through(-0.6, 2.5))


def _turning_in_behind(ahead_m: float, short_m: float, low: float, decel: float = 4.5) -> Foreign:
    """7 stops at the north Stop line and goes straight on down the south arm (x = +1.75), pulling
    away at 2 m/s² (test_foreign_scenarios' STOPS_THEN_GOES); c2 comes from the west at 13.4 m/s to
    turn right into that lane behind it: `short_m` m short of the centre when 7 is `ahead_m` m
    beyond it, c2 brakes at `decel` m/s² to `low` m/s, takes its turn at that speed (held 4 s,
    never stopping) and then pulls away at 2 m/s². Along c2's way 7 is then short_m + 3.5 +
    ahead_m m ahead of it (to the corner at (1.75, 1.75), and down the arm)."""
    begins = _SET_OFF + math.sqrt(ahead_m + 12.5)
    c2 = Motion(-short_m - 13.4 * begins, 13.4, [(begins, 0.0), ((13.4 - low) / decel, -decel), (4.0, 0.0), (10.0, 2.0)])
    return stop_then_go_run(("c2", c2, "west>south"), arm="north")


def test_a_main_road_car_slowing_for_its_own_turn_into_the_road_the_vehicle_went_down_was_not_forced(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): 7, proceeding past its Stop line, must not cause the
    driver of another vehicle "to change its speed or course in order to avoid an accident". 7
    comes out of the north arm and goes on down the south arm; c2, from the west at 13.4 m/s,
    turns right into that lane behind it (the paper run's 228 behind 116 at j2). c2 begins to
    brake (4.5 m/s², to 6.3 m/s) 24.4 m short of the centre as 7 is 6 m beyond it at 8.6 m/s and
    speeding up, 33.9 m ahead along c2's way, and takes its turn at 6.3 m/s without stopping.
    Unslowed it would have come into their zone after 7 had left it (no collision course); it
    must slow for a right turn whatever comes, and at the speed it took its turn, from where it
    began to slow, 7 was always more than the two-second gap ahead of it (HC 126: 2 s at 6.3 m/s,
    12.6 m, with a car's length and a queue's gap, 8 m: 20.6 m) and drawing away. No accident
    with 7 to avoid: its slowing was for its own turn, a lawful Stop, c2 not said to be forced
    (fails where the following question is asked at c2's 13.4 m/s, which no right turn is taken
    at). The control: c2 9 m short as 7 is 2.5 m beyond the centre at 7.7 m/s, braking at 8.5 m/s²
    to 4 m/s for its turn, into their zone 0.21 s after 7 left it: unslowed it was on no collision
    course (0.09 s after 7), but at the speed it took its turn 7 was 15 m ahead of it along its
    way where two seconds at 4 m/s and 8 m are 16 m: 7 pulled out into the road c2 turned into
    inside the gap c2 was to keep behind it, forced, HC 171."""
    (tmp_path / "turn").mkdir()
    (tmp_path / "control").mkdir()
    run = _turning_in_behind(6.0, 24.4, 6.3)
    limb = _second_limb_of_7(run)
    assert [(u.user, u.reason) for u in limb] == [("c2", "own turn")]        # the explanation's reason
    assert "two-second gap" in limb[0].words and "6.3" in limb[0].words      # ... with the speed of its turn
    _lawful_not_forcing_c2(tmp_path / "turn", run)
    _punishable_forcing_c2(tmp_path / "control", _turning_in_behind(2.5, 9.0, 4.0, decel=8.5))

def _cut_in_between(*, eight: bool = True) -> Foreign:
    """7 stops at the west Stop line, sets off 1 s after it stood and crawls at 2 m/s, turning left
    into the main road's northbound lane (x = -1.75) at y = +1.75 at 13.75 s (from START); 8 stops
    at the east Stop line, sets off 2 s after 7 and crawls the same way across the junction,
    turning right into that lane at y = -1.75 at 17.5 s, 9.5 m behind 7 (`eight` False: 8 is not
    there). c2 comes north up the lane at 13.4 m/s and at 14.5 s, 25 m short of 8's way with 7
    34 m ahead of it in the lane, brakes at 4.5 m/s² to 2 m/s and follows at that speed."""
    from tests.reasoner.test_foreign_scenarios import camera

    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop", "east": "stop"})])
    times = rate(5, START, START + 30.0)
    begins = 14.5
    c2 = Motion(-30.5 - 13.4 * begins, 13.4, [(begins, 0.0), ((13.4 - 2.0) / 4.5, -4.5)])
    movers = [("7", Motion.stopping_at(-40.0, 8.0, -LINE_M - 0.5, wait=1.0, then=1.0), "west>north"),
              ("c2", c2, "south")]
    if eight:
        movers.append(("8", Motion.stopping_at(-40.0, 8.0, -LINE_M - 0.5, wait=3.0, then=1.0), "east>north"))
    for user, motion, arm in movers:
        run.spawn(user)
        run.drive(user, motion, arm, times, t_start=START)
        run.watch(user, motion, arm, times, t_start=START,
                  facts=camera(user, sign="stop") if user != "c2" else None)
    return run


def test_a_main_road_car_braking_for_a_second_emerger_that_cut_in_ahead_of_it_was_not_forced_by_the_first(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1: no vehicle may proceed past a Stop line "so as to be likely ...
    to cause the driver of another vehicle to change its speed or course in order to avoid an
    accident". 7 crawls out of the west Stop line into c2's lane, 34 m ahead of c2 when c2 begins
    to slow; 8 crawls out of the east Stop line after it, across the junction and into the same
    lane behind 7, 25 m ahead of c2 on its way, and c2 brakes at 4.5 m/s² to 8's crawl. Unslowed, c2 would have run into 8 in the lane (a collision
    course, 8's zone first on its way): the accident its braking avoided was with 8, the vehicle in
    front of it from then on (HC 126), and it could have come to 7 only behind 8. 8 forced c2:
    punishable, HC 171; 7's Stop is lawful (the paper run's 279, said to force 205 as 266 came out
    of j2's north arm between them; SUMO, asked tick by tick, braked 205 for 266, and its next
    speed was the same with 279 taken away; 266's Stop raised no incident, 205 put down to 279 as
    its leader). The control: without 8, c2 braking the same behind 7 alone was forced by 7."""
    (tmp_path / "both").mkdir()
    (tmp_path / "alone").mkdir()
    found = _lawful_not_forcing_c2(tmp_path / "both", _cut_in_between())
    inc = one(found, "8")
    verdict(inc, "punishable", "HC 171")
    assert any(f.sentence == "8 would force c2 to change speed or course" for f in inc.derived)
    _punishable_forcing_c2(tmp_path / "alone", _cut_in_between(eight=False))


def test_the_braking_cited_for_a_forced_road_user_is_the_stretch_the_act_caused_not_a_later_one_for_another(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 asks of each change of speed whether the vehicle proceeding
    past its Stop line caused it ("to change its speed or course in order to avoid an accident"),
    and an offence rests on the figures that decided. 7 crawls out of the west Stop line into c2's
    lane; c2, 45 m short at 13.4 m/s, brakes at 2.8 m/s² for it from 14.5 s. 8 stands at the east
    Stop line until 16.0 s, then pulls out across c2's lane into it between c2 and 7, and c2 brakes
    at 6 m/s² from 17.0 s, 20 m short of 8's way, down to 1 m/s. 7 forced c2 (2.8 m/s², beyond 2
    m/s² by more than its ± 0.2): punishable, HC 171, on that figure; the 5.4 m/s² of c2's
    hardest second was for 8, whose own Stop is punishable on it (the paper run's 266, whose Stop
    cited 205's 5.5 m/s² braking for 253 rather than its 4.5 m/s² for 266; SUMO's account: foe 266,
    then foe 253). Fails where one hardest braking per road user is cited whatever stretch of its
    slowing the act explains."""
    found = judge(tmp_path, _braking_for_two())
    inc = one(found, "7")
    verdict(inc, "punishable", "HC 171")
    forced = next(f for f in inc.derived if f.sentence == "7 would force c2 to change speed or course")
    assert forced.method.startswith("c2 braked at 2.8 ± 0.2 m/s² against 2 m/s² (12.6 m/s at"), forced.method
    assert "9.8 m/s" in forced.method
    assert inc.margin is None or inc.margin.quantity != "deceleration of the other road user" \
        or round(inc.margin.value, 1) == 2.8
    inc = one(found, "8")
    verdict(inc, "punishable", "HC 171")
    forced = next(f for f in inc.derived if f.sentence == "8 would force c2 to change speed or course")
    assert forced.method.startswith("c2 braked at 5.4 ± 0.2 m/s²"), forced.method


def _braking_for_two() -> Foreign:
    """7 as in `_cut_in_between`: out of the west Stop line at 7.9 s, crawling at 2 m/s into the
    main road's northbound lane at 13.75 s. c2 comes north up that lane at 13.4 m/s, brakes at 2.8
    m/s² from 14.5 s (45.5 m short of the centre) for 2.5 s and then at 6 m/s² for 0.9 s, to 1 m/s
    20.7 m short of 8's way. 8 stands at the east Stop line until 16.0 s
    and pulls away at 2 m/s² for 3 s across the junction and into c2's lane ahead of it."""
    from tests.reasoner.test_foreign_scenarios import camera

    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop", "east": "stop"})])
    times = rate(5, START, START + 30.0)
    begins = 14.5
    c2 = Motion(-45.5 - 13.4 * begins, 13.4, [(begins, 0.0), (2.5, -2.8), (0.9, -6.0)])
    braking = 2 * 27.5 / 8.0                      # 8 m/s braked evenly over 27.5 m to stand at its line
    movers = [("7", Motion.stopping_at(-40.0, 8.0, -LINE_M - 0.5, wait=1.0, then=1.0), "west>north"),
              ("c2", c2, "south"),
              ("8", Motion(-40.0, 8.0, [(braking, -8.0 / braking), (16.0 - braking, 0.0), (3.0, 2.0)]), "east>north")]
    for user, motion, arm in movers:
        run.spawn(user)
        run.drive(user, motion, arm, times, t_start=START)
        run.watch(user, motion, arm, times, t_start=START,
                  facts=camera(user, sign="stop") if user != "c2" else None)
    return run


def _turning_ahead(leaving: str) -> Foreign:
    """A Give Way crossroads whose major road runs east-west: 7 comes up from the south arm at a
    steady 6 m/s, never slowing for its Give Way line (crossed 4.67 s on), and goes straight on up
    the north arm (x = -1.75). c2 comes from the east along the major road at 13.4 m/s, brakes at
    4.5 m/s² from 13.5 m east of the centre to 6.5 m/s where its lane meets 7's (x = -1.75, 4.0 s
    on), and pulls away at 2.6 m/s², never stopping: `leaving` "north", it turns right there into
    the north arm's lane 7 goes up, ahead of 7; "west", it goes straight on across 7's way. c3
    follows c2 at 13.4 m/s, 45 m east of the centre as 7 crosses its line (approaching 7 on the
    main road: HC 172's question is asked), and turns left into the south arm, clear of 7's way."""
    from tests.reasoner.test_foreign_scenarios import camera

    low, turned = 6.5, 4.0
    braking = (13.4 - low) / 4.5
    begins = turned - braking
    c2 = Motion(1.75 - (13.4 ** 2 - low ** 2) / 9.0 - 13.4 * begins, 13.4,
                [(begins, 0.0), (braking, -4.5), ((13.4 - low) / 2.6, 2.6), (20.0, 0.0)])
    c3 = Motion(-45.0 - 13.4 * 28.0 / 6.0, 13.4)
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds={"south": "give_way", "north": "give_way"})])
    times = rate(5, START, START + 18.0)
    for user, motion, arm in (("7", Motion(-40.0, 6.0), "south"), ("c2", c2, "east>north" if leaving == "north" else "east"),
                              ("c3", c3, "east>south")):
        run.spawn(user)
        run.drive(user, motion, arm, times, t_start=START)
        run.watch(user, motion, arm, times, t_start=START, facts=camera("7", sign="give way") if user == "7" else None)
    return run


def test_a_main_road_car_slowing_for_its_own_turn_ahead_of_the_vehicle_coming_in_behind_was_not_forced(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 172): 7, proceeding past its Give Way line, must not cause
    the driver of another vehicle "to change its speed or course in order to avoid an accident";
    issue 35: not for its own control ("its own turn"). c2, on the major road, slows at 4.5 m/s²
    from 13.4 to 6.5 m/s for its right turn into the north arm and takes it at that speed without
    stopping, into 7's lane ahead of 7, which comes up from the south without slowing and goes on
    up the north arm behind it: c2 left their zone 0.77 s before 7 came in (unslowed, 1.57 s). What
    c2 could meet with 7 was 7 running into it from behind, which its slowing could not avoid and
    only brought nearer (HC 126 leaves the gap to the one behind): it slowed for its own turn, and
    7 did not force it (the town run's 411, turning right from j19's east arm into the north arm
    ahead of 236, 9.6 to 6.47 m/s in its turn, through 0.78 s ahead of 236, unslowed 0.96 s; SUMO's
    account: its own exit link's approach, its speeds replayed the same without 236). c2 not said to
    be forced (fails before derived.turned_ahead: "7 would force c2", with c2's 4.5 m/s² as the
    margin); 7's incident is for c3, approaching and not forced: mitigated, HC 172. The control: c2
    the same, braking the same at the same moment, but going straight on across 7's way (through
    1.22 s ahead of it, unslowed 1.86 s), no turn of its own to slow for: a driver that brakes hard
    as a car comes at its Give Way line without slowing may brake for fear of it coming out in
    front (test_a_main_road_car_the_vehicle_turned_in_behind_was_not_forced_by_it's rolling
    control): forced, its deceleration the margin (HC 172's duty is owed to traffic approaching
    on the main road, and c2 was in the junction when 7 entered it: mitigated, as the town run's
    236 was)."""
    (tmp_path / "turn").mkdir()
    (tmp_path / "control").mkdir()
    run = _turning_ahead("north")
    limb = _second_limb_of_7(run)
    c2 = [u for u in limb if u.user == "c2"]
    assert [(u.reason, u.first) for u in c2] == [("turned ahead", "theirs")]        # the explanation's reason
    assert "6.50 m/s" in c2[0].words and "came in behind it" in c2[0].words         # ... and its figures
    inc = one(judge(tmp_path / "turn", run), "7")
    verdict(inc, "mitigated", "HC 172")
    assert not any("would force c2" in f.sentence for f in inc.derived) and inc.margin is None
    control = one(judge(tmp_path / "control", _turning_ahead("west")), "7")
    verdict(control, "mitigated", "HC 172")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in control.derived)
    margin(control, "deceleration", "m/s²", 4.5, 0.25)
