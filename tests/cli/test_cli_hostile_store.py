"""Hostile store files at the command line (issue 15, finding 6): rows no append writes, put into
the file by someone holding it, end in a clear message and an exit code, never a traceback
(tests.helpers.cli.gaps fails on any)."""
from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pytest

from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event, rows, tamper

BLOB_RUN = b"\x01\x02"


@pytest.fixture
def db(tmp_path) -> Path:
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i) for i in range(5)] + [event(0, kind="monitor.potential_violation")])
    return path


def add_blob_run_checkpoint(path: Path) -> None:
    tamper(path, ("INSERT INTO checkpoints (run, count, head, created_at, merkle_root, frontier, prev_count) "
                  "VALUES (?, 1, 'x', 0, 'y', 'z', 0)", (BLOB_RUN,)))


def break_utf8(path: Path, kind: str) -> None:
    """The event of this kind stored with one byte that is not UTF-8 (SQLite keeps TEXT as given)."""
    conn = sqlite3.connect(path)
    try:
        (text,) = conn.execute("SELECT event FROM events WHERE kind = ?", (kind,)).fetchone()
    finally:
        conn.close()
    raw = text.encode().replace(b"enter" if "violation" in kind else b"red", b"\xffnter", 1)
    tamper(path, ("UPDATE events SET event = CAST(? AS TEXT) WHERE kind = ?", (raw, kind)))


def test_verify_names_a_checkpoint_under_a_blob_run(db):
    add_blob_run_checkpoint(db)
    result = gaps("verify", db=db)
    assert result.exit_code == 1
    assert ("FAILED at run b'\\\\x01\\\\x02' src null seq None (chain position None): rows are recorded under "
            "a run id that is not text") in result.stdout
    as_json = json.loads(gaps("verify", "--json", db=db).stdout)
    assert as_json["ok"] is False and "not text" in as_json["problem"]["what"]
    runs = gaps("runs", "--json", db=db)
    assert runs.exit_code == 0 and [r["chain"] for r in json.loads(runs.stdout)] == ["verified"]


def test_verify_and_runs_name_an_event_that_is_not_utf8(db):
    break_utf8(db, "vehicle.perception")
    result = gaps("verify", db=db)
    assert result.exit_code == 1
    assert ("FAILED at run r1 src vehicle/173 seq 0 (chain position 0): the stored event text is not valid UTF-8"
            in result.stdout)
    runs = gaps("runs", "--json", db=db)
    assert runs.exit_code == 0 and json.loads(runs.stdout)[0]["chain"] == "broken"


def test_incidents_on_an_event_that_is_not_utf8_is_a_clear_error(db):
    break_utf8(db, "monitor.potential_violation")
    result = gaps("incidents", db=db)
    assert result.exit_code == 1
    assert result.stderr.startswith("gaps: run r1: a stored event's text is not valid UTF-8")


def test_incidents_ignore_a_checkpoint_under_a_blob_run(db):
    """Incidents judge the runs that have events; the stray checkpoint is verify's to report."""
    add_blob_run_checkpoint(db)
    result = gaps("incidents", "--json", db=db)
    assert result.exit_code == 0 and len(json.loads(result.stdout)) == 1


def test_import_into_a_store_of_a_newer_schema_is_refused(db, tmp_path):
    tamper(db, ("INSERT INTO schema_version (version) VALUES (99)", ()))
    before = db.read_bytes()
    source = tmp_path / "in.jsonl"
    source.write_text(json.dumps(event(9)) + "\n")
    result = gaps("import", source, db=db)
    assert result.exit_code == 2
    assert "its store schema version 99 is newer than this gaps understands" in result.stderr
    assert db.read_bytes() == before  # refused before the writer switched it to WAL


def test_incidents_on_a_forged_kind_index_entry_stop_with_a_message(db):
    """Issue 15, finding 1: the potential violation's kind index entry rewritten (its row, and the
    chain, intact); incidents must not judge the forgery, and say why (exit 1)."""
    from tests.helpers.split_view import rowid_of, split
    rowid = rowid_of(db, "r1", "monitor/m1", 0)
    [(text,)] = rows(db, "SELECT event FROM events WHERE rowid = ?", (rowid,))
    split(db, "events_by_kind", rowid, event=text.replace("enter the junction", "turn left"))
    result = gaps("incidents", db=db)
    assert result.exit_code == 1
    assert result.stderr.startswith("gaps: event run=r1 src=monitor/m1 seq=0: the store's index by kind")
    assert gaps("verify", db=db).exit_code == 1


def test_columns_that_are_not_utf8_are_named_by_verify_and_stop_the_other_commands(db):
    """A src and a hash that are not UTF-8: verify names the first event; commands that read the
    run's sources end in one message (exit 1) pointing at verify."""
    tamper(db, ("UPDATE events SET src = CAST(? AS TEXT) WHERE seq = 2 AND kind = 'vehicle.perception'",
                (b"vehicle/\xff",)),
           ("UPDATE events SET hash = CAST(? AS TEXT) WHERE seq = 4 AND kind = 'vehicle.perception'", (b"\xff",)))
    result = gaps("verify", db=db)
    assert result.exit_code == 1
    assert "FAILED at run r1 src b'vehicle/\\\\xff' seq 2 (chain position 2): column src is" in result.stdout
    assert json.loads(gaps("verify", "--json", db=db).stdout)["ok"] is False
    for command in ("runs", "incidents"):
        other = gaps(command, db=db)
        assert other.exit_code == 1
        assert other.stderr.startswith("gaps: SQLite could not read the store: Could not decode to UTF-8")
        assert "`gaps verify` says what and where" in other.stderr
