"""`gaps verify`: exit codes for scripts, the first event that does not match, progress on stderr
only, and with --snapshots the state snapshots checked against a fresh fold of the events."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from store import Store
from store.cache import snapshots
from store.state import build_snapshots
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import T0, event, tamper

GAPS = str(Path(sys.executable).with_name("gaps"))


@pytest.fixture
def snapshot_db(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i, t=T0 + i * 1_000_000, kind="entity.state",
                            body={"x": float(i), "y": 0.0, "speed_mps": 1.0}) for i in range(40)])
        build_snapshots(store, "r1", every=10)
    return path


def forge_snapshot(path, offset, sealed=True):
    """Alter one snapshot behind the store's back: vehicle/173 said to be somewhere it never was;
    `sealed`: by someone who holds the cache key too (else its seal no longer opens)."""
    with Store(path) as store:
        conn = store.cache.connection
        t, seq, src, n, head, blob, mac, epoch = conn.execute(
            "SELECT t, seq, src, chain_len, head, state, mac, epoch FROM state_snapshots ORDER BY t LIMIT 1 OFFSET ?",
            (offset,)).fetchone()
        forged = snapshots.decode(blob)
        forged["entities"]["vehicle/173"]["state"]["body"]["x"] = -999.0
        blob = snapshots.encode(forged)
        if sealed:
            mac = store.cache.sealer.seal("state_snapshots", ("r1", snapshots.FOLD_VERSION, t, seq, src, n, head),
                                          (blob, epoch))
        conn.execute("UPDATE state_snapshots SET state = ?, mac = ? WHERE t = ? AND seq = ? AND src = ?",
                     (blob, mac, t, seq, src))
    return t, seq, src


def test_matching_snapshots_pass(snapshot_db):
    result = gaps("verify", "--snapshots", db=snapshot_db)
    assert result.exit_code == 0, result.output
    assert "every state snapshot matches its events" in result.stdout
    as_json = json.loads(gaps("verify", "--snapshots", "--json", db=snapshot_db).stdout)
    assert as_json["ok"] is True and as_json["snapshots"] == {"r1": []}


def test_a_snapshot_forged_without_the_cache_key_is_a_warning_and_never_read(snapshot_db):
    """Issue 15, finding 2: a snapshot written behind gaps' back does not carry its seal; reads
    pass it over (so the scene is the events'), and verify names it as a warning, exit 0."""
    from store import state_at
    with Store(snapshot_db) as store:
        before = state_at(store, "r1", T0 + 35_000_000).to_json()
    t, seq, src = forge_snapshot(snapshot_db, 2, sealed=False)
    with Store(snapshot_db) as store:
        assert state_at(store, "r1", T0 + 35_000_000).to_json() == before
        assert store.cache.sealer.tampered() == {"state_snapshots": 1}
    forge_snapshot(snapshot_db, 1, sealed=False)
    checked = gaps("verify", db=snapshot_db)
    assert checked.exit_code == 0, checked.output
    assert "WARNING: the cache file beside the store holds 1 entries that do not carry their seal" in checked.stdout
    as_json = json.loads(gaps("verify", "--json", db=snapshot_db).stdout)
    assert as_json["ok"] is True and as_json["cache"]["ok"] is False
    assert len(as_json["cache"]["snapshots"]["r1"]) == 1


def test_a_wrong_snapshot_fails_verify(snapshot_db):
    """A snapshot is not evidence, but scenes and verdicts read state from it: a forged one with
    a correct key and seal (by someone holding the cache key) must fail plain `gaps verify`, or it
    could change a verdict quietly."""
    t, seq, src = forge_snapshot(snapshot_db, 2)
    skipped = gaps("verify", "--no-snapshots", db=snapshot_db)
    assert skipped.exit_code == 0  # the chain itself is intact
    checked = gaps("verify", db=snapshot_db)
    assert checked.exit_code == 1
    assert f"SNAPSHOTS WRONG in run r1: 1 differ from the events, the first after src {src} seq {seq} (t {t})" \
        in checked.stdout
    as_json = json.loads(gaps("verify", "--snapshots", "--json", db=snapshot_db).stdout)
    assert as_json["ok"] is False and as_json["snapshots"] == {"r1": [[t, seq, src]]}


def test_a_store_without_snapshots_is_left_without_them(tmp_path):
    path = tmp_path / "plain.db"
    with Store(path) as store:
        store.append([event(i) for i in range(5)])
    result = gaps("verify", "--snapshots", db=path)
    assert result.exit_code == 0
    with Store(path) as store:
        assert snapshots.count(store, "r1") == 0  # verify may record its result, never a snapshot


def test_verify_exit_codes(db, tmp_path):
    ok = gaps("verify", db=db)
    assert ok.exit_code == 0 and "verified" in ok.stdout
    tamper(db, ("UPDATE events SET event = replace(event, 'red light', 'red lighT') "
                "WHERE run = 'r1' AND seq = 5", ()))
    bad = gaps("verify", db=db)
    assert bad.exit_code == 1
    assert "FAILED at run r1 src vehicle/173 seq 5 (chain position 3): hash does not match" in bad.stdout
    as_json = json.loads(gaps("verify", "--json", db=db).stdout)
    assert as_json["ok"] is False and as_json["problem"]["seq"] == 5
    missing = gaps("verify", db=tmp_path / "none.db")
    assert missing.exit_code == 2 and "no event store at" in missing.output


def test_installed_gaps_verify_draws_progress_on_stderr_only(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path, durable=False) as store:
        store.append([event(i, t=T0 + i) for i in range(40_000)])
    env = dict(os.environ, FORCE_COLOR="1", COLUMNS="100")
    result = subprocess.run([GAPS, "verify", "--json", "--db", str(path)], capture_output=True, text=True,
                            env=env, timeout=120)
    assert result.returncode == 0, result.stderr
    assert json.loads(result.stdout)["ok"] is True  # stdout stays pure JSON
    assert "verifying" in result.stderr


def test_verify_fails_on_an_index_that_disagrees_with_its_table(db):
    """Issue 15, finding 1: a kind index entry rewritten (the chain intact) fails `gaps verify`."""
    from tests.helpers.split_view import rowid_of, split
    rowid = rowid_of(db, "r2", "monitor/m1", 0)
    split(db, "events_by_kind", rowid, kind="entity.state")  # the observation hidden from reads by kind
    bad = gaps("verify", db=db)
    assert bad.exit_code == 1
    assert "r2: 1 events, chain ok" in bad.stdout
    assert ("FAILED: the store file fails SQLite's integrity check: row " in bad.stdout
            and "missing from index events_by_kind" in bad.stdout)
    as_json = json.loads(gaps("verify", "--json", db=db).stdout)
    assert as_json["ok"] is False and as_json["integrity"]["ok"] is False
    assert "events_by_kind" in as_json["integrity"]["messages"][0]
