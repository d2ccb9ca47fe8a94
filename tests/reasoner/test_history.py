"""Junction passages rebuilt from what a foreign producer records (reasoner/history.py): DESIGN's
core vocabulary and measured fields only, at sample rates other than the simulation's 10 Hz.

Each scenario says beside it what the law makes of the act; these tests check only what the
history measures (the rulebooks decide, elsewhere)."""
import pytest

from reasoner import derived, history, margins
from store import Store
from tests.helpers.foreign import SECOND, T0, Foreign, Motion, crossroads, irregular, ns, rate


def one(events, vehicle="7", at=None):
    found = history.from_events(events, vehicle)
    assert found, "no passage"
    return history.passage_at(found, ns(at)) if at is not None else found[0]


def sentences(passage, at):
    return {f.sentence for f in derived.facts(passage, ns(at))}


def red_cycle(run, amber_at, approach="west"):
    run.lights("J1", approach, [(0, "green"), (amber_at, "amber"), (amber_at + 3, "red")])


# --- red light ---------------------------------------------------------------------------------

def test_a_car_braking_to_a_stop_before_the_line_at_red_has_not_crossed():
    """HC 176 / TSRGD Sch 14 para 5(3): the offence is proceeding beyond the stop line; a car that
    stops behind it has committed none, however it moved a moment earlier."""
    run = Foreign()
    run.spawn("7")
    red_cycle(run, amber_at=2.0)
    motion = Motion.stopping_at(-90, 12.0, -13.0, wait=30)          # stands 1 m before the line
    run.drive("7", motion, "west", rate(2, 0, 20))
    p = one(run.events)
    assert p.approach == "west" and p.line is not None and p.crossing is None and p.entered is None
    assert p.standstills and p.standstills[-1].at_line and abs(p.standstills[-1].to_line_m - 1.0) < 0.01
    facts = sentences(p, 15)
    assert {"7 has red light", "7 is stopped", "7 has speed of 0"} <= facts
    assert not any("crossed" in f or "in the junction" in f for f in facts)


@pytest.mark.parametrize("speed, lag", [(8.0, 0.3), (13.4, 1.0), (17.9, 2.5), (11.0, 4.0)])
@pytest.mark.parametrize("times", ["2 Hz", "5 Hz", "irregular"])
def test_red_light_runners_cross_on_red_with_the_lag_after_red(speed, lag, times):
    """HC 176: crossing the stop line on red, `lag` seconds after it turned red (punishable unless an
    exception applies); the margin is that lag, correct to the interpolation."""
    motion = Motion(-140, speed)
    crossing = motion.when(-12.0)
    red = crossing - lag
    run = Foreign()
    run.spawn("7")
    run.lights("J1", "west", [(0, "green"), (red - 3, "amber"), (red, "red")])
    sample_times = {"2 Hz": rate(2, 0, crossing + 6), "5 Hz": rate(5, 0, crossing + 6),
                    "irregular": irregular(0, crossing + 6, seed=int(speed * 10 + lag * 100))}[times]
    run.drive("7", motion, "west", sample_times)
    p = one(run.events)
    c = p.crossing
    assert c is not None and c.light.colour == "red"
    # steady speed: linear interpolation is exact, up to the 1 mm the producer rounds positions to
    assert abs(c.t - ns(crossing)) < 0.001 / speed * SECOND + 1000
    a, b = c.moment.used
    assert a.t <= c.t <= b.t and c.moment.method.startswith("linear interpolation between entity.state")
    m = margins.margin(p, "enter the junction", "HC 176")
    assert m.unit == "s" and abs(m.value - lag) < 0.001
    assert {"7 has crossed the stop line", "7 crossed the stop line on red light"} <= sentences(p, crossing + 0.01)
    assert "7 has red light" in sentences(p, crossing - 0.3)
    assert "7 has red light" not in sentences(p, crossing + 0.3)


def test_a_car_over_the_line_on_green_that_clears_on_red_crossed_on_green():
    """HC 175/176: the light that matters is the one shown when the car crossed its line; one
    already over it when the light changes clears the junction lawfully."""
    motion = Motion(-60, 5.0, [(20.0, -0.2)])          # slowing through the junction
    crossing = motion.when(-12.0)
    run = Foreign()
    run.spawn("7")
    run.lights("J1", "west", [(0, "green"), (crossing + 0.5, "amber"), (crossing + 3.5, "red")])
    run.drive("7", motion, "west", rate(5, 0, crossing + 8))
    p = one(run.events)
    assert p.crossing.light.colour == "green"
    late = crossing + 4.0                                 # red now, still in the junction
    facts = sentences(p, late)
    assert "7 crossed the stop line on green light" in facts and "7 is in the junction" in facts
    assert not any(f.endswith("red light") for f in facts)
    assert [c.light.colour for c in p.changes] == []      # no change before it crossed
    assert margins.margin(p, "enter the junction") is None   # crossed on green: nothing to measure


# --- amber, rule 126 ------------------------------------------------------------------------------

def test_amber_appearing_when_too_close_to_stop():
    """HC 175: amber means stop unless so close that pulling up might cause an accident. At 30 mph
    (13.4 m/s) rule 126 gives 23 m; amber 15 m before the line: too close, it may go on."""
    motion = Motion(-100, 13.41)
    amber = motion.when(-12.0 - 15.0)
    run = Foreign()
    run.spawn("7")
    run.lights("J1", "west", [(0, "green"), (amber, "amber"), (amber + 3, "red")])
    run.drive("7", motion, "west", rate(2, 0, amber + 6))
    p = one(run.events)
    change = p.changes[0]
    assert change.light.colour == "amber" and abs(change.to_line_m - 15.0) < 0.01
    fact = next(f for f in derived.facts(p, ns(amber + 2)) if f.sentence == "7 is too close to the stop line to stop safely")
    assert "15.0 m before the line" in fact.method and "23.0 m" in fact.method and "rule 126" in fact.method
    assert p.crossing.light.colour == "amber"
    m = margins.margin(p, "enter the junction", "HC 175")
    assert (m.quantity, m.unit, m.value) == ("metres from the stop line when amber came", "m", 15.0)
    assert dict((q, v) for q, v, _ in m.figures)["stopping distance at that speed (rule 126)"] == 23.0


def test_amber_appearing_far_away_is_not_too_close():
    """HC 175: amber 40 m before the line at 30 mph (23 m needed): it can stop, and should."""
    motion = Motion(-100, 13.41)
    amber = motion.when(-12.0 - 40.0)
    run = Foreign()
    run.spawn("7")
    run.lights("J1", "west", [(0, "green"), (amber, "amber"), (amber + 3, "red")])
    run.drive("7", motion, "west", irregular(0, amber + 6, seed=3))
    p = one(run.events)
    assert abs(p.changes[0].to_line_m - 40.0) < 0.01
    assert "7 is too close to the stop line to stop safely" not in sentences(p, amber + 3.5)
    assert p.crossing.light.colour in ("amber", "red")


# --- Stop and Give Way ------------------------------------------------------------------------------

def stop_run():
    return Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop")], monitors=[])


def test_a_stop_sign_roll_through_never_stood_still():
    """HC 171 (RTA s.36): stop behind the line at a Stop sign; rolling through at 2-3 m/s is not
    a stop."""
    motion = Motion(-70, 10.0, [(3.0, -2.5), (4.0, 1.0)])        # down to 2.5 m/s, then away
    run = stop_run()
    run.spawn("7")
    run.drive("7", motion, "west", rate(4, 0, 12))
    p = one(run.events)
    assert p.line.kind == "stop_sign" and p.crossing is not None and not p.standstills
    assert "7 has stopped at the stop line" not in sentences(p, 11)
    m = margins.margin(p, "enter the junction", "HC 171")
    states = [e["body"] for e in run.events if e["kind"] == "entity.state"]
    near = [s for a, b in zip(states, states[1:]) if a["x"] <= -12.0 + 1.0 and b["x"] >= -12.0 - 5.0 and b["x"] <= -12.0
            for s in (a, b)]             # the intervals reaching from 1 m past the line (x = -12) to 5 m before it
    slowest = min(s["speed_mps"] for s in near)
    assert m.quantity == "slowest measured speed before the Stop line"
    assert abs(m.value - slowest * 2.2369362920544) <= 0.01 and m.value - m.uncertainty > 0.5 and not m.unproven, m


def test_a_lawful_stop_stands_at_the_line_then_goes():
    """HC 171: stopped behind the line (here 2 s), then away when safe: lawful."""
    motion = Motion.stopping_at(-60, 10.0, -13.5, wait=2.0, then=10.0)
    run = stop_run()
    run.spawn("7")
    run.drive("7", motion, "west", rate(2, 0, 20))
    p = one(run.events)
    assert p.crossing is not None
    stop = next(s for s in p.standstills if s.at_line)
    assert stop.duration_s >= 1.5 and stop.last.t <= p.crossing.t
    fact = next(f for f in derived.facts(p, p.crossing.t + SECOND) if f.sentence == "7 has stopped at the stop line")
    assert "before the Stop line" in fact.method
    assert margins.margin(p, "enter the junction", "HC 171").value >= 1.5


def give_way_run():
    """J1 where an east-west minor road meets a north-south main road at Give Way lines."""
    return Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds={"west": "give_way", "east": "give_way"})],
                   monitors=[])


def test_a_give_way_failure_that_makes_a_main_road_car_brake():
    """HC 172 / TSRGD: give way to traffic on the main road; emerging so that a main-road driver
    must brake hard is the failure (the rulebook decides, on these facts)."""
    run = give_way_run()
    run.spawn("7")
    run.spawn("8")
    minor = Motion(-60, 8.0)                                   # does not slow at the Give Way line
    main = Motion(-70, 13.0, [(2.5, 0.0), (3.0, -4.5)])        # brakes at 4.5 m/s² from 2.5 s, stops 19 m short
    run.drive("7", minor, "west", rate(5, 0, 10))
    run.drive("8", main, "north", rate(5, 0, 10))              # from the north: the main road
    p = one(run.events)
    assert p.junction.major == frozenset({"north", "south"})
    other = next(o for o in p.others if o.user == "8")
    assert other.arm == "north" and other.main_road and other.braking.decel_mps2 > 4.0
    crossing = p.crossing.t / SECOND - T0 / SECOND
    assert {"7 would force 8 to change speed or course", "8 is on the main road"} <= sentences(p, crossing)
    assert {"8 is approaching 7", "8 is on the main road"} <= sentences(p, crossing - 2.5)   # 8 braking, 7 coming
    m = margins.margin(p, "enter the junction", "HC 172")
    assert m.unit == "m/s²" and m.value > 4.0


def test_a_main_road_car_that_keeps_its_speed_was_not_forced():
    run = give_way_run()
    run.spawn("7")
    run.spawn("8")
    run.drive("7", Motion(-60, 8.0), "west", rate(5, 0, 10))
    run.drive("8", Motion(-90, 13.0), "north", rate(5, 0, 10))
    p = one(run.events)
    assert not any("would force" in f for f in sentences(p, 6))


def test_a_main_road_car_braking_behind_a_slower_one_was_not_forced():
    """The same failure to slow at the Give Way line, but the main-road car 8 brakes because the
    car 9 ahead of it in its lane is slowing to a stop: following within the two-second rule's
    headway (HC 126) explains the braking, so 7 is not shown to force 8 (others.py)."""
    run = give_way_run()
    for v in ("7", "8", "9"):
        run.spawn(v)
    run.drive("7", Motion(-60, 8.0), "west", rate(5, 0, 10))
    run.drive("9", Motion(-55, 13.0, [(2.5, 0.0), (3.0, -4.5)]), "north", rate(5, 0, 10))   # ahead, braking
    run.drive("8", Motion(-70, 13.0, [(2.5, 0.0), (3.0, -4.5)]), "north", rate(5, 0, 10))   # 15 m behind it
    p = one(run.events)
    eight = next(o for o in p.others if o.user == "8")
    assert eight.braking.decel_mps2 > 4.0 and eight.followed == "9"
    crossing = p.crossing.t / SECOND - T0 / SECOND
    assert "7 would force 8 to change speed or course" not in sentences(p, crossing)
    # the leader 9 stops 2 m short of 7's path 2 s before 7 gets there; unslowed it would have
    # passed the conflict zone over 2 s ahead of 7 (conflicts.PET_MAX_S): not shown forced by 7 either
    assert "7 would force 9 to change speed or course" not in sentences(p, crossing)


# --- box junction ---------------------------------------------------------------------------------

def test_a_blocked_box_junction():
    """HC 174: do not enter the box until your exit is clear. Car 9 queues just beyond the box
    on the east exit; car 7 enters from the west anyway and stops in the box."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "none", kinds={}, box=True)], monitors=[])
    for v in ("7", "9"):
        run.spawn(v)
    queued = Motion(20.0, 0.0)                                  # 8 m beyond the box edge (12 m), standing
    run.drive("9", queued, "west", rate(2, 0, 20))
    entering = Motion.stopping_at(-60, 8.0, 4.0, wait=10.0)    # stops 4 m past the centre, in the box
    run.drive("7", entering, "west", rate(2, 0, 20))
    p = one(run.events)
    entry = p.entered.t / SECOND - T0 / SECOND
    at_entry = sentences(p, entry + 0.01)
    assert "7 is at a box junction" in at_entry
    assert "the exit of the box junction is clear for 7" not in at_entry
    later = sentences(p, 18)
    assert {"7 is stopped in the box junction", "7 is in the junction"} <= later
    assert margins.margin(p, "enter the box junction").unit == "s"


def test_a_box_junction_with_a_clear_exit():
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "none", kinds={}, box=True)], monitors=[])
    run.spawn("7")
    run.drive("7", Motion(-60, 8.0), "west", rate(2, 0, 15))
    p = one(run.events)
    assert "the exit of the box junction is clear for 7" in sentences(p, p.entered.t / SECOND - T0 / SECOND)


# --- emergency calls and speed ----------------------------------------------------------------------

def test_an_emergency_vehicle_on_and_then_off_a_call():
    """TSRGD Sch 14 para 5(6), RTRA s.87: the exemptions follow the purpose (the call), not the type."""
    run = Foreign()
    run.spawn("3", "ambulance", emergency=True)
    run.drive("3", Motion(-90, 12.0), "west", rate(2, 0, 5))
    run.drive("3", Motion(-90, 12.0), "west", rate(2, 5.5, 12), extra={"emergency": False})
    p = one(run.events, "3")
    assert "3 is on an emergency call" in sentences(p, 4)
    assert "3 is on an emergency call" not in sentences(p, 6)
    on = next(f for f in derived.facts(p, ns(4)) if f.sentence == "3 is on an emergency call")
    assert on.evidence[0].kind == "entity.spawn"


def test_an_unmarked_car_on_a_call_is_on_a_call():
    run = Foreign()
    run.spawn("5", "car", emergency=True)
    run.drive("5", Motion(-90, 12.0), "west", rate(2, 0, 10))
    assert "5 is on an emergency call" in sentences(one(run.events, "5"), 5)


def test_speeding_in_a_30_limit():
    """RTRA 1984 s.89: 40 mph (17.9 m/s) in a 30 limit, 10 mph over."""
    run = Foreign()
    run.spawn("7")
    run.drive("7", Motion(-120, 17.88), "west", rate(2, 0, 10))
    p = one(run.events)
    assert {"7 has speed of 40", "the speed limit is 30"} <= sentences(p, 3)
    m = margins.margin(p, "exceed the speed limit")
    assert (m.quantity, m.unit) == ("mph over the speed limit", "mph") and abs(m.value - 10.0) < 0.1


# --- partial evidence ----------------------------------------------------------------------------------

def test_sequence_gaps_around_the_act_are_reported_as_uncertain():
    """Events lost around the crossing: the crossing is still bracketed, but said to be uncertain."""
    motion = Motion(-100, 12.0)
    crossing = motion.when(-12.0)
    run = Foreign()
    run.spawn("7")
    run.lights("J1", "west", [(0, "green"), (crossing - 4, "amber"), (crossing - 1, "red")])
    states = run.drive("7", motion, "west", rate(5, 0, crossing + 5))
    lost = [e["seq"] for e in states if abs(e["t"] - ns(crossing)) < 0.7 * SECOND]
    run.drop("vehicle/7", lost)
    p = one(run.events)
    assert p.crossing is not None and p.crossing.moment.uncertain
    assert "missing" in p.crossing.moment.uncertain and "vehicle/7" in p.crossing.moment.uncertain
    fact = next(f for f in derived.facts(p, ns(crossing + 1)) if f.sentence == "7 crossed the stop line on red light")
    assert fact.uncertain and "missing" in fact.uncertain
    assert any("missing" in note for note in p.uncertain)


def test_a_lost_signal_change_leaves_the_light_at_the_crossing_uncertain():
    """The red report is lost: the record shows amber at the crossing, and says a change may be missing."""
    motion = Motion(-100, 12.0)
    crossing = motion.when(-12.0)
    run = Foreign()
    run.lights("J1", "west", [(0, "green"), (crossing - 4, "amber"), (crossing - 1, "red"), (crossing + 20, "green")])
    run.drive("7", motion, "west", rate(5, 0, crossing + 5))
    run.drop("signal/J1-west", [2])
    p = one(run.events)
    assert p.crossing.light.colour == "amber"
    assert "signal/J1-west event 2 missing" in p.crossing.light_uncertain
    fact = next(f for f in derived.facts(p, ns(crossing + 1)) if f.sentence == "7 crossed the stop line on amber light")
    assert "a change of the light may be missing" in fact.uncertain


def test_measurements_only_from_a_monitor():
    """A human-driven car with no recorder: the camera's measured positions and speeds are enough."""
    motion = Motion(-75, 11.0)
    crossing = motion.when(-12.0)
    run = Foreign()
    red_cycle(run, amber_at=crossing - 5)
    run.watch("7", motion, "west", rate(4, 0, crossing + 4), facts=["7 is of type car"])
    p = one(run.events)
    assert p.series == "monitor.observation" and p.crossing.light.colour == "red"
    assert p.crossing.moment.used[0].ref.kind == "monitor.observation"
    assert "7 crossed the stop line on red light" in sentences(p, crossing + 1)


def test_sentences_only_give_no_passage_and_no_crash():
    run = Foreign()
    red_cycle(run, amber_at=2)
    for i in range(10):
        run.emit("monitor/m1", ns(i), "monitor.observation", {"vehicle": "7", "facts": ["7 has red light"]})
        run.emit("vehicle/7", ns(i), "vehicle.perception", {"facts": ["7 is of type car", "7 has red light"]})
    assert history.from_events(run.events, "7") == ()


@pytest.mark.parametrize("junk", [float("nan"), float("inf"), "9.0", True, 1e300, -5.0, None, [1, 2], {"a": 1}])
def test_hostile_values_are_left_out_never_a_crash(junk):
    run = Foreign()
    red_cycle(run, amber_at=2)
    motion = Motion(-80, 10.0)
    states = run.drive("7", motion, "west", rate(2, 0, 12))
    for e in states[::3]:
        e["body"]["x"] = junk
    for e in states[1::3]:
        e["body"]["speed_mps"] = junk
    states[2]["body"]["heading_deg"] = junk
    run.events.append({"v": 1, "run": "foreign-1", "src": "signal/J1-west", "seq": 99, "t": ns(5), "kind": "signal.state",
                       "body": {"junction": junk, "colour": junk}})
    found = history.from_events(run.events, "7")
    for p in found:
        for at in (1, 5, 9):
            derived.facts(p, ns(at))
        margins.margin(p, "enter the junction")
        p.to_json()


def test_a_hostile_map_is_read_as_far_as_it_goes():
    run = Foreign(junctions=[{"id": "J1", "x": "0", "y": 0.0, "control": "lights"},
                             {"id": 5, "x": 0.0, "y": 0.0},
                             {"id": "J2", "x": 0.0, "y": 0.0, "control": "lights",
                              "stop_lines": [{"approach": "west", "from": [0, 0], "to": [0, 0]}, "junk", None],
                              "box": [[1, 2]], "box_m": float("nan"), "major": "everything"}],
                  roads=[{"id": "R", "from": [0, 0], "to": [float("inf"), 0]}, {"junk": True}])
    run.drive("7", Motion(-80, 10.0), "west", rate(2, 0, 12), junction="J2")
    found = history.from_events(run.events, "7")
    assert [p.junction.id for p in found] == ["J2"]
    assert found[0].line is None and found[0].uncertain


def test_a_long_record_costs_bounded_samples():
    run = Foreign()
    states = run.drive("7", Motion(-5000, 10.0), "west", rate(10, 0, 600))   # ten minutes at 10 Hz
    assert len(states) == 6001
    found = history.from_events(run.events, "7")
    assert len(found) == 1 and len(found[0].samples) < 400                    # only what lies near J1


# --- the store gives what the events give -----------------------------------------------------------

def test_from_a_store_as_from_the_events(tmp_path):
    motion = Motion(-100, 12.0)
    crossing = motion.when(-12.0)
    run = Foreign()
    run.spawn("7")
    run.spawn("8")
    run.lights("J1", "west", [(0, "green"), (crossing - 4, "amber"), (crossing - 1, "red")])
    run.drive("7", motion, "west", rate(5, 0, crossing + 6))
    run.drive("8", Motion(-60, 13.0, [(3.0, -3.0)]), "north", rate(5, 0, crossing + 6))
    run.watch("7", motion, "west", rate(2, 0, crossing + 6))
    run.watch("8", Motion(-60, 13.0, [(3.0, -3.0)]), "north", rate(2, 0, crossing + 6))
    with Store(tmp_path / "gaps.db") as store:
        assert not store.append(run.events).rejected
        from_store = history.passage(store, "foreign-1", "7", ns(crossing))
    from_events = history.passage_at(history.from_events(run.events, "7", around=ns(crossing)), ns(crossing))
    assert from_store.crossing.t == from_events.crossing.t
    assert from_store.crossing.light == from_events.crossing.light
    assert [o.user for o in from_store.others] == ["8"]
    assert sentences(from_store, crossing + 0.5) == sentences(from_events, crossing + 0.5)


def test_a_store_with_lost_events_reports_the_gap(tmp_path):
    motion = Motion(-100, 12.0)
    crossing = motion.when(-12.0)
    run = Foreign()
    red_cycle(run, amber_at=crossing - 5)
    states = run.drive("7", motion, "west", rate(2, 0, crossing + 5))
    run.drop("vehicle/7", [e["seq"] for e in states if abs(e["t"] - ns(crossing)) < 0.6 * SECOND])
    with Store(tmp_path / "gaps.db") as store:
        store.append(run.events)
        p = history.passage(store, "foreign-1", "7", ns(crossing))
    assert p.crossing.moment.uncertain and "missing" in p.crossing.moment.uncertain
