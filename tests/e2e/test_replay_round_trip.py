"""`gaps replay`, the round trip issue 16 asks for: a run the simulation recorded (the golden run's
MCAP file) replayed onto Zenoh into a running `gaps serve` gives a store with the same events, the
same chain heads and the same verdicts as the recording imported directly."""
from __future__ import annotations

import json
from pathlib import Path

from reasoner.investigation import Investigation
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.ingest_testkit import free_endpoint
from tests.helpers.serve_testkit import ServeProcess

RECORDING = Path(__file__).resolve().parents[1] / "golden" / "golden-sim.mcap"


def test_a_recording_replayed_into_an_ingest_is_the_recording(tmp_path):
    direct, live, endpoint = tmp_path / "direct.db", tmp_path / "live.db", free_endpoint()
    assert gaps("import", RECORDING, db=direct).exit_code == 0
    serve = ServeProcess(live, endpoint, "--json")
    try:
        serve.wait_for_log("serve.ready")
        replayed = gaps("replay", RECORDING, "--speed", "max", "--connect", endpoint, "--json")
        assert replayed.exit_code == 0, replayed.output
        code, _ = serve.stop()
    finally:
        serve.kill()
    assert code == 0
    sent = json.loads(replayed.stdout)
    with Store.open_read_only(direct) as a, Store.open_read_only(live) as b:
        assert [r.run for r in a.runs()] == [r.run for r in b.runs()] == [r["run"] for r in sent["runs"]]
        for run in a.run_names():
            assert b.count(run) == a.count(run) == next(r["events"] for r in sent["runs"] if r["run"] == run)
            assert list(b.events(run)) == list(a.events(run))
            assert b.chain_head(run) == a.chain_head(run)
            judged = [[i.to_json() for i in Investigation(s).incidents(run)] for s in (a, b)]
            assert judged[0] and judged[0] == judged[1]


def test_replay_says_what_is_wrong(tmp_path):
    endpoint = free_endpoint()
    assert "one of them" in gaps("replay", "--connect", endpoint).output
    assert "nowhere to publish" in gaps("replay", RECORDING).output
    assert "no such recording" in gaps("replay", tmp_path / "none.mcap", "--connect", endpoint).output
    wrong_run = gaps("replay", RECORDING, "--run", "nope", "--connect", endpoint)
    assert wrong_run.exit_code == 2 and "no run 'nope'" in wrong_run.output
    assert "not a speed" in gaps("replay", RECORDING, "--speed", "fast", "--connect", endpoint).output
