"""A regression's new side judges each case as far as its summary goes (reasoner/speedups/summaries.py
`summarised`): the verdict, its rule, the penalty and who is liable, asked afresh every time;
the findings, evidence and proofs of an incident are worked out only for one whose change shows
them, and the result is the plain path's, to the byte."""
from __future__ import annotations

from reasoner.judge import pipeline as pipeline_module
from reasoner.case_memo import CaseMemo
from store import Store

from tests.reasoner import regress_runs as R
from tests.reasoner.regress_runs import db, new_rules  # noqa: F401 (fixtures)


def _counted(monkeypatch) -> dict[str, int]:
    """Calls of missing_evidence (a finding) and of CaseMemo._value by kind."""
    calls: dict[str, int] = {}
    missing, value = pipeline_module.missing_evidence, CaseMemo._value

    def note(name: str) -> None:
        calls[name] = calls.get(name, 0) + 1
    monkeypatch.setattr(pipeline_module, "missing_evidence", lambda *a: note("findings") or missing(*a))
    monkeypatch.setattr(CaseMemo, "_value", lambda memo, kind, *a: note(f"whole {kind}") or value(memo, kind, *a))
    return calls


def test_the_new_side_works_out_no_findings_and_the_changed_incident_s_proofs_alone(db, new_rules, monkeypatch):
    first = R.regressed(db, new_rules)
    incidents = first["runs"][0]["incidents"]
    changed = [i for i in incidents if i["changes"] and i["after"] is not None]
    assert len(changed) == 1 and len(incidents) == 3 and changed[0]["changes"][0]["rules"]
    assert first == R.plain(db, new_rules)
    calls = _counted(monkeypatch)
    assert R.regressed(db, new_rules) == first
    assert "findings" not in calls                         # no incident judged whole: its proofs alone
    assert calls["whole derived"] == len(incidents) + len(changed)     # derived facts, kept and read alone
    assert "whole measurement" not in calls


def test_a_summarised_incident_is_the_whole_judgement_when_asked(db, new_rules, monkeypatch):
    with Store.open_read_only(db) as store:
        full, found, _ = R.summarised(store, new_rules)
        assert [(i.id, i.t, i.vehicle, i.action, i.verdict, i.rule, i.penalty, i.liable, i.parties) for i in found] \
            == [(i.id, i.t, i.vehicle, i.action, i.verdict, i.rule, i.penalty, i.liable, i.parties) for i in full]
        calls = _counted(monkeypatch)
        assert [i.proofs for i in found] == [i.proofs for i in full]
        assert "findings" not in calls and "whole measurement" not in calls       # the proofs alone
        assert [i.whole() for i in found] == full
        assert calls["findings"] == len(full)


def test_both_sides_share_one_reading_of_the_cases(db, new_rules, monkeypatch):
    """The run's recorded potential violations, its kept cases and those the monitor rulebook does
    not raise are read once for both sides of a warm regression (the same chain, the same monitor
    rulebook), to the same result."""
    first = R.regressed(db, new_rules)
    calls = _counted(monkeypatch)
    read: list = []
    events = Store.events
    monkeypatch.setattr(Store, "events", lambda store, run, *a, **k: read.append(k.get("kinds")) or events(store, run, *a, **k))
    assert R.regressed(db, new_rules) == first
    assert read.count(["monitor.potential_violation"]) == 1
    assert calls["whole cases"] == calls["whole unraised"] == 1


def test_the_baseline_reads_the_changed_incident_s_whole_entry_alone(db, new_rules, monkeypatch):
    """A kept incident is read whole by its key, where its change shows its proofs: not every
    incident's entry (on the hour 24 MB) to use 214 of 1,758; a forged one is still dropped."""
    from store.cache import derived as derived_cache
    first = R.regressed(db, new_rules)
    loaded: dict[str, derived_cache.Sealed] = {}
    load = derived_cache.load
    monkeypatch.setattr(derived_cache, "load", lambda store, run, kind, *a, **k: loaded.setdefault(
        kind, load(store, run, kind, *a, **k)))
    assert R.regressed(db, new_rules) == first
    changed = [i for i in first["runs"][0]["incidents"] if i["changes"] and i["before"] is not None]
    assert len(changed) == 1
    assert len([row for row in loaded["incident"]._rows.values() if row is not None]) == len(changed)
    assert len(loaded["incident summary"]._rows) == 3


def test_an_entry_read_by_its_key_is_sealed_all_the_same(tmp_path):
    from store.cache import derived as derived_cache
    db = R.build_store(tmp_path / "g.db")
    with Store(db) as store:
        chain = derived_cache.current_chain(store, R.RUN)
        assert derived_cache.save(store, R.RUN, "k", "v", chain, {"a": "[1]", "b": "[2]"})
        store.cache.connection.execute("UPDATE derived SET payload = '[3]' WHERE key = 'b'")
        sealed = derived_cache.load(store, R.RUN, "k", "v", chain, by_key=True)
        assert sealed.get("a") == "[1]" and sealed.get("b") is None and sealed.get("c") is None
        assert sealed.get("b") is None and store.cache.sealer.tampered().get("derived") == 1
        assert derived_cache.load(store, R.RUN, "k", "v", (chain[0] + 1, chain[1]), by_key=True).get("a") is None
