"""The simulation as a producer: same seed, same events; valid envelopes numbered per source; a run.start
that carries the map, the rulebooks and the config; monitors that see only their cone; faults that
show as what they are."""
from __future__ import annotations

import json
from collections import defaultdict

import pytest

from reasoner.engine import sha256_text
from sim_replay.monitors import read_monitors
from sim_replay.maps import map_files
from sim_replay.sim_config import Behaviour, FaultRates, SimConfig
from sim_replay.simulation import Simulation
from store import validate_event

BUSY = SimConfig(vehicles=14, duration_s=45.0, seed=11, pedestrians=4, emergency_share=0.2,
                 behaviour=Behaviour(red_runner=0.3, amber_runner=0.3, stop_roller=0.4, speeder=0.3),
                 faults=FaultRates(misperceived_light=0.3, missed_road_user=0.2, speed_error=0.2, lost_event=0.01,
                                   recorder_stops=0.3))


@pytest.fixture(scope="module")
def busy():
    sim = Simulation(BUSY)
    return sim, list(sim.events())


def test_same_seed_same_events_byte_for_byte(busy):
    sim, first = busy
    again = list(Simulation(BUSY).events())
    assert json.dumps(first, sort_keys=True) == json.dumps(again, sort_keys=True)


def test_same_seed_same_truth_and_another_seed_another_run(busy):
    sim, first = busy
    again = Simulation(BUSY)
    list(again.events())
    assert json.dumps(sim.truth.to_json(), sort_keys=True) == json.dumps(again.truth.to_json(), sort_keys=True)
    other = list(Simulation(SimConfig(**{**BUSY.__dict__, "seed": 12})).events())
    assert [e["body"] for e in other if e["kind"] == "entity.state"] != \
        [e["body"] for e in first if e["kind"] == "entity.state"]


def test_every_event_is_valid_and_sources_count_up_from_zero_with_gaps_only_where_lost(busy):
    sim, events = busy
    seqs = defaultdict(list)
    for ev in events:
        validate_event(ev)
        seqs[ev["src"]].append(ev["seq"])
    lost = {(f.src, f.detail["seq"]) for f in sim.truth.faults if f.kind == "lost_event"}
    assert lost, "no event was lost at this rate and seed"
    for src, numbers in seqs.items():
        missing = set(range(max(numbers) + 1)) - set(numbers)
        assert numbers == sorted(numbers) and missing == {seq for s, seq in lost if s == src and seq <= max(numbers)}
    assert [e["t"] for e in events] == sorted(e["t"] for e in events)


def test_run_start_carries_the_map_the_rulebooks_and_the_config(busy):
    _, events = busy
    start = events[0]
    assert start["kind"] == "run.start" and start["src"] == "sim/world"
    body = start["body"]
    assert {j["id"] for j in body["map"]["junctions"]} == {"j1", "j2"} and len(body["map"]["monitors"]) == 3
    assert [b["name"] for b in body["rulebooks"]][:2] == ["highway_code.le", "monitors.le"]
    assert all(b["sha256"] == sha256_text(b["text"]) for b in body["rulebooks"])
    assert body["seed"] == 11 and body["config"]["vehicles"] == 14
    assert events[-1]["kind"] == "run.end"


def test_the_mix_and_the_summary(busy):
    sim, events = busy
    kinds = {e["kind"] for e in events}
    assert kinds >= {"entity.spawn", "entity.state", "signal.state", "vehicle.perception", "vehicle.decision",
                     "vehicle.trace", "monitor.observation", "ads.event", "entity.despawn"}
    spawned = [e["body"] for e in events if e["kind"] == "entity.spawn"]
    assert {"autonomous", "human", "none"} <= {b["driver"] for b in spawned}
    assert any(b.get("emergency") for b in spawned) and any(b["type"] == "pedestrian" for b in spawned)
    s = sim.summary
    assert s.events == len(events) and s.rulebook_queries > 0 and s.vehicles == 14
    assert s.potential_violations == sum(e["kind"] == "monitor.potential_violation" for e in events)
    signals = [e for e in events if e["kind"] == "signal.state"]
    assert {e["src"] for e in signals} == {f"signal/j1-{a}" for a in ("east", "north", "south", "west")}


def test_a_monitor_observes_only_what_is_inside_its_cone(busy):
    _, events = busy
    monitors = {m.id: m for m in read_monitors(map_files("paper").monitors)}
    where = {}
    observed = outside = 0
    for ev in events:
        if ev["kind"] == "entity.state" and ev["src"].startswith("vehicle/"):
            where[ev["src"].split("/")[1], ev["t"]] = (ev["body"]["x"], ev["body"]["y"])
        elif ev["kind"] == "monitor.observation":
            m = monitors[ev["src"].split("/")[1]]
            assert m.sees(ev["body"]["x"], ev["body"]["y"])
            assert (ev["body"]["vehicle"], ev["t"]) not in where or \
                where[ev["body"]["vehicle"], ev["t"]] == (ev["body"]["x"], ev["body"]["y"])
            observed += 1
    for (vid, t), (x, y) in where.items():
        if not any(m.sees(x, y) for m in monitors.values()):
            outside += 1
    assert observed > 100 and outside > 100, "the run should have road users both inside and outside the cones"
    seen = {(e["body"]["vehicle"], e["t"]) for e in events if e["kind"] == "monitor.observation"}
    for (vid, t), (x, y) in where.items():
        if not any(m.sees(x, y) for m in monitors.values()):
            assert (vid, t) not in seen


def test_a_camera_states_the_blue_lights_it_sees_not_a_call_it_cannot(busy):
    _, events = busy
    on_call, stated = {}, defaultdict(list)
    for ev in events:
        if ev["kind"] == "entity.state" and ev["src"].startswith("vehicle/"):
            on_call[ev["src"].split("/")[1]] = ev["body"]["emergency"]
        elif ev["kind"] == "monitor.observation":
            vid = ev["body"]["vehicle"]
            says = f"{vid} is on an emergency call" in ev["body"]["facts"]
            assert not says or on_call.get(vid), f"{vid}: a call stated with no blue lights"
            if on_call.get(vid):
                stated[ev["src"], vid].append(says)
    assert stated, "no vehicle on a call passed a monitor"
    for key, says in stated.items():        # the lights flash: stated from the first flash it sees on
        assert any(says) and all(says[says.index(True):]), key


def test_a_recorder_that_stops_publishes_nothing_of_its_own_after(busy):
    sim, events = busy
    stops = {f.src: f.t_s for f in sim.truth.faults if f.kind == "recorder_stops"}
    assert stops, "no recorder stopped at this rate and seed"
    own = ("vehicle.perception", "vehicle.decision", "vehicle.trace", "ads.event")
    t0 = events[0]["t"]
    for ev in events:
        if ev["src"] in stops and ev["kind"] in own:
            assert (ev["t"] - t0) / 1e9 < stops[ev["src"]]


def test_automated_vehicles_keep_a_dssad_record(busy):
    sim, events = busy
    spawned = {e["src"]: e["body"] for e in events if e["kind"] == "entity.spawn"}
    ads = [e for e in events if e["kind"] == "ads.event"]
    assert ads and all(spawned[e["src"]]["driver"] == "autonomous" for e in ads)
    assert all(spawned[e["src"]]["automation_level"] in (3, 4) for e in ads)
    firsts = {}
    for e in ads:
        firsts.setdefault(e["src"], e["body"]["event"])
    assert set(firsts.values()) == {"activated"}


def test_an_unmarked_police_car_is_a_car_on_a_call():
    from sim_replay.demand import Departure
    sim = Simulation(SimConfig(duration_s=20.0, pedestrians=0, on_call_share=1.0, call_change_per_min=0.0),
                     departures=[Departure("101", 0.0, "car", "emergency", True, "w_j1", "j2_e")])
    events = list(sim.events())
    (spawn,) = [e["body"] for e in events if e["kind"] == "entity.spawn"]
    assert spawn["type"] == "car" and spawn["emergency"] is True and spawn["driver"] == "human"
    assert sim.truth.road_users["101"]["unmarked"] is True
    assert all(e["body"]["emergency"] for e in events if e["kind"] == "entity.state")


def test_progress_is_reported_in_world_seconds_up_to_the_end():
    seen = []
    sim = Simulation(SimConfig(vehicles=3, duration_s=25.0, pedestrians=0),
                     progress=lambda done, total: seen.append((done, total)))
    list(sim.events())
    assert seen[-1] == (25.0, 25.0) and [d for d, _ in seen] == sorted(d for d, _ in seen) and len(seen) >= 3
    assert sim.summary.world_s == 25.0 and sim.summary.events_per_s > 0


def test_a_speed_error_shows_in_the_cameras_readings(busy):
    sim, events = busy
    errors = {(f.src.split("/")[1], f.detail["vehicle"]): f.detail["factor"]
              for f in sim.truth.faults if f.kind == "speed_error"}
    assert errors
    speed = {(e["src"].split("/")[1], e["t"]): e["body"]["speed_mps"]
             for e in events if e["kind"] == "entity.state" and e["src"].startswith("vehicle/")}
    high = 0
    for e in events:
        if e["kind"] == "monitor.observation" and (e["src"].split("/")[1], e["body"]["vehicle"]) in errors:
            true = speed.get((e["body"]["vehicle"], e["t"]))
            if true is not None and true > 1.0:
                assert e["body"]["speed_mps"] > true
                high += 1
    assert high > 0
