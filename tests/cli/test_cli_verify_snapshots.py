"""`gaps verify --snapshots`: the state snapshots checked against a fresh fold of the events."""

import json

import pytest
from store_testkit import T0, event
from typer.testing import CliRunner

from cli.main import app
from store import Store, snapshots
from store.state import build_snapshots


def gaps(*args, db):
    result = CliRunner().invoke(app, [*args, "--db", str(db)], env={"COLUMNS": "200"})
    assert "Traceback" not in result.output
    return result


@pytest.fixture
def db(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i, t=T0 + i * 1_000_000, kind="entity.state",
                            body={"x": float(i), "y": 0.0, "speed_mps": 1.0}) for i in range(40)])
        build_snapshots(store, "r1", every=10)
    return path


def forge_snapshot(path, offset):
    """Alter one snapshot behind the store's back: vehicle/173 said to be somewhere it never was."""
    with Store(path) as store:
        conn = store.cache.connection
        t, seq, src, blob = conn.execute(
            "SELECT t, seq, src, state FROM state_snapshots ORDER BY t LIMIT 1 OFFSET ?", (offset,)).fetchone()
        forged = snapshots.decode(blob)
        forged["entities"]["vehicle/173"]["state"]["body"]["x"] = -999.0
        conn.execute("UPDATE state_snapshots SET state = ? WHERE t = ? AND seq = ? AND src = ?",
                     (snapshots.encode(forged), t, seq, src))
    return t, seq, src


def test_matching_snapshots_pass(db):
    result = gaps("verify", "--snapshots", db=db)
    assert result.exit_code == 0, result.output
    assert "every state snapshot matches its events" in result.stdout
    as_json = json.loads(gaps("verify", "--snapshots", "--json", db=db).stdout)
    assert as_json["ok"] is True and as_json["snapshots"] == {"r1": []}


def test_a_wrong_snapshot_fails_verify_only_when_asked(db):
    t, seq, src = forge_snapshot(db, 2)
    plain = gaps("verify", db=db)
    assert plain.exit_code == 0  # the chain is intact: snapshots are not evidence
    checked = gaps("verify", "--snapshots", db=db)
    assert checked.exit_code == 1
    assert f"SNAPSHOTS WRONG in run r1: 1 differ from the events, the first after src {src} seq {seq} (t {t})" \
        in checked.stdout
    as_json = json.loads(gaps("verify", "--snapshots", "--json", db=db).stdout)
    assert as_json["ok"] is False and as_json["snapshots"] == {"r1": [[t, seq, src]]}


def test_a_store_without_snapshots_is_left_without_them(tmp_path):
    path = tmp_path / "plain.db"
    with Store(path) as store:
        store.append([event(i) for i in range(5)])
    result = gaps("verify", "--snapshots", db=path)
    assert result.exit_code == 0
    with Store(path) as store:
        assert snapshots.count(store, "r1") == 0  # verify may record its result, never a snapshot
