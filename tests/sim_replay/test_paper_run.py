"""The paper's scenarios as events: valid envelopes, numbered sources, decisions asked of the rules."""
from collections import defaultdict

from reasoner.engine import sha256_text
from sim_replay.paper import paper_run
from store import validate_event


def test_every_event_is_valid_and_each_source_counts_from_zero():
    events = paper_run()
    seqs = defaultdict(list)
    for ev in events:
        validate_event(ev)
        seqs[ev["src"]].append(ev["seq"])
    assert all(s == list(range(len(s))) for s in seqs.values())
    assert {ev["kind"] for ev in events} >= {
        "run.start", "entity.spawn", "signal.state", "vehicle.perception", "vehicle.decision",
        "monitor.observation", "monitor.potential_violation", "run.end"}


def test_run_start_carries_the_rulebook_text_by_its_hash():
    (start,) = [e for e in paper_run() if e["kind"] == "run.start"]
    (rb,) = start["body"]["rulebooks"]
    assert rb["sha256"] == sha256_text(rb["text"]) and "can enter the junction" in rb["text"]


def test_vehicles_decisions_come_from_the_rulebook():
    decisions = {e["src"]: e["body"] for e in paper_run() if e["kind"] == "vehicle.decision"}
    assert decisions["vehicle/173"]["permitted"] is False
    assert decisions["vehicle/253"]["permitted"] is True
    assert all(d["proceeds"] for d in decisions.values())
