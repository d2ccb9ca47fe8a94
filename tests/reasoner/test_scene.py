"""The scene at a time (reasoner/scene.py), on the paper's run: every fact with its event, the
same whatever order the events arrived in, control from the ads.event history, and the
validator's answer when asked."""
import json
import random

import pytest

from reasoner.investigation import Investigation
from reasoner.scene import UnknownVehicle, run_start, scene
from sim_replay.paper import RUN, SECOND, T0, paper_run
from store import NoSuchRun, Store


def ev(src, seq, t, kind, body):
    return {"v": 1, "run": RUN, "src": src, "seq": seq, "t": t, "kind": kind, "body": body}


def av_events():
    """An SAE level 3 car (a user-in-charge in the seat): the feature engaged at 2 s, a transition
    demand at 20 s that nobody answers, and a car only the monitor saw (no recorder)."""
    src = "vehicle/300"
    return [
        ev(src, 0, T0 + SECOND, "entity.spawn", {"type": "car", "driver": "human", "automation_level": 3}),
        ev(src, 1, T0 + 2 * SECOND, "ads.event", {"event": "activated"}),
        ev(src, 2, T0 + 20 * SECOND, "ads.event", {"event": "transition_demand", "reason": "end of motorway"}),
        ev("monitor/m1", 100, T0 + 50 * SECOND, "monitor.observation",
           {"vehicle": "77", "facts": ["77 is of type bus", "77 has red light"]}),
        ev(src, 3, T0 + 55 * SECOND, "entity.despawn", {"reason": "parked"}),
    ]


@pytest.fixture(scope="module")
def store(tmp_path_factory):
    with Store(tmp_path_factory.mktemp("scene") / "paper.db") as s:
        s.append(paper_run())
        yield s


def at(seconds):
    return T0 + int(seconds * SECOND)


def test_car_173_at_ten_seconds(store):
    sc = scene(store, RUN, at(10.0))
    assert (sc.t_iso, sc.offset, sc.note) == ("2024-11-21T08:00:10.000Z", "+10s", None)
    assert [b.name for b in sc.rulebooks] == ["paper.le"]
    car = next(v for v in sc.vehicles if v.vehicle == "173").to_json()
    red = next(f for f in car["vehicle_scenario"] if f["fact"] == "173 has red light")
    assert red["evidence"] == {"run": RUN, "src": "vehicle/173", "seq": 2, "t": at(9.5), "kind": "vehicle.perception"}
    typed = next(f for f in car["vehicle_scenario"] if f["fact"] == "173 is of type car")
    assert typed["evidence"]["kind"] == "entity.spawn"
    action = car["vehicle_action"]
    assert (action["action"], action["proceeds"], action["goal"]) == ("enter the junction", True,
                                                                      "173 can enter the junction")
    assert action["evidence"]["kind"] == "vehicle.decision"
    assert car["control"]["in_control"] == "driver"
    assert car["state"]["junction"] == "j1" and car["state"]["evidence"]["seq"] == 4
    (m1,) = car["monitor_scenarios"]
    assert m1["monitor"] == "monitor/m1"
    assert [(f["fact"], f["evidence"]["kind"]) for f in m1["facts"]] == [("173 has red light", "monitor.observation")]
    validator = car["validator_scenario"]
    assert validator["goal"] == "173 can enter the junction" and validator["judged_on"] == "vehicle scenario"
    assert validator["facts"] == car["vehicle_scenario"]
    assert "lawful" not in validator                 # no Prolog for the whole scene unless asked
    assert [s.to_json() for s in sc.signals] == [{"junction": "j1", "approach": "west", "colour": "red",
                              "since": {"run": RUN, "src": "signal/j1-west", "seq": 1, "t": at(7),
                                        "kind": "signal.state"},
                              "evidence": {"run": RUN, "src": "signal/j1-west", "seq": 1, "t": at(7),
                                           "kind": "signal.state"}}]
    (monitor,) = sc.monitors
    assert monitor.placed("junction") == "j1" and monitor.observed == ("173",)
    json.dumps(sc.to_json())                         # plain JSON data


def test_before_a_vehicle_perceives_its_scenario_is_its_spawn(store):
    car = scene(store, RUN, at(5), vehicle="173", judge=False).vehicles[0].to_json()
    assert [f["fact"] for f in car["vehicle_scenario"]] == ["173 is of type car"]
    assert car["vehicle_action"] is None and car["monitor_scenarios"] == []


def test_judging_asks_the_validator_rulebook(store):
    inv = Investigation(store)
    car = scene(store, RUN, at(10), vehicle="173", investigation=inv).vehicles[0].validator_scenario.to_json()
    assert car["lawful"] is False and car["rulebook"]["name"] == "paper.le"
    assert car["rulebook"]["sha256"] == inv.ruleset(RUN)["validator"].rulebook.sha256
    ambulance = scene(store, RUN, at(40), vehicle="253", investigation=inv).vehicles[0].validator_scenario.to_json()
    assert ambulance["lawful"] is True and "is among the lawful actions" in ambulance["why"]
    whole = scene(store, RUN, at(40), judge=True, investigation=inv)
    assert {v.vehicle: v.validator_scenario.judged.lawful for v in whole.vehicles if v.validator_scenario.judged} == {"173": False, "253": True}


def test_the_scene_does_not_depend_on_arrival_order(tmp_path):
    events = paper_run() + av_events()
    shuffled = events[:]
    random.Random(11).shuffle(shuffled)
    with Store(tmp_path / "a.db") as a, Store(tmp_path / "b.db") as b:
        a.append(events)
        for i in range(0, len(shuffled), 3):                 # small batches, out of order
            b.append(shuffled[i:i + 3])
        for seconds in (0, 9.5, 10, 25, 40, 50, 56, 60):
            assert scene(a, RUN, at(seconds)) == scene(b, RUN, at(seconds))


def test_control_follows_the_ads_history(tmp_path):
    with Store(tmp_path / "av.db") as s:
        s.append(paper_run() + av_events())

        def control(seconds):
            return scene(s, RUN, at(seconds), vehicle="300", judge=False).vehicles[0].to_json()["control"]

        assert control(1.5)["in_control"] == "driver"
        assert control(2)["in_control"] == "self-driving feature"
        pending = control(29.9)
        assert pending["in_control"] == "self-driving feature" and pending["transition_demand"]["seq"] == 2
        expired = control(30)                                # 10 s unanswered (UN R157 5.4.4.1)
        assert expired["in_control"] == "user-in-charge" and expired["transition_demand_expired"]


def test_vehicles_present_and_the_unknown_vehicle_error(tmp_path):
    with Store(tmp_path / "av.db") as s:
        s.append(paper_run() + av_events())
        assert [v.vehicle for v in scene(s, RUN, at(50)).vehicles] == ["77", "173", "253", "300"]
        bus = scene(s, RUN, at(50), vehicle="77", judge=False).vehicles[0].to_json()
        assert not bus["recorded"] and bus["validator_scenario"]["judged_on"] == "monitor scenario"
        assert [f["fact"] for f in bus["validator_scenario"]["facts"]] == ["77 is of type bus", "77 has red light"]
        assert [v.vehicle for v in scene(s, RUN, at(56)).vehicles] == ["77", "173", "253"]
        with pytest.raises(UnknownVehicle, match="left the run") as gone:
            scene(s, RUN, at(56), vehicle="300")
        assert "173, 253" in str(gone.value)
        with pytest.raises(UnknownVehicle, match="no vehicle '999'.*vehicles present then: 77, 173, 253, 300"):
            scene(s, RUN, at(50), vehicle="999")
        assert isinstance(gone.value, ValueError)


def test_before_the_run_start_the_scene_is_empty_and_says_so(store):
    sc = scene(store, RUN, at(-1))
    assert sc.events == 0 and sc.vehicles == () and sc.signals == () and sc.rulebooks == ()
    assert sc.offset == "-1s" and "nothing was recorded yet" in sc.note
    assert "after the run ended" in scene(store, RUN, at(61)).note


def test_run_start_and_unknown_run(store):
    assert run_start(store, RUN) == T0
    with pytest.raises(NoSuchRun, match=f"runs: {RUN}"):
        run_start(store, "nope")
    with pytest.raises(NoSuchRun):
        scene(store, "nope", T0)


def test_run_start_is_the_run_start_event_not_an_earlier_one(tmp_path):
    with Store(tmp_path / "early.db") as s:
        s.append(paper_run() + [ev("vehicle/9", 0, T0 - 5 * SECOND, "entity.spawn", {"type": "car"})])
        assert run_start(s, RUN) == T0
        s.append([{**e, "run": "bare"} for e in paper_run() if e["kind"] != "run.start"])
        assert run_start(s, "bare") == T0                     # no run.start: the first event


def test_a_misread_light_is_judged_as_the_monitor_saw_it_as_the_incident_is(tmp_path):
    """Car 173 misreads the red as green (its perception says green, the camera saw red). The
    Validator Scenario puts what the monitor witnessed in place of the vehicle's own view (DESIGN
    "Reasoning"; the paper's Figure 1), so `scene --judge` must not call its entering lawful while
    the incident convicts it (issue 39: the demo's incident 6 "lawful: yes" on the screen)."""
    events = [dict(e, body={**e["body"], "facts": ["173 is of type car", "173 has green light"]})
              if e["src"] == "vehicle/173" and e["kind"] == "vehicle.perception" else e for e in paper_run()]
    with Store(tmp_path / "misread.db") as s:
        s.append(events)
        inv = Investigation(s)
        car = scene(s, RUN, at(10), vehicle="173", investigation=inv).vehicles[0].validator_scenario.to_json()
        verdicts = {i.vehicle: i.verdict for i in inv.incidents(RUN)}
    assert car["judged_on"] == "corrected vehicle scenario"
    assert "173 has red light" in [f["fact"] for f in car["facts"]]
    assert "173 has green light" not in [f["fact"] for f in car["facts"]]
    assert car["lawful"] is False and verdicts["173"] == "punishable"
    assert car["lawful_on_its_own_view"] is True          # both views shown, the monitor's deciding
