"""`gaps sim` as a user runs it: a seeded run into a store through an in-process ingest, recorded
as MCAP, with its ground truth beside it; the same seed gives the same events; mistakes in the
arguments are clear errors."""
from __future__ import annotations

import json

import pytest
from mcap.reader import make_reader

from store import Store, canonical_json
from tests.helpers.cli import gaps

ARGS = ("sim", "--vehicles", "12", "--duration", "40s", "--seed", "5", "--run", "try-1")


@pytest.fixture(scope="module")
def simulated(tmp_path_factory):
    where = tmp_path_factory.mktemp("sim")
    result = gaps(*ARGS, "--record", where / "run.mcap", "--json", db=where / "s.db")
    assert result.exit_code == 0, result.output
    return where, json.loads(result.stdout)


def test_the_run_is_stored_recorded_and_its_truth_written_beside_the_recording(simulated):
    where, out = simulated
    events = out["simulation"]["events"]
    assert out["stored"]["stored"] == events == out["published"]["published"] == out["published"]["recorded"]
    assert out["simulation"]["world_s"] == 40.0 and out["simulation"]["vehicles"] == 12
    with Store(where / "s.db", read_only=True) as store:
        stored = sorted(canonical_json(e) for e in store.events("try-1"))
    with open(where / "run.mcap", "rb") as f:
        recorded = sorted(m.data for _, c, m in make_reader(f).iter_messages() if c.topic.startswith("gaps/try-1/"))
    assert stored == recorded and len(stored) == events
    truth = json.loads((where / "try-1.truth.json").read_text())
    assert out["truth"] == str(where / "try-1.truth.json") and truth["seed"] == 5
    assert isinstance(truth["yields"], list) and isinstance(truth["conflicts"], list)   # SUMO's own account


def test_the_same_seed_gives_the_same_events(simulated, tmp_path):
    where, _ = simulated
    again = gaps(*ARGS, "--record", tmp_path / "again.mcap", "--json", db=tmp_path / "s.db")
    assert again.exit_code == 0, again.output
    with Store(where / "s.db", read_only=True) as a, Store(tmp_path / "s.db", read_only=True) as b:
        assert [canonical_json(e) for e in a.events("try-1")] == [canonical_json(e) for e in b.events("try-1")]


@pytest.mark.parametrize("args,message", [
    (("--faults", "misread=0.1"), "unknown fault 'misread': use misperceived_light"),
    (("--faults", "lost_event=2"), "fault lost_event: '2' is not a rate from 0 to 1"),
    (("--duration", "ten minutes"), "'ten minutes' is not a duration"),
    (("--speed", "fast"), "'fast' is not a speed"),
    (("--map", "nowhere.net.xml", "--monitors", "m.json"), "no such network file: nowhere.net.xml"),
])
def test_argument_mistakes_are_clear_errors_without_a_traceback(tmp_path, args, message):
    result = gaps("sim", "--duration", "5s", *args, db=tmp_path / "s.db")
    assert result.exit_code == 2
    assert message in " ".join(result.output.split()) and "Traceback" not in result.output
    assert not (tmp_path / "s.db").exists()


def test_sign_keys_signs_every_event_published_and_recorded_alike(tmp_path):
    keys = tmp_path / "keys"
    result = gaps("sim", "--vehicles", "2", "--duration", "10s", "--run", "signed-1", "--sign-keys", keys,
                  "--record", tmp_path / "run.mcap", "--json", db=tmp_path / "s.db")
    assert result.exit_code == 0, result.output
    out = json.loads(result.stdout)
    assert out["public_keys"] == str(keys / "public-keys.json")
    with Store(tmp_path / "s.db", read_only=True) as store:
        stored = sorted(canonical_json(e) for e in store.events("signed-1"))
    with open(tmp_path / "run.mcap", "rb") as f:
        recorded = sorted(m.data for _, c, m in make_reader(f).iter_messages() if c.topic.startswith("gaps/signed-1/"))
    assert stored == recorded and all(b'"sig":{' in text for text in stored)
    checked = gaps("verify", "--keys", keys / "public-keys.json", "--json", "--no-snapshots", db=tmp_path / "s.db")
    s = json.loads(checked.stdout)["signatures"]
    assert checked.exit_code == 0 and s["valid"] == s["signed"] == out["simulation"]["events"]
