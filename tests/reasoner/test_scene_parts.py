"""The scene's parts are values (reasoner/scene_parts.py) and its JSON is what `gaps scene --json`
printed when they were dicts: data/scenes_before_typed_parts.json was written by the scene code
before the parts were typed (commit 8c2183b), from the same events as below. The text is compared
with its key order, since `gaps scene --json` prints keys in the order the scene gives them."""
import dataclasses
import json
from pathlib import Path

import pytest

from reasoner.investigation import Investigation
from reasoner.scene import scene
from reasoner.model import AdsEvent, Cited
from reasoner.scene_parts import MonitorShown, RunRulebook, SignalShown, VehicleShown
from sim_replay.paper import RUN, SECOND, T0, paper_run
from store import EventRef, Store

from tests.reasoner.test_scene import av_events

BEFORE = json.loads((Path(__file__).parent / "data" / "scenes_before_typed_parts.json").read_text(encoding="utf-8"))


def misread(events):
    """Car 173's perception says green where the camera saw red: its Validator Scenario is corrected."""
    return [dict(e, body={**e["body"], "facts": ["173 is of type car", "173 has green light"]})
            if e["src"] == "vehicle/173" and e["kind"] == "vehicle.perception" else e for e in events]


@pytest.fixture(scope="module")
def stores(tmp_path_factory):
    folder = tmp_path_factory.mktemp("parts")
    with Store(folder / "av.db") as av, Store(folder / "misread.db") as wrong:
        av.append(paper_run() + av_events())
        wrong.append(misread(paper_run()))
        yield {"av": (av, Investigation(av)), "misread": (wrong, Investigation(wrong))}


@pytest.mark.parametrize("key", sorted(BEFORE))
def test_the_json_is_the_same_to_the_key_order(stores, key):
    name, seconds, *judged = key.split()
    store, inv = stores[name]
    sc = scene(store, RUN, T0 + int(float(seconds) * SECOND), judge=bool(judged), investigation=inv)
    assert json.dumps(sc.to_json(), ensure_ascii=False) == json.dumps(BEFORE[key], ensure_ascii=False)


def test_the_parts_are_frozen_values_read_by_attribute(stores):
    store, inv = stores["misread"]
    sc = scene(store, RUN, T0 + 10 * SECOND, vehicle="173", investigation=inv)
    (car,) = sc.vehicles
    assert isinstance(car, VehicleShown) and all(isinstance(s, SignalShown) for s in sc.signals)
    assert all(isinstance(m, MonitorShown) for m in sc.monitors)
    with pytest.raises(dataclasses.FrozenInstanceError):
        car.vehicle = "999"                                     # type: ignore[misc]
    assert isinstance(car.state.evidence, EventRef) and car.state.field("junction") == "j1"
    validator = car.validator_scenario
    assert validator.judged_on == "corrected vehicle scenario"
    assert validator.judged.lawful is False and validator.judged.lawful_on_its_own_view is True
    assert validator.judged.rulebook.name == "paper.le"
    assert sc.signals[0].since.kind == "signal.state"


def test_the_last_event_the_rulebooks_and_the_control_status_are_values(stores):
    """At 25 s car 300's feature is engaged since its ads.event seq 1 (2 s) and a transition demand
    (seq 2, 20 s) is pending (tests/reasoner/test_scene.py's av_events); the last event folded is
    that demand, and the run.start recorded paper.le. Each is read by attribute; the JSON is the
    fold's {src, seq, t} and the rulebook entry as recorded (test above)."""
    store, inv = stores["av"]
    sc = scene(store, RUN, T0 + 25 * SECOND, investigation=inv)
    assert sc.last == Cited("vehicle/300", 2, T0 + 20 * SECOND)
    assert [(type(b), b.name) for b in sc.rulebooks] == [(RunRulebook, "paper.le")]
    control = next(v.control for v in sc.vehicles if v.vehicle == "300")
    assert control.since == Cited("vehicle/300", 1, T0 + 2 * SECOND)
    assert control.transition_demand == Cited("vehicle/300", 2, T0 + 20 * SECOND)
    assert control.transition_demand.ref(RUN, "ads.event") == EventRef(RUN, "vehicle/300", 2, T0 + 20 * SECOND,
                                                                      "ads.event")
    assert control.to_json()["since"] == {"src": "vehicle/300", "seq": 1, "t": T0 + 2 * SECOND}
    assert control.last_ads_event == AdsEvent("vehicle/300", 2, T0 + 20 * SECOND, "transition_demand")
    assert control.last_ads_event.ref(RUN).kind == "ads.event"
