"""Liveliness is evidence too (issue 15): the reasoner's missing-evidence finding reads the
liveliness and wire-miss tables, so since schema v7 each is a hash chain that `gaps verify`
recomputes; an edited, inserted or removed row fails verify, naming the row."""
from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from store import Store, migrate_copy
from store.wire import LivelinessChange, WireMiss
from tests.helpers.store_testkit import old_schema

CHANGES = [LivelinessChange("r", "vehicle/1", True, 10, None), LivelinessChange("r", "vehicle/2", True, 11, None),
           LivelinessChange("r", "vehicle/1", False, 20, 41), LivelinessChange("r", "vehicle/2", False, 30, 9)]
MISSES = [WireMiss("r", "vehicle/2", "entity.state", 3, 25, 7), WireMiss("r", "vehicle/1", "entity.state", 1, 26, 8)]


@pytest.fixture
def wired(tmp_path: Path) -> Path:
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.record_wire(CHANGES[:2], MISSES[:1])
        store.record_wire(CHANGES[2:], MISSES[1:])  # a second write extends the chains
        assert store.verify().ok
    return db


def raw(db: Path, *statements: str) -> None:
    """Change the file as someone holding it would: the append-only triggers dropped first."""
    conn = sqlite3.connect(db)
    for table in ("liveliness", "wire_misses"):
        for op in ("update", "delete"):
            conn.execute(f"DROP TRIGGER IF EXISTS {table}_no_{op}")
    for statement in statements:
        conn.execute(statement)
    conn.commit()
    conn.close()


def problem(db: Path) -> str | None:
    with Store.open_read_only(db) as store:
        report = store.verify()
        assert report.ok is (report.problem is None)
        return None if report.problem is None else report.problem.what


@pytest.mark.parametrize("statement, row", [
    ("UPDATE liveliness SET at = 5 WHERE id = 3", "liveliness row 3"),              # 'stopped publishing' earlier
    ("UPDATE liveliness SET alive = 1 WHERE id = 3", "liveliness row 3"),            # the disappearance hidden
    ("UPDATE liveliness SET last_seq = 2 WHERE id = 3", "liveliness row 3"),
    ("DELETE FROM liveliness WHERE id = 3", "liveliness row 4"),                     # a change removed
    ("INSERT INTO liveliness (id, run, src, alive, at, last_seq, hash) VALUES (9, 'r', 'vehicle/3', 0, 12, 1, "
     "'00')", "liveliness row 9"),                                                    # a change forged
    ("UPDATE wire_misses SET count = 0 WHERE id = 1", "wire_misses row 1"),
    ("UPDATE liveliness SET hash = NULL WHERE id = 1", "liveliness row 1"),
])
def test_an_edited_liveliness_or_wire_miss_row_fails_verify(wired: Path, statement: str, row: str) -> None:
    raw(wired, statement)
    what = problem(wired)
    assert what is not None and what.startswith(row) and "does not match its hash chain" in what


@pytest.mark.parametrize("statement, said", [
    ("DELETE FROM liveliness WHERE id = 4", "a checkpoint names row 4, which the chain does not hold"),
    ("DELETE FROM wire_misses WHERE id = 2", "a checkpoint names row 2, which the chain does not hold"),
    ("DELETE FROM wire_checkpoints WHERE tbl = 'liveliness' AND through_id = 4", "row 4 is not covered"),
    ("UPDATE wire_checkpoints SET head = '00' WHERE tbl = 'liveliness' AND through_id = 2", "another head"),
])
def test_rows_cut_off_the_end_or_checkpoints_changed_fail_verify(wired: Path, statement: str, said: str) -> None:
    """The last rows (a 'stopped publishing' change) are covered by the write's checkpoint."""
    raw(wired, "DROP TRIGGER IF EXISTS wire_checkpoints_no_update", "DROP TRIGGER IF EXISTS wire_checkpoints_no_delete",
        statement)
    what = problem(wired)
    assert what is not None and said in what


def test_the_chains_span_writes_and_hold_when_untouched(wired: Path) -> None:
    hashes = sqlite3.connect(wired).execute("SELECT hash FROM liveliness ORDER BY id").fetchall()
    assert len({h for (h,) in hashes}) == 4 and all(h and len(h) == 64 for (h,) in hashes)
    assert problem(wired) is None


def v6_file(path: Path) -> None:
    """A store as gaps wrote it at schema v6, with liveliness rows and no hashes."""
    conn = old_schema(path, 6)
    conn.execute("INSERT INTO liveliness (run, src, alive, at, last_seq) VALUES ('r', 'vehicle/1', 1, 10, NULL)")
    conn.execute("INSERT INTO wire_misses (run, src, kind, count, at, after_seq) "
                 "VALUES ('r', 'vehicle/1', 'entity.state', 2, 11, 3)")
    conn.close()


def test_a_v6_store_migrates_its_rows_kept_as_legacy_and_new_rows_chained(tmp_path: Path) -> None:
    old, new = tmp_path / "v6.db", tmp_path / "v7.db"
    v6_file(old)
    assert migrate_copy(old, new).from_version == 6
    with Store(new) as store:
        assert store.verify().ok
        store.record_wire([LivelinessChange("r", "vehicle/1", False, 20, 5)])
        assert [c.alive for c in store.liveliness_changes("r")] == [True, False]
        assert store.verify().ok
    assert sqlite3.connect(new).execute("SELECT tbl, through_id FROM wire_legacy ORDER BY tbl").fetchall() == \
        [("liveliness", 1), ("wire_misses", 1)]
    raw(new, "UPDATE liveliness SET at = 19 WHERE id = 2")
    assert problem(new).startswith("liveliness row 2")


def test_verify_names_a_non_text_value_without_a_traceback(wired: Path) -> None:
    raw(wired, "UPDATE liveliness SET src = x'ff' WHERE id = 2")
    assert problem(wired) is not None
