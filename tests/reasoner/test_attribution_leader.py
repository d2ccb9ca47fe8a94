"""Issue 35: a main-road car braking as the car ahead of it braked, in scenarios written as a
foreign producer writes them (tests/helpers/foreign.py: positions at 5 Hz, core sentences only),
the law's answer beside each.

HC 126 asks a driver to leave "enough space between you and the vehicle in front so that you can
pull up safely if it suddenly slows down or stops" (the two-second rule). A car closer than that
behind a leader going its speed brakes when the leader does, whatever a Stop-line vehicle does:
it changed speed for its leader, not "in order to avoid an accident" with that vehicle (TSRGD
2016 Sch 9 Pt 7 para 1). SUMO's account of the simulated runs names such a braking's leader (the
paper run's 164 20 m behind 221, the town's 241 20 m behind 292: both pairs within 0.1 m/s of
each other, braking from the same sample), where the reasoner had named the Stop-line vehicle
because the leader was 0.08 m/s the faster when the two began to slow (attribution.leader).

The shared Stop-line run (test_foreign_scenarios.stop_then_go_run): 7 stops at the west Stop line,
waits 2 s and pulls away at 2 m/s² east along y = +1.75; it is in its conflict zone with the main
road's southbound lane (x = +1.75) from about 3.2 s to 4.3 s after it set off. c1 and c2 come down
that lane from the north, c2 20 m behind c1.
"""
from __future__ import annotations

from tests.helpers.foreign import Motion
from tests.reasoner.test_foreign_scenarios import _SET_OFF, judge, no_violation, of, stop_then_go_run, verdict

FORCED_C2 = "would force c2"
_BRAKE = _SET_OFF + 1.0          # c2 brakes 1 s after 7 set off, at 5 m/s², from 50 m short of the centre


def _c2():
    """c2 at 13.33 m/s (30 mph) braking at 5 m/s² to a stop 32 m short of the centre; unslowed it
    would have reached 7's conflict zone 0.09 s after 7 left it (under 2 s: a conflict)."""
    return Motion(-50.0 - 13.33 * _BRAKE, 13.33, [(_BRAKE, 0.0), (13.33 / 5.0, -5.0)])


def test_a_main_road_car_braking_with_its_leader_within_the_two_second_gap_was_not_forced(tmp_path):
    """c0 stands on the far side of the junction in the southbound lane (14 m south of the centre,
    a queue on the exit); c1, at 13.41 m/s, brakes at 5 m/s² to a stop 12 m short of the centre
    for it (its leader: keeping the two-second gap behind a standing car from 44 m at 13.41 m/s
    takes 13.41² / (2 × (44 - 8)) = 2.5 m/s²), and c2, 20 m behind c1 at 13.33 m/s (1.5 s: inside
    the two-second gap), brakes with it from the same moment. c2 braked because the car in front of it did (HC 126), not to avoid an
    accident with 7. Law (para 1): 7 caused no change of speed: a lawful Stop (on main, "7 would
    force c2" and punishable, HC 171: c1 was 0.08 m/s the faster when c2 began to slow, so it was
    not counted as its leader)."""
    c1 = Motion(-30.0 - 13.41 * _BRAKE, 13.41, [(_BRAKE, 0.0), (13.41 / 5.0, -5.0)])
    found = judge(tmp_path, stop_then_go_run(("c0", Motion(14.0, 0.0), "north"), ("c1", c1, "north"),
                                             ("c2", _c2(), "north")))
    assert not any(FORCED_C2 in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_the_control_a_leader_going_on_at_its_speed_is_no_cause(tmp_path):
    """c1, 32 m ahead of c2 at 13.41 m/s when c2 brakes (inside the two-second gap and a car's
    length, 8 m + 2 s × 13.41 m/s = 34.8 m), goes on through the junction ahead of 7 without
    slowing; c2 brakes as before, 1 s after 7 set off. A car going on at c2's speed ahead of it asked no
    braking of it; unslowed, c2 would have come within 0.09 s of 7 in their conflict zone. Law
    (para 1): 7 caused c2 to change speed to avoid an accident: punishable, HC 171, "7 would
    force c2"."""
    c1 = Motion(-18.0 - 13.41 * _BRAKE, 13.41)
    found = judge(tmp_path, stop_then_go_run(("c1", c1, "north"), ("c2", _c2(), "north")))
    inc = [i for i in of(found, "7") if i.verdict == "punishable"]
    assert inc and any(FORCED_C2 in f.sentence for i in inc for f in i.derived), \
        [(i.verdict, i.rule, [f.sentence for f in i.derived if "force" in f.sentence]) for i in of(found, "7")]
    verdict(inc[0], "punishable", "HC 171")
