"""One run, one producer, for `gaps replay` (issue 37): a replay publishes to a `gaps serve` whose
store it cannot see, so a recording of another run under an id that store holds was mixed into it
(its conflicting seqs quarantined, the rest chained on). The replay now asks the ingest's history
queryable first and is refused (exit 2) with nothing published; the same run again goes out.
Loopback, explicit endpoints, scouting off (ServeProcess, the wire contract's config)."""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

from store import Store
from tests.helpers.cli import gaps
from tests.helpers.ingest_testkit import free_endpoint
from tests.helpers.serve_testkit import ServeProcess
from tests.helpers.store_testkit import T0, event


def _jsonl(path: Path, events: list[dict]) -> Path:
    path.write_text("".join(json.dumps(e) + "\n" for e in events))
    return path


def _replayed_into(db: Path, recording: Path):
    endpoint = free_endpoint()
    serve = ServeProcess(db, endpoint, "--json")
    try:
        serve.wait_for_log("serve.ready")
        result = gaps("replay", recording, "--speed", "max", "--connect", endpoint)
        code, _ = serve.stop()
    finally:
        serve.kill()
    assert code == 0
    return result


def test_a_replay_of_another_run_under_a_held_id_is_refused_before_publishing(tmp_path):
    db = tmp_path / "serve.db"
    with Store(db) as store:
        store.append([event(seq) for seq in range(5)])
    # run r1 again, another recording: other times, more seqs than held, a new source
    other = _jsonl(tmp_path / "other.jsonl", [event(seq, t=T0 + seq * 100_000_000 + 7_000_000) for seq in range(10)]
                   + [event(seq, src="vehicle/174") for seq in range(3)])
    result = _replayed_into(db, other)
    assert result.exit_code == 2, result.output
    assert "run r1 is held by the ingest with other events" in result.output and "seq 0 differs" in result.output
    with Store.open_read_only(db) as store:       # nothing published: nothing stored, nothing quarantined
        assert store.count("r1") == 5 and store.sources("r1") == ["vehicle/173"] and store.quarantine_count() == 0


def test_the_same_run_replayed_again_goes_out(tmp_path):
    db = tmp_path / "serve.db"
    held = [event(seq) for seq in range(5)]
    with Store(db) as store:
        store.append(held)
    before = hashlib.sha256(db.read_bytes()).hexdigest()
    same = _jsonl(tmp_path / "same.jsonl", held + [event(seq) for seq in range(5, 8)])   # and resumed
    result = _replayed_into(db, same)
    assert result.exit_code == 0, result.output
    assert hashlib.sha256(db.read_bytes()).hexdigest() != before
    with Store.open_read_only(db) as store:
        assert store.count("r1") == 8 and store.quarantine_count() == 0 and store.verify().ok


def test_a_simulation_of_another_seed_into_a_serve_holding_its_run_is_refused(tmp_path):
    """`gaps sim --connect` to a serve whose store holds run sim-001 from another seed: before,
    mixed in as `gaps sim --db` was; now refused (exit 2), nothing published, the truth file kept."""
    db, endpoint = tmp_path / "serve.db", free_endpoint()
    serve = ServeProcess(db, endpoint, "--json")
    try:
        serve.wait_for_log("serve.ready")
        sim = ("sim", "--duration", "5s", "--vehicles", "2", "--speed", "max", "--connect", endpoint)
        first = gaps(*sim, "--seed", "0", "--truth", tmp_path / "first.truth.json", "--json")
        assert first.exit_code == 0, first.output
        held = json.loads(first.stdout)["published"]["published"]
        second = gaps(*sim, "--seed", "1", "--truth", tmp_path / "second.truth.json")
        code, _ = serve.stop()
    finally:
        serve.kill()
    assert code == 0 and held > 0
    assert second.exit_code == 2, second.output
    assert "run sim-001 is held by the ingest with other events than this simulation's" in second.output
    assert not (tmp_path / "second.truth.json").exists()
    with Store.open_read_only(db) as store:
        assert store.count("sim-001") == held and store.quarantine_count() == 0
