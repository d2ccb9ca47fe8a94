"""Verdicts from the store alone, for the paper's two scenarios and variations of them."""
import random

import pytest

from reasoner.investigation import Investigation
from sim_replay.paper import RUN, paper_run
from store import Store


@pytest.fixture()
def events():
    return paper_run()


def verdicts(tmp_path, events, name="s.db"):
    with Store(tmp_path / name) as store:
        store.append(events)
        return {i.vehicle: i for i in Investigation(store).incidents(RUN)}


def test_car_punishable_and_ambulance_mitigated(tmp_path, events):
    found = verdicts(tmp_path, events)
    assert found["173"].verdict == "punishable" and found["173"].liable == "driver"
    assert found["253"].verdict == "mitigated" and found["253"].liable == "none"
    assert found["173"].rule == "HC 176"
    assert found["173"].rulebook.source == "recorded"
    assert {e.kind for e in found["173"].evidence} >= {"monitor.potential_violation", "vehicle.decision"}


def test_verdicts_do_not_depend_on_arrival_order(tmp_path, events):
    shuffled = events[:]
    random.Random(7).shuffle(shuffled)
    a, b = verdicts(tmp_path, events, "a.db"), verdicts(tmp_path, shuffled, "b.db")
    assert {v: i.verdict for v, i in a.items()} == {v: i.verdict for v, i in b.items()}


def test_ambulance_whose_perception_says_car_is_punishable(tmp_path, events):
    for ev in events:
        if ev["kind"] == "entity.spawn" and ev["src"] == "vehicle/253":
            ev["body"]["type"] = "car"
        if ev["kind"] == "vehicle.perception" and ev["src"] == "vehicle/253":
            ev["body"]["facts"] = ["253 has red light"]
    assert verdicts(tmp_path, events)["253"].verdict == "punishable"


def test_monitor_disagreement_and_unknown_facts_are_findings(tmp_path, events):
    for ev in events:
        if ev["kind"] == "monitor.observation" and ev["body"]["vehicle"] == "173":
            ev["body"]["facts"] = ["173 has green light", "173 juggles"]
    found = verdicts(tmp_path, events)["173"]
    kinds = [f.kind for f in found.findings]
    assert "monitor disagreement" in kinds and "unknown fact" in kinds
    # the monitor's own observation (green) does not support what it recorded: dismissed, and why
    assert found.verdict == "dismissed" and "observation" in found.why
    assert found.recorded and not found.rederived
