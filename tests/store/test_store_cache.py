"""The cache file: derived data kept beside the store, never in it, keyed by the chain it was
derived from, so that deleting it changes no answer and a cache of another chain head is not used."""

import json
import os

import pytest
from tests.helpers.store_testkit import T0, event, rows

from store import Store
from store.cache import snapshots
from store.state import build_snapshots, state_at


def states(n, *, first=0, t0=T0):
    return [event(i, kind="entity.state", t=t0 + i * 1_000_000,
                  body={"x": float(i), "y": 0.0, "speed_mps": 1.0}) for i in range(first, first + n)]


def folded(store, t):
    return state_at(store, "r1", t, use_snapshots=False)


def test_snapshots_are_written_to_the_cache_not_the_store(store, db_path):
    store.append(states(40))
    assert build_snapshots(store, "r1", every=10) == 4
    tables = {name for (name,) in rows(db_path, "SELECT name FROM sqlite_master WHERE type = 'table'")}
    assert not tables & {"state_snapshots", "state_watermarks", "verifications"}
    assert store.cache.path == f"{db_path}.cache"
    assert rows(store.cache.path, "SELECT count(*) FROM state_snapshots") == [(4,)]


def test_deleting_the_cache_changes_no_answer(db_path):
    with Store(db_path) as store:
        store.append(states(60))
        build_snapshots(store, "r1", every=7)
        before = [state_at(store, "r1", T0 + ms * 1_000_000) for ms in (0, 13, 59)]
        verdict = store.verified("r1").as_dict()
    os.remove(f"{db_path}.cache")
    with Store.open_read_only(db_path) as store:
        assert [state_at(store, "r1", T0 + ms * 1_000_000) for ms in (0, 13, 59)] == before
        assert store.verified("r1").as_dict() == verdict


def forge(store, t, chain_len, head):
    """A snapshot at t that holds a vehicle no event mentions, keyed to the chain given."""
    state = {k: v for k, v in folded(store, t).to_json().items() if k not in ("run", "t")}  # a snapshot's keys
    state["entities"]["vehicle/666"] = state["entities"]["vehicle/173"]
    last = state["last"]
    blob = snapshots.encode(state)
    key = ("r1", snapshots.FOLD_VERSION, last["t"], last["seq"], last["src"], chain_len, head)
    (epoch,) = store.cache.connection.execute("SELECT epoch FROM state_watermarks WHERE run = 'r1'").fetchone()
    mac = store.cache.sealer.seal(snapshots.SNAPSHOTS, key, (blob, epoch))  # by a holder of the cache key
    store.cache.connection.execute("INSERT OR REPLACE INTO state_snapshots VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                                   (*key, blob, epoch, mac))


def test_a_wrong_snapshot_of_an_old_head_is_not_used_once_late_events_arrive(db_path):
    with Store(db_path) as store:
        store.append(states(30, t0=T0 + 100_000_000))
        build_snapshots(store, "r1", every=10)
        head = rows(db_path, "SELECT hash FROM events WHERE chain_pos = 29")[0][0]
        forge(store, T0 + 120_000_000, 30, head)  # keyed to the head of 30 events
    with Store(db_path) as writer:  # no hook: the cache hears nothing of this
        writer.append([event(0, src="vehicle/9", kind="entity.state", t=T0 + 50_000_000,
                             body={"x": 9.0, "y": 0.0, "speed_mps": 0.0})])
    with Store.open_read_only(db_path) as reader:
        t = T0 + 125_000_000
        assert "vehicle/666" not in state_at(reader, "r1", t).entities
        assert state_at(reader, "r1", t) == folded(reader, t)


def test_a_snapshot_of_another_chain_is_not_used(store, db_path):
    store.append(states(30))
    build_snapshots(store, "r1", every=10)
    forge(store, T0 + 25_000_000, 26, "ab" * 32)  # a head this store never had at 26 events
    t = T0 + 27_000_000
    assert "vehicle/666" not in state_at(store, "r1", t).entities
    assert state_at(store, "r1", t) == folded(store, t)


def test_a_cache_of_another_store_is_not_used(tmp_path):
    one, two = tmp_path / "one.db", tmp_path / "two.db"
    with Store(one) as store:
        store.append(states(40))
        build_snapshots(store, "r1", every=10)
        store.verify("r1")
    with Store(two) as store:
        store.append(states(40, t0=T0 + 7))  # same run name, same length, other events
    os.replace(f"{one}.cache", f"{two}.cache")
    with Store.open_read_only(two) as store:
        for ms in (5, 15, 35, 39):
            assert state_at(store, "r1", T0 + 7 + ms * 1_000_000) == folded(store, T0 + 7 + ms * 1_000_000)
        assert store.verified("r1").runs[0].head == store.verify("r1").runs[0].head


def test_verification_is_computed_once_per_chain_head(store, monkeypatch):
    store.append(states(20))
    first = store.verified("r1")
    assert first.ok
    calls = []
    monkeypatch.setattr("store.db.verify_store", lambda *a, **k: calls.append(a) or first)
    assert store.verified("r1").as_dict() == first.as_dict() and calls == []
    store.append(states(1, first=20))  # a new head: recomputed
    store.verified("r1")
    assert len(calls) == 1


def test_verify_always_recomputes_and_a_forged_result_does_not_survive_a_new_head(store, db_path):
    store.append(states(20))
    store.verify("r1")
    forged = {"ok": False, "runs": [{"run": "r1", "events": 20, "head": None, "ok": False}],
              "problem": {"run": "r1", "src": None, "seq": None, "chain_pos": 3, "what": "forged"}}
    store.cache.connection.execute("UPDATE verifications SET report = ?", (json.dumps(forged),))
    assert store.verify("r1").ok  # the command's own verdict is never the cache's
    store.append(states(1, first=20))
    assert store.verified("r1").ok


def test_a_damaged_cache_file_is_replaced_by_one_in_memory(db_path):
    with Store(db_path) as store:
        store.append(states(20))
    with open(f"{db_path}.cache", "wb") as junk:
        junk.write(b"not a cache " * 500)
    with Store.open_read_only(db_path) as store:
        assert state_at(store, "r1", T0 + 19_000_000) == folded(store, T0 + 19_000_000)
        assert store.cache.path == ":memory:"


@pytest.mark.parametrize("version", [0, 99])
def test_a_cache_of_another_version_is_emptied(db_path, version):
    with Store(db_path) as store:
        store.append(states(20))
        build_snapshots(store, "r1", every=5)
        store.cache.connection.execute(f"PRAGMA user_version = {version}")
    with Store(db_path) as store:
        assert snapshots.count(store, "r1") == 0
        assert state_at(store, "r1", T0 + 19_000_000) == folded(store, T0 + 19_000_000)


def test_a_store_named_relative_to_the_working_folder_keeps_its_cache_beside_it(tmp_path, monkeypatch):
    """`gaps incidents` with the default ./gaps.db (or any --db without a folder) kept nothing: the
    cache's folder was "", making it failed, and the cache fell back to memory, so every command
    measured the whole run again (a 10-minute run's 30 s, each time)."""
    monkeypatch.chdir(tmp_path)
    with Store("gaps.db") as store:
        store.append(states(40))
    with Store.open_read_only("gaps.db") as store:
        assert build_snapshots(store, "r1", every=10) == 4
        assert store.cache.path == "gaps.db.cache"
    assert rows(str(tmp_path / "gaps.db.cache"), "SELECT count(*) FROM state_snapshots") == [(4,)]
