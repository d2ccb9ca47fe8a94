"""Proof trees of incidents as DESIGN's JSON: text, rule label, LE source and evidence."""
from reasoner.investigation import Investigation
from sim_replay.paper import RUN, paper_run
from store import Store


def nodes(tree):
    yield tree
    for kid in tree["children"]:
        yield from nodes(kid)


def test_incident_proofs_cite_rule_source_and_the_events_behind_facts(tmp_path):
    with Store(tmp_path / "s.db") as store:
        store.append(paper_run())
        found = {i.vehicle: i for i in Investigation(store).incidents(RUN)}
    pv = found["173"].proofs.potential_violation.trees[0]
    assert pv["text"] == "173 potentially violates enter the junction"
    assert pv["label"] == "HC 176" and pv["source"] == {"file": "paper.le", "line": 38}
    fact = next(n for n in nodes(pv) if n["status"] == "fact")
    assert fact["text"] == "173 has red light"
    assert fact["evidence"][0]["src"] == "monitor/m1" and fact["evidence"][0]["kind"] == "monitor.observation"
    verdict = found["253"].proofs.verdict.trees[0]
    spawn = next(n for n in nodes(verdict) if n["text"] == "253 is of type ambulance")
    assert spawn["evidence"][0]["kind"] == "entity.spawn"
    assert all(set(n) >= {"sentence", "text", "status", "rule", "label", "source", "evidence", "children"}
               for n in nodes(verdict))
