"""Issue 35: a road user that went into its conflict zone with the vehicle ahead of it, in
scenarios written as a foreign producer writes them (tests/helpers/foreign.py: positions at 5 Hz,
core sentences only), the law's answer beside each.

TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): no vehicle may proceed past a Stop line "so as to be likely
to ... cause the driver of another vehicle to change its speed or course in order to avoid an
accident". A main-road car that went through the place where the two paths meet before the Stop-line
vehicle came to it did not give way to that vehicle. Two such slowings are not the vehicle's doing,
from SUMO's own account of the simulated runs:

- a stop, after which it went into the zone ahead of the vehicle (derived._went_first; the paper
  run's 224 and the town run's 424, which SUMO says braked for their leaders, not for the
  Stop-line vehicle): it did not wait for the vehicle to pass, so what it stopped for is not shown
  to be the vehicle;
- slowing begun inside the zone where, had it kept its speed, it would have left the zone 2 s or
  more before the vehicle came in (derived._inside_gap, conflicts.exit_gap: the projected gap of a
  road user already in the zone; the paper run's 238, 3.06 s, SUMO: its leader).

The shared Stop-line run (test_foreign_scenarios.stop_then_go_run): 7 stops at the west Stop line,
waits 2 s and pulls away at 2 m/s² east along y = +1.75; it is in its conflict zone with the main
road's southbound lane (x = +1.75) from about 3.2 s to 4.3 s after it set off. c2 comes down that
lane from the north.
"""
from __future__ import annotations

from tests.helpers.foreign import Motion
from tests.reasoner.test_foreign_scenarios import _SET_OFF, judge, no_violation, of, stop_then_go_run, verdict

FORCED_C2 = "would force c2"


def _stood_run(go: bool):
    """c2 at 6 m/s brakes at 3 m/s² from 1 s before 7 sets off (still at 3 m/s then) to a stop
    6 m short of the centre 1 s after; `go`: it pulls away at once at 4.5 m/s² and goes through,
    in the zone from about 1.5 s to 2.9 s after 7 set off, out 0.34 s before 7 came in
    (unslowed it would have passed 1.74 s ahead of 7: a near miss, under PET_MAX_S); else it
    waits there 6 s, until 7 has gone through."""
    begins = _SET_OFF - 1.0
    c2 = Motion(-6.0 - 6.0 - 6.0 * begins, 6.0, [(begins, 0.0), (2.0, -3.0), (0.01 if go else 6.0, 0.0), (20.0, 4.5)])
    return stop_then_go_run(("c2", c2, "north"))


def test_a_main_road_car_that_stopped_and_then_went_through_ahead_of_the_vehicle_was_not_forced(tmp_path):
    """c2 stops 6 m short of the centre as 7 sets off, then goes straight through the junction
    ahead of 7 and is out of their conflict zone before 7 comes in. It did not wait for 7 to pass:
    its stop only narrowed its gap to 7 (1.74 s unslowed, 0.34 s as it went), so it did not change
    speed to avoid an accident with 7. Law (para 1): that 7 caused c2 to change speed is not
    shown: a lawful Stop (on main, "7 would force c2" and punishable, HC 171: unslowed, c2's gap
    to 7 was under 2 s)."""
    found = judge(tmp_path, _stood_run(go=True))
    assert not any(FORCED_C2 in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_the_control_a_main_road_car_that_stopped_and_waited_for_the_vehicle_was_forced(tmp_path):
    """The same c2 stopping as 7 sets off, waiting there until 7 has gone through: it gave way to
    7, which was on course to pass within 2 s of it (para 1: 7 caused c2 to change speed to avoid
    an accident): punishable, HC 171, "7 would force c2"."""
    found = judge(tmp_path, _stood_run(go=False))
    inc = [i for i in of(found, "7") if i.verdict == "punishable"]
    assert inc and any(FORCED_C2 in f.sentence for i in inc for f in i.derived), \
        [(i.verdict, i.rule, [f.sentence for f in i.derived if "force" in f.sentence]) for i in of(found, "7")]
    verdict(inc[0], "punishable", "HC 171")


def _inside_run(begins: float):
    """c2 comes down the main road at 8 m/s and, 4 m short of the centre (already in the place
    where its lane meets 7's path), `begins` s after 7 set off, brakes at 4.5 m/s² for 1 s to
    3.5 m/s, then goes on at 3 m/s²."""
    at = _SET_OFF + begins
    return stop_then_go_run(("c2", Motion(-4.0 - 8.0 * at, 8.0, [(at, 0.0), (1.0, -4.5), (20.0, 3.0)]), "north"))


def test_a_main_road_car_slowing_inside_the_zone_well_before_the_vehicle_came_was_not_forced(tmp_path):
    """c2 brakes 0.2 s after 7 set off, already in their conflict zone; unslowed it would have left
    it 2.29 s before 7 came in (it leaves, slowed, 1.97 s before): had it kept its speed it would
    have been gone 2 s or more before 7 got there (PET_MAX_S, SUMO's SSM threshold), so it slowed
    for something else. Law (para 1): 7 caused no change of speed: a lawful Stop (on main, "7
    would force c2" and punishable, HC 171: the braking inside the junction counted
    (derived._toward_zone), and a road user already in the zone had no projected gap to clear it)."""
    found = judge(tmp_path, _inside_run(0.2))
    assert not any(FORCED_C2 in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_the_control_a_main_road_car_slowing_inside_the_zone_as_the_vehicle_came_was_forced(tmp_path):
    """The same c2 braking 1.5 s after 7 set off, in the zone: unslowed it would have left it 0.97 s
    before 7 came in (under 2 s: a conflict; slowed, 0.67 s before). Slowing where
    7 was about to come (as the simulated golden run's 143 stopped as 145 crossed in front of it)
    is V's to answer for. Law (para 1): 7 caused c2 to change speed to avoid an accident:
    punishable, HC 171, "7 would force c2"."""
    found = judge(tmp_path, _inside_run(1.5))
    inc = [i for i in of(found, "7") if i.verdict == "punishable"]
    assert inc and any(FORCED_C2 in f.sentence for i in inc for f in i.derived), \
        [(i.verdict, i.rule, [f.sentence for f in i.derived if "force" in f.sentence]) for i in of(found, "7")]
    verdict(inc[0], "punishable", "HC 171")


def test_why_the_car_that_went_first_was_not_forced_is_said_with_its_times():
    """The explanation names the stop and how long after c2 7 came into their zone, or the gap c2
    would have left unslowed from inside the zone (issue 35: the figures a court can weigh)."""
    from reasoner import derived, history

    run = _stood_run(go=True)
    p = next(p for p in history.from_events(run.events, "7") if p.crossing is not None)
    c2 = next(o for o in derived.reacting(p) if o.user == "c2")
    assert derived.explained(p, c2)
    cause = derived._cause(p, c2)
    assert cause.startswith("it stopped (") and "ahead of 7 (7 came in 1.78 s after it)" in cause, cause

    run = _inside_run(0.2)
    p = next(p for p in history.from_events(run.events, "7") if p.crossing is not None)
    c2 = next(o for o in derived.reacting(p) if o.user == "c2")
    cause = derived._cause(p, c2)
    assert cause.startswith("it began to slow (") and "already in its conflict zone with 7" in cause, cause
    assert "it would have left it 2.29 s before 7 came in" in cause and "under 2 s is a conflict" in cause, cause
