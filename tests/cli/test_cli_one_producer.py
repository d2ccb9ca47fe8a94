"""One run, one producer (issue 37): `gaps sim --db j.db` twice, another seed the second time, stored
the second simulation into run sim-001 beside the first ("duplicates 7, rejected 426", exit 0) and
overwrote the ground truth. A simulation or an import into a run the store holds from another
producer or seed is refused (exit 2, saying what to do instead), nothing of it stored; the same
export imported again, or the rest of a run, still goes in."""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import T0, event


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def jsonl(path: Path, events: list[dict]) -> Path:
    path.write_text("".join(json.dumps(e) + "\n" for e in events))
    return path


def test_a_second_simulation_with_another_seed_is_refused_and_the_truth_kept(tmp_path):
    db = tmp_path / "j.db"
    first = gaps("sim", "--duration", "10s", "--vehicles", "2", "--seed", "0", db=db)
    assert first.exit_code == 0, first.output
    truth = tmp_path / "sim-001.truth.json"
    store_was, truth_was = digest(db), digest(truth)
    second = gaps("sim", "--duration", "10s", "--vehicles", "2", "--seed", "1", db=db)
    assert second.exit_code == 2, second.output
    assert "run sim-001 already holds" in second.output and "another --run" in second.output
    assert digest(db) == store_was and digest(truth) == truth_was


def test_a_simulation_never_replaces_a_ground_truth_file(tmp_path):
    truth = tmp_path / "sim-001.truth.json"
    truth.write_text('{"run": "sim-001", "seed": 0}\n')
    result = gaps("sim", "--duration", "10s", "--vehicles", "2", db=tmp_path / "new.db")
    assert result.exit_code == 2 and "already exists" in result.output and str(truth) in result.output
    assert truth.read_text() == '{"run": "sim-001", "seed": 0}\n'


def test_an_import_of_another_producers_run_under_the_same_id_is_refused(tmp_path):
    db = tmp_path / "gaps.db"
    with Store(db) as store:
        store.append([event(seq) for seq in range(5)])
    # the same run id and sources, other times (another producer, or another seed), and
    # more events than the store holds: before, seqs 0-4 were quarantined and 5-9 chained onto r1
    other = jsonl(tmp_path / "other.jsonl", [event(seq, t=T0 + seq * 100_000_000 + 7_000_000) for seq in range(10)]
                  + [event(0, run="r9")])
    result = gaps("import", other, db=db)
    assert result.exit_code == 2, result.output
    assert "run 'r1'" in result.output and "vehicle/173 seq 0 differs" in result.output
    with Store.open_read_only(db) as store:       # nothing of the file stored, nothing quarantined
        assert store.count("r1") == 5 and store.quarantine_count() == 0 and store.run_names() == ["r1"]


def test_the_same_export_again_and_the_rest_of_a_run_still_import(tmp_path):
    db = tmp_path / "gaps.db"
    with Store(db) as store:
        store.append([event(seq) for seq in range(5)])
    assert gaps("export", "--run", "r1", "-o", tmp_path / "r1.jsonl", db=db).exit_code == 0
    again = gaps("import", tmp_path / "r1.jsonl", db=db)
    assert again.exit_code == 0 and "duplicates 5" in again.output, again.output
    rest = gaps("import", jsonl(tmp_path / "rest.jsonl", [event(seq) for seq in range(5, 9)]), db=db)
    assert rest.exit_code == 0 and "stored 4" in rest.output, rest.output
    with Store.open_read_only(db) as store:
        assert store.count("r1") == 9 and store.verify().ok
