"""What the ingest noticed on the wire is kept beside the events: liveliness changes and samples lost
beyond a publisher's cache, append-only, outside the hash chains, read without changing the file."""
from __future__ import annotations

import hashlib
import sqlite3
from pathlib import Path

import pytest

from store import Store
from store.wire import LivelinessChange, WireMiss


def test_changes_and_misses_are_kept_and_summed_up_per_source(tmp_path: Path) -> None:
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.record_wire([LivelinessChange("r", "vehicle/1", True, 10, None),
                           LivelinessChange("r", "vehicle/2", True, 11, None),
                           LivelinessChange("r", "vehicle/1", False, 20, 41)],
                          [WireMiss("r", "vehicle/2", "entity.state", 3, 25, 7)])
        head = store.verify().ok
    digest = hashlib.sha256(db.read_bytes()).hexdigest()
    with Store.open_read_only(db) as store:
        lives = {life.src: life for life in store.lives("r")}
        assert (lives["vehicle/1"].alive, lives["vehicle/1"].disappeared_at, lives["vehicle/1"].last_seq) == (False, 20, 41)
        assert lives["vehicle/2"].alive and lives["vehicle/2"].appeared_at == 11
        assert [c.alive for c in store.liveliness_changes("r", "vehicle/1")] == [True, False]
        assert store.wire_misses("r") == [WireMiss("r", "vehicle/2", "entity.state", 3, 25, 7)]
        assert store.count() == 0 and head        # no event, no chain touched
    assert hashlib.sha256(db.read_bytes()).hexdigest() == digest


@pytest.mark.parametrize("table", ["liveliness", "wire_misses"])
def test_the_records_cannot_be_rewritten(tmp_path: Path, table: str) -> None:
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.record_wire([LivelinessChange("r", "vehicle/1", True, 10, None)],
                          [WireMiss("r", "vehicle/1", "entity.state", 1, 12, 0)])
    conn = sqlite3.connect(db)
    with pytest.raises(sqlite3.DatabaseError, match="append-only"):
        conn.execute(f"DELETE FROM {table}")
    conn.close()
