"""The synthetic run: valid events, numbered sources, the seeded incidents present, and a ground
truth that the rulebooks themselves agree with (the benchmarks check verdicts against it)."""
from __future__ import annotations

import hashlib
from collections import Counter, defaultdict

import pytest

from reasoner.bundled import bundled
from reasoner.engine import get_engine
from reasoner import vocabulary as vocab
from reasoner.le.sentences import parse_fact
from sim_replay.synthetic import RULEBOOKS, Oracle, expected_incidents, synthetic_run
from store import Store

SMALL = {"vehicles": 10, "seconds": 300, "seed": 7, "run": "synthetic-test", "intensity": 1.0}
SEEDED = {  # every misbehaving role of the first ten vehicles shows up in five minutes at intensity 1
    "red light runner (human driver)", "red light runner (ADS engaged)", "ambulance off call through red",
    "perception fault: the ADS saw green, the light was red", "user took over from the ADS, then ran the red",
    "rolled through the stop sign", "speeding", "emergency vehicle on call through red",
}


@pytest.fixture(scope="module")
def small() -> tuple[list[dict], list[dict]]:
    truth: list[dict] = []
    events = list(synthetic_run(**SMALL, truth=truth))
    return events, truth


def test_every_event_is_stored_by_the_store(small, tmp_path):
    events, _ = small
    with Store(tmp_path / "s.db", durable=False) as store:
        report = store.append(events, origin="test")
        assert report.rejected == [] and report.duplicates == 0
        assert report.stored == len(events) == store.count("synthetic-test")


def test_each_source_counts_from_zero_and_time_never_goes_back(small):
    events, _ = small
    seqs: dict[str, list[int]] = defaultdict(list)
    for ev in events:
        seqs[ev["src"]].append(ev["seq"])
    assert all(s == list(range(len(s))) for s in seqs.values())
    assert all(a["t"] <= b["t"] for a, b in zip(events, events[1:]))
    assert {s.split("/")[0] for s in seqs} == {"sim", "vehicle", "signal", "monitor"}
    kinds = Counter(ev["kind"] for ev in events)
    assert kinds["entity.state"] == 10 * 300 * 10  # 10 Hz for every vehicle
    assert kinds["vehicle.perception"] >= 10 * 300 * 4  # at least 4 Hz
    assert events[0]["kind"] == "run.start" and events[-1]["kind"] == "run.end"


def test_run_start_carries_the_bundled_rulebooks_by_hash(small):
    events, _ = small
    books = {b["name"]: b for b in events[0]["body"]["rulebooks"]}
    assert list(books) == list(RULEBOOKS)
    for name, book in books.items():
        assert book["text"] == bundled(name)
        assert book["sha256"] == hashlib.sha256(book["text"].encode()).hexdigest()
    decisions = {ev["body"]["rulebook"] for ev in events if ev["kind"] == "vehicle.decision"}
    pvs = {ev["body"]["rulebook"] for ev in events if ev["kind"] == "monitor.potential_violation"}
    assert decisions == {books["highway_code.le"]["sha256"]} and pvs == {books["monitors.le"]["sha256"]}
    m = events[0]["body"]["map"]
    assert {j["control"] for j in m["junctions"]} == {"lights", "stop", "give_way"}
    assert all({"junction", "x", "y", "heading_deg", "range_m", "fov_deg"} <= set(mon) for mon in m["monitors"])


def test_the_seeded_incidents_are_potential_violations(small):
    events, truth = small
    pvs = {f"{ev['src']}:{ev['seq']}": ev for ev in events if ev["kind"] == "monitor.potential_violation"}
    assert [t["id"] for t in truth] == list(pvs)
    for expected in truth:
        pv = pvs[expected["id"]]
        assert (pv["t"], pv["body"]["vehicle"], pv["body"]["action"]) == (
            expected["t"], expected["vehicle"], expected["action"])
    assert {t["cause"] for t in truth} >= SEEDED
    by_cause = {t["cause"]: t for t in truth}
    assert by_cause["perception fault: the ADS saw green, the light was red"]["findings"] == ["perception fault"]
    assert by_cause["emergency vehicle on call through red"]["verdict"] == "mitigated"
    assert by_cause["user took over from the ADS, then ran the red"]["liable"] == "driver"
    assert by_cause["red light runner (ADS engaged)"]["liable"] == "authorised self-driving entity"


def test_deterministic_for_a_seed():
    a = list(synthetic_run(vehicles=6, seconds=60, seed=3, run="d"))
    b = list(synthetic_run(vehicles=6, seconds=60, seed=3, run="d"))
    c = list(synthetic_run(vehicles=6, seconds=60, seed=4, run="d"))
    assert a == b and a != c
    assert expected_incidents(**SMALL) == expected_incidents(**SMALL)


def test_the_default_hour_rates_are_a_few_hundred_incidents():
    """At the default intensity a tenth of the hour (200 vehicles) has tens of incidents, not thousands."""
    truth = expected_incidents(vehicles=200, seconds=360)
    assert 10 <= len(truth) <= 150
    assert Counter(t["verdict"] for t in truth).keys() == {"mitigated", "punishable"}


def test_facts_are_in_the_rulebooks_vocabulary_and_the_truth_agrees_with_the_rules(small):
    """Every sentence a vehicle or monitor writes fits a template of the rulebook that reads it,
    and at each potential violation monitors.le re-derives it and validators.le gives the
    verdict (and perception fault) the ground truth says, on the vehicle's latest perception."""
    events, truth = small
    engine = get_engine()
    books = {b["name"]: b["text"] for b in events[0]["body"]["rulebooks"]}
    monitors = engine.load(books["monitors.le"], "monitors.le")
    validators = engine.load(books["validators.le"], "validators.le")
    for ev in events:
        if ev["kind"] == "vehicle.perception":
            assert all(parse_fact(f, validators.document.templates) for f in ev["body"]["facts"]), ev
        elif ev["kind"] in ("monitor.observation", "monitor.potential_violation"):
            assert all(parse_fact(f, monitors.document.templates) for f in ev["body"]["facts"]), ev

    def atoms(rb, sentences):
        return [parse_fact(s, rb.document.templates) for s in sentences]

    latest: dict[str, dict] = {}
    spawns = {ev["src"]: ev["body"] for ev in events if ev["kind"] == "entity.spawn"}
    by_id = {t["id"]: t for t in truth}
    checked = 0
    for ev in events:
        if ev["kind"] == "vehicle.perception":
            latest[ev["src"]] = ev
        if ev["kind"] != "monitor.potential_violation":
            continue
        expected, body = by_id[f"{ev['src']}:{ev['seq']}"], ev["body"]
        v, action = body["vehicle"], body["action"]
        pv = f"{v} potentially violates {action}"
        assert engine.holds(monitors, parse_fact(pv, monitors.document.templates), atoms(monitors, body["facts"]))
        own = latest[f"vehicle/{v}"]["body"]["facts"]
        if spawns[f"vehicle/{v}"].get("emergency"):
            own = own + [f"{v} is on an emergency call"]
        seen = [f.replace(f"{v} has ", "the monitor observed ").replace(" light", f" light for {v}")
                for f in body["facts"] if f.endswith(" light")]
        facts = atoms(validators, own + seen + [pv])
        punishable = engine.holds(validators, parse_fact(f"{v} punishably violates {action}",
                                                         validators.document.templates), facts)
        fault = engine.holds(validators, parse_fact(f"{v} has a perception fault about the light",
                                                    validators.document.templates), facts)
        assert ("punishable" if punishable else "mitigated") == expected["verdict_on_vehicle_scenario"], expected
        assert fault == ("perception fault" in expected["findings"]), expected
        checked += 1
    assert checked == len(truth) > 0


def test_no_potential_violation_the_monitors_did_not_record(small):
    """The reasoner re-derives potential violations from every observation (episodes of
    consecutive observations on which monitors.le holds): each such episode must hold the one
    the monitor recorded, or the run would carry incidents its ground truth does not know."""
    events, _ = small
    engine = get_engine()
    monitors = engine.load(events[0]["body"]["rulebooks"][1]["text"], "monitors.le")
    templates = monitors.document.templates
    recorded = {(ev["src"], ev["body"]["vehicle"], ev["body"]["action"], ev["t"])
                for ev in events if ev["kind"] == "monitor.potential_violation"}
    open_: dict[tuple, list[int]] = {}
    episodes: list[tuple[tuple, list[int]]] = []
    for ev in events:
        if ev["kind"] != "monitor.observation":
            continue
        v = ev["body"]["vehicle"]
        facts = [parse_fact(f, templates) for f in ev["body"]["facts"]]
        for action in ("enter the junction", "exceed the speed limit"):
            key = (ev["src"], v, action)
            if engine.holds(monitors, parse_fact(f"{v} potentially violates {action}", templates), facts):
                open_.setdefault(key, []).append(ev["t"])
            elif key in open_:
                episodes.append((key, open_.pop(key)))
    episodes += list(open_.items())
    assert episodes
    for key, ts in episodes:  # recorded just after the observation it rests on, in the same µs slot
        assert sum(1 for *k, t in recorded if tuple(k) == key and ts[0] <= t <= ts[-1] + 1000) == 1, (key, ts)
    assert len(episodes) == len(recorded)


def test_every_decision_is_what_highway_code_le_says_on_its_perception(small):
    """`permitted` is asked of highway_code.le and remembered across vehicles in the same
    situation: asked afresh, on each decision's own perception, the rulebook agrees."""
    events, _ = small
    engine = get_engine()
    hc = engine.load(bundled("highway_code.le"), "highway_code.le")
    latest: dict[str, list[str]] = {}
    answers: Counter = Counter()
    for ev in events:
        if ev["kind"] == "vehicle.perception":
            latest[ev["src"]] = ev["body"]["facts"]
        elif ev["kind"] == "vehicle.decision":
            facts = [parse_fact(f, hc.document.templates) for f in latest[ev["src"]]]
            goal = parse_fact(ev["body"]["goal"], hc.document.templates)
            assert engine.holds(hc, goal, facts) == ev["body"]["permitted"], (ev, latest[ev["src"]])
            answers[ev["body"]["permitted"]] += 1
    assert answers[True] > 0 and answers[False] > 0


def test_a_situation_is_asked_once_whatever_the_vehicle():
    """The memo is keyed by the facts with the vehicle's id blanked, so a second vehicle in the same
    situation costs no question; a sentence no template fits is an error, not a silent no."""
    oracle = Oracle({name: bundled(name) for name in RULEBOOKS})

    def can_enter(v: str) -> bool:
        facts = [vocab.IS_OF_TYPE.text(v, "bus"), vocab.HAS_LIGHT.text(v, "amber"), vocab.HAS_SPEED_OF.text(v, 77)]
        return oracle.holds("highway_code.le", vocab.CAN, (v, "enter the junction"), v, facts)

    assert can_enter("901") is False and oracle.asked == 1
    assert can_enter("902") is False and oracle.asked == 1
    with pytest.raises(ValueError, match="no template"):
        oracle.holds("highway_code.le", vocab.CAN, ("101", "enter the junction"), "101",
                     ["101 is of type car", "101 wears a hat"])
