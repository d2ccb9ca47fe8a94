"""Golden files: `gaps incidents --json`, and every incident's full JSON, for a few stores.

The JSON an investigator's scripts read must not move unnoticed. Every incident says whether it
has a margin (`margin`: null, or what its history measured, issue 12); the demo store's map draws
a stop line, so its incidents have one. Regenerate with GAPS_UPDATE_GOLDEN=1 and read the diff
before committing it.
"""
from __future__ import annotations

import json
import os
import sys
from pathlib import Path

import pytest

from sim_replay.paper import paper_run
from store import Store

from tests.helpers.verdict_runs import RUN, RunBuilder, car
from test_verdict_paths import mixed_run, paper_scenarios

GOLDEN = Path(__file__).with_name("golden")
UPDATE = os.environ.get("GAPS_UPDATE_GOLDEN") == "1"


def _dismissed_with_decision_fault(run: RunBuilder) -> None:
    run.spawn("42", "car")
    run.lights(10, "red")
    run.crossing("42", 10, car("42") + ["42 has red light"], ["42 has red light", "42 is stopped"],
                 proceeds=False)
    run.spawn("173", "car")
    run.lights(40, "red")
    run.crossing("173", 40, car("173") + ["173 has red light"],
                 ["173 has red light", "173 crossed the stop line on red light"], says=True)


def _gap(run: RunBuilder) -> list[dict]:
    run.spawn("173", "car")
    run.lights(10, "red")
    c = run.crossing("173", 10, car("173") + ["173 has red light"],
                     ["173 has red light", "173 crossed the stop line on red light"], observations=2)
    return [e for e in run.finish() if e is not c["approach"]]


def _events(name: str) -> list[dict]:
    if name == "demo":
        return paper_run()
    if name == "mixed":
        return mixed_run()
    if name == "no_rulebooks":
        run = RunBuilder(books=None)
        paper_scenarios(run)
        return run.finish()
    if name == "dismissed_decision_fault":
        run = RunBuilder()
        _dismissed_with_decision_fault(run)
        return run.finish()
    if name == "missing_evidence":
        return _gap(RunBuilder())
    raise KeyError(name)


STORES = ("demo", "mixed", "no_rulebooks", "dismissed_decision_fault", "missing_evidence")


def _store(path: Path, name: str) -> Path:
    with Store(path) as store:
        report = store.append(_events(name))
        assert not report.rejected, report.rejected
    return path


def _cli_json(db: Path, capsys) -> list[dict]:
    from cli.main import main
    argv = sys.argv
    sys.argv = ["gaps", "incidents", "--db", str(db), "--json"]
    try:
        main()
    except SystemExit as exc:
        assert not exc.code, capsys.readouterr().err
    finally:
        sys.argv = argv
    return json.loads(capsys.readouterr().out)


def _full_json(db: Path) -> list[dict]:
    from reasoner.investigation import Investigation
    with Store(db) as store:
        inv = Investigation(store)
        return [inc.to_json() for run in [r.run for r in store.runs()] for inc in inv.incidents(run)]


def _with_margin(incidents: list[dict]) -> list[dict]:
    for inc in incidents:
        assert "margin" in inc, "every incident says whether it has a margin"
    return incidents


def _check(name: str, found: list[dict]) -> None:
    path = GOLDEN / name
    text = json.dumps(found, indent=2, ensure_ascii=False) + "\n"      # key order too
    if UPDATE or not path.exists():
        GOLDEN.mkdir(exist_ok=True)
        path.write_text(text, encoding="utf-8")
        if not UPDATE:
            pytest.fail(f"wrote the new golden file {path}; read it, then run again")
    assert text == path.read_text(encoding="utf-8"), f"{name} differs (GAPS_UPDATE_GOLDEN=1 rewrites it)"


@pytest.mark.parametrize("name", STORES)
def test_incidents_json_is_unchanged(tmp_path, capsys, name):
    db = _store(tmp_path / "s.db", name)
    found = _cli_json(db, capsys)
    assert found, "each golden store has incidents"
    _check(f"{name}.cli.json", _with_margin(found))
    _check(f"{name}.full.json", _with_margin(_full_json(db)))


def test_the_golden_stores_cover_the_incident_shapes():
    """The stores hold every verdict, a finding of each kind the reasoner makes here, a penalty
    with regulatory sanctions and a run judged with the current rulebooks."""
    found = [inc for name in STORES
             for inc in json.loads((GOLDEN / f"{name}.full.json").read_text(encoding="utf-8"))]
    assert {inc["verdict"] for inc in found} == {"punishable", "mitigated", "dismissed"}
    kinds = {f["kind"] for inc in found for f in inc["findings"]}
    assert {"perception fault", "decision fault", "monitor disagreement", "missing evidence"} <= kinds
    assert any(inc["penalty"] and inc["penalty"].get("regulatory_sanctions") for inc in found)
    assert any('"current"' in json.dumps(inc["rulebooks"]) for inc in found)
    assert all(inc["run"] in {RUN, "paper-junctions"} for inc in found)


def test_a_run_is_verified_once_for_all_its_explanations(tmp_path):
    """Every explanation states the chain's status; recomputing the chain reads the whole run,
    so an investigation does it once per run."""
    from reasoner.investigation import Investigation
    db = _store(tmp_path / "s.db", "mixed")
    with Store(db) as store:
        calls = []
        verify = store.verify
        store.verify = lambda run=None, progress=None: calls.append(run) or verify(run, progress)
        inv = Investigation(store)
        found = inv.incidents(RUN)
        explained = [inv.explanation(inc, counterfactuals=False) for inc in found]
    assert len(found) > 1 and calls == [RUN]
    assert all(e.chain.verified for e in explained)
    assert [e.incident for e in explained] == [inc.id for inc in found]
