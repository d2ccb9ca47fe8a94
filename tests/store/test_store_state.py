"""State at a time: what each entity, signal and monitor was at t, each piece citing its event."""

import dataclasses
import json
import random

import pytest
from tests.helpers.store_testkit import T0, event

from store.state import ads_status, empty_state, fold_rows, state_at

MS = 1_000_000
CAR = "vehicle/173"


def at(ms: int) -> int:
    return T0 + ms * MS


def ev(src: str, seq: int, ms: int, kind: str, body: dict | None = None) -> dict:
    return event(seq, src=src, t=at(ms), kind=kind, body=body)


def cite(e: dict) -> dict:
    return {"src": e["src"], "seq": e["seq"], "t": e["t"]}


def piece(e: dict) -> dict:
    return {**cite(e), "body": e["body"]}


BOOK = {"name": "highway-code", "version": "2024", "sha256": "a" * 64, "text": "a long LE text"}
MAP = {"roads": [{"id": "R1", "from": [0, 0], "to": [100, 0]}],
       "junctions": [{"id": "J1", "x": 100, "y": 0, "control": "lights"}], "monitors": []}

START = ev("sim/world", 0, 0, "run.start", {"map": MAP, "rulebooks": [BOOK], "seed": 7})
SPAWN = ev(CAR, 0, 10, "entity.spawn", {"type": "car", "driver": "autonomous", "automation_level": 4})
STATE_1 = ev(CAR, 1, 100, "entity.state", {"x": 1.0, "y": 0.0, "speed_mps": 8.0, "road": "R1", "junction": None})
SEEN = ev(CAR, 2, 150, "vehicle.perception", {"facts": ["173 is of type car", "173 has red light"]})
STATE_2 = ev(CAR, 3, 200, "entity.state", {"x": 2.0, "y": 0.0, "speed_mps": 0.0, "road": "R1", "junction": None})
DECIDED = ev(CAR, 4, 200, "vehicle.decision",
             {"goal": "173 can enter the junction", "action": "enter the junction", "proceeds": False})
TRACE = ev(CAR, 5, 200, "vehicle.trace", {"query": "173 can enter the junction", "answer": False})
RED = ev("signal/J1", 0, 50, "signal.state", {"junction": "J1", "approach": "north", "colour": "red"})
RED_AGAIN = ev("signal/J1", 1, 150, "signal.state", {"junction": "J1", "approach": "north", "colour": "red"})
GREEN = ev("signal/J1", 2, 250, "signal.state", {"junction": "J1", "approach": "north", "colour": "green"})
OBSERVED = ev("monitor/m1", 0, 160, "monitor.observation", {"vehicle": "173", "facts": ["173 has red light"]})
OBSERVED_AGAIN = ev("monitor/m1", 1, 260, "monitor.observation", {"vehicle": "173", "facts": ["173 has green light"]})
OTHER = ev("monitor/m1", 2, 270, "monitor.observation", {"vehicle": "12", "facts": ["12 is stopped"]})
SCENE = [START, SPAWN, STATE_1, SEEN, STATE_2, DECIDED, TRACE, RED, RED_AGAIN, GREEN, OBSERVED, OBSERVED_AGAIN, OTHER]


@pytest.fixture
def scene(store):
    store.append(SCENE)
    return store


def test_before_the_first_event_the_state_is_empty(scene):
    assert state_at(scene, "r1", at(-1)).to_json() == {"run": "r1", "t": at(-1), **empty_state()}


def test_a_run_that_does_not_exist_is_empty(scene):
    assert state_at(scene, "nope", at(1000)).events == 0


def test_the_latest_of_each_kind_at_t_with_its_event(scene):
    car = state_at(scene, "r1", at(199)).entities[CAR]
    assert car["spawn"] == piece(SPAWN)
    assert car["state"] == piece(STATE_1)
    assert car["perception"] == piece(SEEN)
    assert car["decision"] is None
    later = state_at(scene, "r1", at(200)).entities[CAR]
    assert later["state"] == piece(STATE_2)
    assert later["decision"] == piece(DECIDED)


def test_t_is_inclusive_and_the_state_says_how_far_it_got(scene):
    state = state_at(scene, "r1", at(150))
    assert state.events == 6  # START, SPAWN, STATE_1, RED, SEEN, RED_AGAIN
    assert state.last == cite(SEEN)  # same t as RED_AGAIN, but seq 2 comes after seq 1
    assert state.run == "r1" and state.t == at(150)


def test_run_start_keeps_the_map_and_cites_rulebooks_without_their_text(scene):
    start = state_at(scene, "r1", at(0)).start
    assert start["body"]["map"] == MAP
    assert start["body"]["rulebooks"] == [{k: v for k, v in BOOK.items() if k != "text"}]
    assert cite(start) == cite(START)


def test_a_signal_colour_holds_since_its_first_report(scene):
    north = state_at(scene, "r1", at(200)).signals["J1"]["north"]
    assert north == {"colour": "red", "since": cite(RED), "last": piece(RED_AGAIN)}
    north = state_at(scene, "r1", at(250)).signals["J1"]["north"]
    assert north["colour"] == "green" and north["since"] == cite(GREEN)


def test_a_signal_event_without_approach_is_filed_under_star(store):
    store.append([ev("signal/J2", 0, 0, "signal.state", {"junction": "J2", "colour": "amber"})])
    assert state_at(store, "r1", at(0)).signals["J2"]["*"]["colour"] == "amber"


def test_monitors_keep_their_latest_observation_of_each_vehicle(scene):
    seen = state_at(scene, "r1", at(1000)).monitors["monitor/m1"]
    assert seen["observations"] == {"173": piece(OBSERVED_AGAIN), "12": piece(OTHER)}
    assert state_at(scene, "r1", at(200)).monitors["monitor/m1"]["observations"] == {"173": piece(OBSERVED)}


def test_potential_violations_and_collisions_are_kept_per_vehicle(store):
    flagged = ev("monitor/m1", 0, 10, "monitor.potential_violation", {"vehicle": "173", "action": "enter the junction"})
    crash = ev("sim/world", 0, 20, "collision", {"entities": ["173", "12"]})
    store.append([flagged, crash])
    state = state_at(store, "r1", at(20))
    assert state.monitors["monitor/m1"]["potential_violations"] == {"173": piece(flagged)}
    assert state.collisions == {"173": piece(crash), "12": piece(crash)}


def test_traces_are_counted_but_not_folded(scene):
    state = state_at(scene, "r1", at(200))
    assert state.last == cite(TRACE)
    assert "trace" not in state.entities[CAR]


def test_despawn_marks_the_entity_and_a_new_spawn_starts_afresh(scene):
    gone = ev(CAR, 6, 300, "entity.despawn", {"reason": "left the map"})
    back = ev(CAR, 7, 400, "entity.spawn", {"type": "car", "driver": "human"})
    scene.append([gone, back])
    left = state_at(scene, "r1", at(300)).entities[CAR]
    assert left["despawned"] == piece(gone)
    assert left["state"] == piece(STATE_2)  # where it was last seen
    again = state_at(scene, "r1", at(400)).entities[CAR]
    assert again == {"spawn": piece(back), "state": None, "perception": None, "decision": None,
                     "ads": None, "despawned": None}


def test_equal_t_is_ordered_by_seq_then_src(store):
    a = ev("signal/A", 5, 10, "signal.state", {"junction": "J1", "approach": "north", "colour": "red"})
    b = ev("signal/B", 5, 10, "signal.state", {"junction": "J1", "approach": "north", "colour": "green"})
    c = ev("signal/C", 4, 10, "signal.state", {"junction": "J1", "approach": "north", "colour": "amber"})
    store.append([b, a, c])
    north = state_at(store, "r1", at(10)).signals["J1"]["north"]
    assert north["last"] == piece(b)  # (10, 4, C) < (10, 5, A) < (10, 5, B)


def test_the_state_is_plain_json(scene):
    state = state_at(scene, "r1", at(1000)).to_json()
    assert list(state) == ["run", "t", *empty_state()]
    assert json.loads(json.dumps(state)) == state


def test_the_state_is_frozen(scene):
    state = state_at(scene, "r1", at(1000))
    with pytest.raises(dataclasses.FrozenInstanceError):
        state.entities = {}  # type: ignore[misc]


# --- arrival order ------------------------------------------------------------------------------


def jumbled_run(rng: random.Random) -> list[dict]:
    """Events of a few sources with many equal timestamps, so that only (t, seq, src) orders them."""
    events = [START]
    for src, kind, body in [
        ("vehicle/1", "entity.state", {"x": 0.0, "y": 0.0, "speed_mps": 1.0}),
        ("vehicle/2", "entity.state", {"x": 5.0, "y": 0.0, "speed_mps": 2.0}),
        ("vehicle/1", "vehicle.perception", {"facts": ["1 has red light"]}),
        ("signal/J1", "signal.state", {"junction": "J1", "approach": "north", "colour": "red"}),
        ("monitor/m1", "monitor.observation", {"vehicle": "1", "facts": ["1 has red light"]}),
    ]:
        start = sum(1 for e in events if e["src"] == src)
        for seq in range(start, start + 40):
            changed = {**body, **({"colour": rng.choice(["red", "green"])} if "colour" in body else {"n": seq})}
            events.append(ev(src, seq, rng.randrange(0, 20) * 10, kind, changed))
    return events


@pytest.mark.parametrize("every", [None, 7], ids=["no snapshots", "snapshots every 7 events"])
def test_state_does_not_depend_on_arrival_order_or_batches(tmp_path, monkeypatch, every):
    from store import Store, state

    if every:
        monkeypatch.setattr(state, "SNAPSHOT_EVERY", every)
    events = jumbled_run(random.Random(11))
    times = [at(ms) for ms in range(-5, 210, 5)]
    states = []
    for attempt in range(4):
        rng = random.Random(attempt)
        shuffled = events[:]
        rng.shuffle(shuffled)
        with Store(tmp_path / f"{attempt}.db", durable=False) as store:
            while shuffled:
                size = rng.randint(1, 30)
                store.append(shuffled[:size])
                shuffled = shuffled[size:]
            states.append([state_at(store, "r1", t) for t in times])
    assert all(s == states[0] for s in states[1:])
    assert states[0][-1].events == len(events)


# --- the fold itself --------------------------------------------------------------------------------


def rows(*events: dict) -> list[tuple]:
    return [(e["src"], e["seq"], e["t"], e["kind"], json.dumps(e)) for e in events]


def test_superseded_events_in_a_batch_fold_like_one_at_a_time():
    events = sorted(SCENE, key=lambda e: (e["t"], e["seq"], e["src"]))
    together, one_by_one = empty_state(), empty_state()
    fold_rows(together, rows(*events))
    for e in events:
        fold_rows(one_by_one, rows(e))
    assert together == one_by_one
    assert json.dumps(together) == json.dumps(one_by_one)  # same key order too


def test_bodies_of_unexpected_shape_do_not_break_the_fold():
    odd = [
        ev("monitor/m1", 0, 0, "monitor.observation", {"vehicle": 173, "facts": []}),
        ev("signal/J1", 0, 0, "signal.state", {"junction": ["J", 1], "colour": "red"}),
        ev("sim/world", 0, 1, "collision", {"entities": "173"}),
        ev(CAR, 0, 2, "ads.event", {"event": 42}),
    ]
    state = empty_state()
    fold_rows(state, rows(*odd))
    assert set(state["monitors"]["monitor/m1"]["observations"]) == {"173"}
    assert state["signals"] == {'["J", 1]': {"*": state["signals"]['["J", 1]']["*"]}}
    assert set(state["collisions"]) == {"173"}
    assert state["entities"][CAR]["ads"]["engaged"] is False


# --- ADS status ----------------------------------------------------------------------------------


def ads(*names: str) -> tuple[dict, list[dict]]:
    status, pieces = None, []
    for seq, name in enumerate(names):
        p = piece(ev(CAR, seq, seq * 100, "ads.event", {"event": name}))
        pieces.append(p)
        status = ads_status(status, p)
    return status, pieces


def test_ads_engaged_since_activation():
    status, (on,) = ads("activated")
    assert status["engaged"] is True and status["since"] == cite(on) and status["last"] == on


def test_a_transition_demand_is_pending_from_its_first_request_until_the_driver_takes_over():
    status, (on, demand, again) = ads("activated", "transition_demand", "transition_demand")
    assert status["engaged"] is True and status["transition_demand"] == cite(demand)
    status = ads_status(status, piece(ev(CAR, 3, 300, "ads.event", {"event": "driver_override"})))
    assert status["engaged"] is False and status["transition_demand"] is None
    assert status["since"] == {"src": CAR, "seq": 3, "t": at(300)}


def test_a_minimal_risk_manoeuvre_keeps_the_demand_pending():
    status, (_, demand, mrm) = ads("activated", "transition_demand", "minimal_risk_manoeuvre")
    assert status["engaged"] is True
    assert status["transition_demand"] == cite(demand) and status["minimal_risk_manoeuvre"] == cite(mrm)
    status, _ = ads("activated", "transition_demand", "minimal_risk_manoeuvre", "deactivated")
    assert status["engaged"] is False and status["minimal_risk_manoeuvre"] is None


def test_emergency_manoeuvres_and_failures():
    status, (_, start, failure) = ads("activated", "emergency_manoeuvre_start", "failure")
    assert status["emergency_manoeuvre"] == cite(start) and status["failure"] == cite(failure)
    status, _ = ads("activated", "emergency_manoeuvre_start", "emergency_manoeuvre_end", "failure")
    assert status["emergency_manoeuvre"] is None


def test_activation_after_deactivation_moves_since_but_repeats_do_not():
    status, (on, off, on_again, repeat) = ads("activated", "deactivated", "activated", "activated")
    assert status["engaged"] is True and status["since"] == cite(on_again) and status["last"] == repeat


def test_ads_status_folds_into_the_entity(store):
    store.append([SPAWN, ev(CAR, 1, 20, "ads.event", {"event": "activated"})])
    assert state_at(store, "r1", at(20)).entities[CAR]["ads"]["engaged"] is True
    assert state_at(store, "r1", at(19)).entities[CAR]["ads"] is None
