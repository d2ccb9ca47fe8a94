"""The cache's seals (issue 15, finding 2): a cache can make things faster, never different. Every
entry is sealed under a key kept outside the store's folder; an entry whose seal does not open is
dropped, rebuilt and counted, never believed."""
from __future__ import annotations

import json
import os
import sqlite3
import stat
from pathlib import Path

import pytest

from store import Store, state_at
from store.cache import seal as cache_seal, cache_tampering
from store.cache.file import MEMORY
from store.state import build_snapshots
from tests.helpers.store_testkit import T0, event


def states(n: int) -> list[dict]:
    return [event(i, t=T0 + i * 1_000_000, kind="entity.state", body={"x": float(i), "y": 0.0, "speed_mps": 1.0})
            for i in range(n)]


def test_the_key_is_made_once_0600_outside_the_store_folder(tmp_path: Path, monkeypatch) -> None:
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    key = cache_seal.load_or_create_key()
    path = Path(cache_seal.key_path())
    assert key is not None and len(key) == 32 and path.read_bytes() == key
    assert path.parent == tmp_path / "config" / "mind-the-gaps"
    assert stat.S_IMODE(path.stat().st_mode) == 0o600
    assert cache_seal.load_or_create_key() == key  # the same key on the next use


def test_without_a_place_for_the_key_the_cache_lives_in_memory(tmp_path: Path, monkeypatch) -> None:
    """A persistent cache sealed under a key of this process would be believed by no other: none
    is written, and reads still work."""
    blocker = tmp_path / "not-a-folder"
    blocker.write_text("")
    monkeypatch.setenv("XDG_CONFIG_HOME", str(blocker))
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.append(states(30))
        build_snapshots(store, "r1", every=10)
        assert store.cache.path == MEMORY and state_at(store, "r1", T0 + 25_000_000).entities
    assert not Path(f"{db}.cache").exists()


def test_a_cache_sealed_under_another_key_is_emptied_not_reported(tmp_path: Path, monkeypatch) -> None:
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.append(states(30))
        build_snapshots(store, "r1", every=10)
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "another"))  # a new key: not tampering
    with Store(db) as store:
        assert cache_tampering(store, ["r1"]).ok
        assert store.cache.connection.execute("SELECT count(*) FROM state_snapshots").fetchone() == (0,)


def test_a_forged_verification_is_not_cited_and_is_counted(tmp_path: Path) -> None:
    """The explanation cites Store.verified: a result written behind gaps' back (an altered run
    declared intact, or an intact one declared broken) is recomputed, not believed."""
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.append(states(20))
        assert store.verified("r1").ok
        forged = {"ok": False, "runs": [{"run": "r1", "events": 20, "head": None, "ok": False}],
                  "problem": {"run": "r1", "src": None, "seq": None, "chain_pos": 3, "what": "forged"}}
        store.cache.connection.execute("UPDATE verifications SET report = ?", (json.dumps(forged),))
        assert cache_tampering(store, ["r1"]).verifications == [["r1", 20, store.chain_head("r1")[1]]]
        assert store.verified("r1").ok
        assert store.cache.sealer.tampered() == {"verifications": 1}


@pytest.mark.parametrize("change", [
    "UPDATE state_watermarks SET chain_len = chain_len + 100",
    "UPDATE state_snapshots SET chain_len = chain_len - 1",
    "DELETE FROM state_snapshots WHERE rowid IN (SELECT rowid FROM state_snapshots LIMIT 1)",
])
def test_snapshot_entries_changed_behind_gaps_back_change_no_scene(tmp_path: Path, change: str) -> None:
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.append(states(40))
        build_snapshots(store, "r1", every=7)
        before = [state_at(store, "r1", T0 + ms * 1_000_000).to_json() for ms in (5, 15, 30, 39)]
    conn = sqlite3.connect(f"{db}.cache")
    conn.execute(change)
    conn.commit()
    conn.close()
    with Store.open_read_only(db) as store:
        assert [state_at(store, "r1", T0 + ms * 1_000_000).to_json() for ms in (5, 15, 30, 39)] == before


def test_the_seal_binds_table_key_and_payload() -> None:
    sealer = cache_seal.Sealer(bytes(32))
    mac = sealer.seal("t", ("r1", 3, "ab"), b"payload")
    assert sealer.opens("t", ("r1", 3, "ab"), b"payload", mac)
    for table, key, payload in (("u", ("r1", 3, "ab"), b"payload"), ("t", ("r1", 4, "ab"), b"payload"),
                                ("t", ("r1", 3, "ab"), b"payloaD"), ("t", ("r1", "3", "ab"), b"payload"),
                                ("t", ("r1", 3), ("ab", b"payload"))):
        assert not sealer.opens(table, key, payload, mac)
    assert sealer.tampered() == {"u": 1, "t": 4}
    assert not cache_seal.Sealer(os.urandom(32)).opens("t", ("r1", 3, "ab"), b"payload", mac)


def test_a_stale_snapshot_put_back_is_not_used(tmp_path: Path) -> None:
    """A genuine, sealed snapshot that a late event made stale, put back from a copy of the cache
    kept before: it is of an older epoch than the watermark's, so no read uses it."""
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.append(states(30))
        build_snapshots(store, "r1", every=5)
        conn = store.cache.connection
        kept = conn.execute("SELECT * FROM state_snapshots WHERE t >= ?", (T0 + 20_000_000,)).fetchall()
        assert kept
        store.append([event(0, src="vehicle/9", kind="entity.state", t=T0 + 15_500_000,
                            body={"x": 9.0, "y": 9.0, "speed_mps": 0.0})])  # late: before those snapshots
        truth = state_at(store, "r1", T0 + 29_000_000, use_snapshots=False)
        assert state_at(store, "r1", T0 + 29_000_000) == truth  # the late event drops them
        conn.executemany(f"INSERT OR REPLACE INTO state_snapshots VALUES ({', '.join('?' * len(kept[0]))})", kept)
    with Store.open_read_only(db) as store:
        assert "vehicle/9" in state_at(store, "r1", T0 + 29_000_000).entities
        assert state_at(store, "r1", T0 + 29_000_000) == truth
