"""Issue 35: each braking attributed to the conflict it resolved (reasoner/attribution.py), in
scenarios written as a foreign producer writes them (tests/helpers/foreign.py: positions at 5 Hz,
core sentences only), the law's answer beside each.

TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): no vehicle may proceed past a Stop line "so as to be likely
to ... cause the driver of another vehicle to change its speed or course in order to avoid an
accident". A main-road driver that had to brake for something else in its way, whatever the
vehicle at the Stop line did, did not change speed to avoid an accident with that vehicle:

- a car standing in its lane ahead of it (here beyond the junction, on its exit), so close that
  keeping the two-second gap behind it (HC 126) took braking at 2 m/s² or harder
  (reaction.FORCE_DECEL_MPS2, Hupfer 1997);
- another road user crossing its way before the Stop-line vehicle's path, where, unslowed, it
  would have come within 2 s of it (conflicts.PET_MAX_S, SUMO's SSM device default).

The shared Stop-line run (test_foreign_scenarios.stop_then_go_run): 7 stops at the west Stop line
(major road north-south), waits 2 s and pulls away at 2 m/s², going straight on east along
y = +1.75: s = -12.5 + t² from its line, t from when it set off (_SET_OFF after START).
"""
from __future__ import annotations

from tests.helpers.foreign import Motion
from tests.reasoner.test_conflict_scenarios import walk
from tests.reasoner.test_foreign_scenarios import START, _SET_OFF, judge, no_violation, of, stop_then_go_run, verdict

FORCED_C2 = "would force c2"


def _queued_exit_run(queue: bool):
    """c2 comes down the main road's southbound lane (x = +1.75) at 13.4 m/s (30 mph) and, 30 m
    short of the centre, 3.43 s after 7 set off, brakes at 5 m/s² to a stop 12 m short of it;
    `queue`: c1 stands in that lane on the far side, 14 m south of the centre (its exit)."""
    begins = _SET_OFF + 3.43
    c2 = Motion(-30.0 - 13.4 * begins, 13.4, [(begins, 0.0), (13.4 / 5.0, -5.0)])
    others = [("c2", c2, "north")] + ([("c1", Motion(14.0, 0.0), "north")] if queue else [])
    return stop_then_go_run(*others)


def test_a_main_road_car_stopping_short_of_a_queue_on_its_exit_was_not_forced(tmp_path):
    """c1 stands in c2's lane on the far side of the junction (a queue on c2's exit, 14 m south of
    the centre). c2, 44 m behind it at 13.4 m/s, brakes at 5 m/s² and stops 12 m short of the
    centre, out of the junction: keeping the two-second gap behind a standing car from 44 m at
    13.4 m/s needs 13.4² / (2 × (44 - 8)) = 2.5 m/s² (HC 126; 8 m for a car's length and the gap
    of a queue), so c2 had to brake hard for c1 whatever 7 did (and must not enter a junction
    whose exit is blocked, HC 174). Unslowed, c2 would have come within about 1 s of 7 where their
    paths meet, and on main 7 was convicted of forcing c2: others.py's `followed` looks on c2's
    own arm only, and c1 stands on another. Law: 7 caused no change of speed; a lawful Stop and
    pull-out (SUMO's account names such a braking's leader, not the vehicle crossing)."""
    found = judge(tmp_path, _queued_exit_run(queue=True))
    assert not any(FORCED_C2 in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_the_control_with_the_exit_clear_is_forcing(tmp_path):
    """The same c2 with nobody on its exit: unslowed it would have come within about 1 s of 7 where
    their paths meet, and it braked at 5 m/s² as 7 pulled out: 7 caused it to change speed to
    avoid an accident (para 1): punishable, HC 171, "7 would force c2" (the test above turns on
    c1, not on a c2 that nobody else explains)."""
    found = judge(tmp_path, _queued_exit_run(queue=False))
    assert any(FORCED_C2 in f.sentence for i in of(found, "7") for f in i.derived)
    assert any(i.verdict == "punishable" and i.rule == "HC 171" for i in of(found, "7"))


# c2 comes up the main road from the south along x = -1.75 (northbound): it meets 8's path (y = -1.75,
# westbound from the east Stop line) at s = -1.75 before 7's (y = +1.75) at s = +1.75. 7 is in their
# conflict zone (a vehicle's width either side of c2's lane, half a car's length more) from 2.4 s to
# 3.96 s after it set off; 8, at 6 m/s, is on c2's lane at 4.3 s after it.
_EIGHT_ON_C2S_LANE = _SET_OFF + 4.3
_C2_BRAKES = _SET_OFF + 2.75


def _crossing_run():
    c2 = Motion(-25.0 - 13.4 * _C2_BRAKES, 13.4, [(_C2_BRAKES, 0.0), (13.4 / 5.0, -5.0)])
    eight = Motion(1.75 - 6.0 * _EIGHT_ON_C2S_LANE, 6.0)
    return stop_then_go_run(("c2", c2, "south"), ("8", eight, "east"))


def test_a_main_road_car_braking_for_another_emerger_it_would_have_met_first_was_forced_by_that_one(tmp_path):
    """7 stops and pulls out; at the same time 8 rolls out of the opposite (east) Stop line at
    6 m/s without stopping, along y = -1.75, across c2's northbound lane. c2, 25 m short of the
    centre, brakes at 5 m/s² to a stop 7 m short of it, 2.75 s after 7 set off. Unslowed, c2 would
    have been in the zone where its path meets 8's together with 8 (a projected gap below 0),
    and would have reached it before the zone where its path meets 7's (a gap of 0.5 s there):
    the driver resolves the first conflict on its way, so it braked for 8, and came nowhere near
    7's path. Law: 8 caused c2 to change speed to avoid an accident (para 1, and 8 never stopped
    at its line): punishable, HC 171, "8 would force c2"; 7 forced nobody: a lawful Stop (on main
    7 was convicted of forcing c2, too)."""
    found = judge(tmp_path, _crossing_run())
    assert not any(FORCED_C2 in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")
    eight = of(found, "8")
    assert any(i.verdict == "punishable" and i.rule == "HC 171" for i in eight)
    assert any(f.sentence == "8 would force c2 to change speed or course" for i in eight for f in i.derived)


def test_the_attribution_is_said_with_its_measures():
    """The explanation of why c2 was not forced by 7 names 8 and the distances and gap that decided
    (issue 35: the figures a court can weigh)."""
    from reasoner import derived, history

    run = _crossing_run()
    p = next(p for p in history.from_events(run.events, "7") if p.crossing is not None)
    c2 = next(o for o in derived.reacting(p) if o.user == "c2")
    assert derived.explained(p, c2)
    cause = derived._cause(p, c2)
    assert cause.startswith("8, whose conflict it braked for") and "from their conflict zone" in cause, cause
    assert "from 7's" in cause and "in it with 8" in cause and "a collision course with 8" in cause, cause
    assert "under 2 s is a conflict" in cause, cause


def test_a_main_road_car_stopping_for_a_pedestrian_on_a_crossing_before_the_vehicle_s_path_was_not_forced(tmp_path):
    """p9 walks east across the north arm 10 m from the centre (y = +10, a crossing of the main
    road) at 1.4 m/s, on c2's southbound lane (x = +1.75) 5.2 s after 7 set off. c2 comes down that
    lane at 13.4 m/s and, 34 m from the centre, brakes at 5 m/s² to a stop at 16 m, short of p9's
    way, 2.6 s after 7 set off. Unslowed, c2 would have reached p9's way first and been there with
    p9, and then 7's path 1 s after 7 left it (the camera measures p9 as it measures vehicles). A driver must give way to a pedestrian on a
    crossing (HC 195; Zebra, Pelican and Puffin Pedestrian Crossings Regulations 1997 reg. 25): c2
    stopped for p9, not to avoid an accident with 7 (the paper run's 133, which SUMO says braked for
    pedestrian p12). Law: 7 forced nobody; nor was p9 in or entering 7's path: a lawful Stop."""
    begins = _SET_OFF + 2.6
    c2 = Motion(-34.0 - 13.4 * begins, 13.4, [(begins, 0.0), (13.4 / 5.0, -5.0)])
    run = stop_then_go_run(("c2", c2, "north"))
    on_lane = START + _SET_OFF + 5.2
    walk(run, "p9", (1.75 - 1.4 * (on_lane - START), 10.0), (1.4, 0.0), START + 25.0, watched=True)
    found = judge(tmp_path, run)
    assert not any(FORCED_C2 in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def _p9_beyond_run(begins: float, on_lane: float):
    """c2 from the north at 13.4 m/s, 34 m short of the centre at `begins` (after 7 set off),
    braking at 5 m/s² to a stop; p9 crossing the south arm (y = -10, beyond 7's path on c2's way)
    at 1.4 m/s, on c2's lane `on_lane` s after 7 set off."""
    c2 = Motion(-34.0 - 13.4 * (_SET_OFF + begins), 13.4, [(_SET_OFF + begins, 0.0), (13.4 / 5.0, -5.0)])
    run = stop_then_go_run(("c2", c2, "north"))
    walk(run, "p9", (1.75 - 1.4 * _SET_OFF - 1.4 * on_lane, -10.0), (1.4, 0.0), START + 25.0, watched=True)
    return run


def test_a_pedestrian_crossing_beyond_the_vehicle_s_path_on_a_collision_course_explains_the_stop(tmp_path):
    """p9's crossing is beyond 7's path on c2's way (the south arm, y = -10). c2 brakes 2.6 s
    after 7 set off; unslowed it would have passed 7's conflict zone 0.48 s after 7 had left it
    (within 2 s, but no collision course) and been on p9's crossing together with p9 (a projected
    gap of -2.1 s). It had to stop for p9 whatever 7 did: a driver must give way to a pedestrian
    on a crossing (HC 195; Zebra, Pelican and Puffin Pedestrian Crossings Regulations 1997 reg.
    25), and the conflict nearer an accident is the one the braking resolved (reasoner/
    attribution.py; SUMO names the constraint allowing the lowest speed, as its paper run's 139
    braking for pedestrians p6 and p7 shows). Before the attribution weighed the conflicts'
    severity, this test held 7 to have forced c2 because 7's zone came first on c2's way. Law
    (para 1): that 7 caused c2 to change speed to avoid an accident is not shown; nor was p9 in
    or entering 7's path: a lawful Stop."""
    found = judge(tmp_path, _p9_beyond_run(2.6, 6.8))
    assert not any(FORCED_C2 in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_the_pedestrian_control_a_collision_course_with_the_vehicle_is_forcing_whatever_lies_beyond(tmp_path):
    """The same p9 crossing beyond 7's path, c2 braking 0.6 s sooner (2 s after 7 set off):
    unslowed, c2 would now have been in 7's conflict zone together with 7 (a projected gap of
    -0.12 s). A collision course with 7 is 7's whatever lies beyond it: without p9, c2 had to brake
    for 7 all the same. Law (para 1): 7 caused c2 to change speed to avoid an accident:
    punishable, HC 171, "7 would force c2"."""
    found = judge(tmp_path, _p9_beyond_run(2.0, 6.2))
    inc = [i for i in of(found, "7") if i.verdict == "punishable"]
    assert inc and any(FORCED_C2 in f.sentence for i in inc for f in i.derived), \
        [(i.verdict, i.rule, [f.sentence for f in i.derived if "force" in f.sentence]) for i in of(found, "7")]
    verdict(inc[0], "punishable", "HC 171")
