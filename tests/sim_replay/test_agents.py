"""The agents do what their kind does, and the law is the rulebook's: a red-running driver crosses on
red; an automated car that reads the light right holds at red, one that misreads it crosses and
says it saw green; the ambulance on a call goes through the red only when nothing is approaching.

j1's plan (paper.tll.xml): r1 (west arm) green 2-29 s, amber 29-32, red 32-75, red and amber 75-77;
r2 (north and south arms) green 36-58. A car set off at the west end reaches j1's line in about 14 s.
"""
from __future__ import annotations

import pytest

from sim_replay.demand import Departure
from sim_replay.sim_config import Behaviour, FaultRates, SimConfig
from sim_replay.simulation import Simulation

CAREFUL = Behaviour(speeder=0, amber_runner=0, red_runner=0, stop_roller=0, no_give_way=0, recorder=1.0)
QUIET = dict(pedestrians=0, ads_event_per_min=0.0, call_change_per_min=0.0, behaviour=CAREFUL)


def run(departures, duration_s=60.0, **config):
    sim = Simulation(SimConfig(**{**QUIET, "duration_s": duration_s, **config}), departures=departures)
    events = list(sim.events())
    return sim, events


def crossings(sim, vehicle):
    return [a for a in sim.truth.acts if a.vehicle == vehicle and a.kind == "crossed the stop line"]


def bodies(events, vehicle, kind):
    return [e["body"] for e in events if e["src"] == f"vehicle/{vehicle}" and e["kind"] == kind]


def test_a_red_running_driver_crosses_on_red():
    runner = Behaviour(speeder=0, amber_runner=0, red_runner=1.0, stop_roller=0, no_give_way=0, propensity=1.0,
                       recorder=1.0)
    sim, events = run([Departure("101", 24.0, "car", "human", False, "w_j1", "j2_e")], behaviour=runner)
    (act, *_) = crossings(sim, "101")
    assert act.junction == "j1" and act.approach == "west" and act.light == "red"
    assert act.why.startswith("red runner") and act.driver == "human"
    assert not bodies(events, "101", "vehicle.trace"), "a human driver does not ask the rulebook"
    assert bodies(events, "101", "vehicle.decision")[-1]["proceeds"] is True


def test_an_automated_car_that_reads_the_light_holds_at_red():
    sim, events = run([Departure("101", 24.0, "car", "autonomous", False, "w_j1", "j2_e")], duration_s=85.0)
    (act, *_) = crossings(sim, "101")
    assert act.junction == "j1" and act.light == "green" and act.t_s > 75.0 and act.stopped_at_line
    decisions = bodies(events, "101", "vehicle.decision")
    assert any(d["permitted"] is False and d["proceeds"] is False for d in decisions)
    traces = bodies(events, "101", "vehicle.trace")
    assert traces and all(t["query"] == "101 can enter the junction" and t["proof"] for t in traces)
    assert any("101 has red light" in p["facts"] for p in bodies(events, "101", "vehicle.perception"))


def test_an_automated_car_that_misreads_red_as_green_crosses_and_says_it_saw_green():
    sim, events = run([Departure("101", 24.0, "car", "autonomous", False, "w_j1", "j2_e")],
                      faults=FaultRates(misperceived_light=1.0))
    (act, *_) = crossings(sim, "101")
    assert act.light == "red" and act.fault == "misperceived_light: saw green"
    last = bodies(events, "101", "vehicle.perception")[-1]["facts"]
    assert "101 has green light" in last and "101 has red light" not in last
    decision = bodies(events, "101", "vehicle.decision")[-1]
    assert decision["permitted"] is True and decision["proceeds"] is True
    (fault,) = [f for f in sim.truth.faults if f.kind == "misperceived_light"]
    assert fault.detail == {"light": "red", "perceived": "green"}


def test_the_ambulance_on_a_call_crosses_on_red_when_nothing_approaches():
    sim, events = run([Departure("253", 25.0, "ambulance", "emergency", False, "w_j1", "j2_e")], on_call_share=1.0)
    (act, *_) = crossings(sim, "253")
    assert act.light == "red" and act.on_call and act.driver == "human"
    assert all(d["permitted"] for d in bodies(events, "253", "vehicle.decision"))


@pytest.mark.parametrize("gap_s", [0.0, 3.0])
def test_the_ambulance_on_a_call_waits_while_cross_traffic_approaches(gap_s):
    cross = [Departure(str(110 + n), 30.0 + gap_s + 2.5 * n, "car", "human", False, "s1_j1", "j1_n1")
             for n in range(3)]
    sim, events = run([Departure("253", 30.0, "ambulance", "emergency", False, "w_j1", "j2_e"), *cross],
                      on_call_share=1.0, duration_s=75.0)
    decisions = bodies(events, "253", "vehicle.decision")
    perceptions = bodies(events, "253", "vehicle.perception")
    assert len(decisions) == len(perceptions)
    for d, p in zip(decisions, perceptions):       # the rulebook decides: never a go with a road user forced
        if any("would force" in f for f in p["facts"]):
            assert d["permitted"] is False
    assert any(d["permitted"] is False for d in decisions), "it never had to wait for the cross traffic"
    (act, *_) = crossings(sim, "253")
    assert act.light == "red"
    assert all(decel < 2.0 for _, decel in act.reactions), f"a road user braked hard for it: {act.reactions}"
    first_cross = min(a.t_s for c in cross for a in crossings(sim, c.id))
    assert act.t_s > first_cross


def test_an_automated_car_that_misses_the_major_road_traffic_pulls_out_in_front_of_it():
    main_road = [Departure(str(110 + n), 3.0 + 2.0 * n, "car", "human", False, "e_j2", "j1_w") for n in range(4)]
    sim, events = run([Departure("101", 5.0, "car", "autonomous", False, "s2_j2", "j2_n2"), *main_road],
                      duration_s=40.0, faults=FaultRates(missed_road_user=1.0))
    missed = {f.detail["missed"] for f in sim.truth.faults if f.kind == "missed_road_user"}
    assert missed
    for p in bodies(events, "101", "vehicle.perception"):
        assert not any(f"{other} is approaching 101" in p["facts"] for other in missed)
    (act, *_) = crossings(sim, "101")
    assert act.line == "give_way" and act.fault.startswith("missed_road_user")
