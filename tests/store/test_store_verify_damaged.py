"""Verify on a file SQLite itself cannot read (issue 15, finding 6: random bit flips gave
tracebacks): a report that fails, saying so, never an exception."""
from __future__ import annotations

import sqlite3

from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event


def break_table_root(path) -> None:
    """Overwrite the page type of the events table's root page: SQLite calls the file malformed."""
    conn = sqlite3.connect(path)
    try:
        (root,) = conn.execute("SELECT rootpage FROM sqlite_master WHERE name = 'events'").fetchone()
        (page_size,) = conn.execute("PRAGMA page_size").fetchone()
    finally:
        conn.close()
    with open(path, "r+b") as f:
        f.seek((root - 1) * page_size)
        f.write(b"\x00")


def test_verify_of_a_file_sqlite_cannot_read_fails_with_a_report(db_path):
    with Store(db_path) as store:
        store.append([event(i) for i in range(300)])
    break_table_root(db_path)
    with Store.open_read_only(db_path) as store:
        report = store.verify()
    assert not report.ok and report.integrity.ok is False
    assert report.problem.what.startswith("SQLite cannot read the store file: database disk image is malformed")
    result = gaps("verify", db=db_path)
    assert result.exit_code == 1 and "FAILED: " in result.stdout
