"""What SQLite says of the store reaches the user as one line and the README's exit code, never a
traceback: said as before the store translated SQLite's errors into its own (store/sqlite_errors.py).
A command that writes names what it was doing (exit 2); any other says SQLite could not read the
store and that `gaps verify` says what and where (exit 1). Real SQLite failures: a held lock, a
connection made read-only (PRAGMA query_only), SQLite's own full disk (PRAGMA max_page_count), a
file whose pages are overwritten."""
from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pytest

import store
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event

DAMAGE_HINT = "; the file may be damaged or altered: `gaps verify` says what and where"


@pytest.fixture
def db(tmp_path: Path) -> Path:
    path = tmp_path / "gaps.db"
    with Store(path) as kept:
        kept.append([event(i) for i in range(50)])
    return path


@pytest.fixture
def source(tmp_path: Path) -> Path:
    path = tmp_path / "more.jsonl"
    path.write_text("".join(json.dumps(event(seq)) + "\n" for seq in range(50, 60)))
    return path


def _writes_with(monkeypatch: pytest.MonkeyPatch, pragma: str) -> None:
    """Every Store the command opens runs `pragma` on its connection before it appends."""
    class Limited(Store):
        def _append(self, feed):
            self.connection.execute(pragma.format(pages=self.connection.execute("PRAGMA page_count").fetchone()[0]))
            return super()._append(feed)
    monkeypatch.setattr(store, "Store", Limited)


def test_import_into_a_read_only_store(db, source, monkeypatch):
    _writes_with(monkeypatch, "PRAGMA query_only = 1")
    result = gaps("import", source, db=db)
    assert (result.exit_code, result.output) == (
        2, f"gaps: cannot import {source} into {db}: attempt to write a readonly database\n")


def test_import_into_a_full_store(tmp_path, db, monkeypatch):
    big = tmp_path / "big.jsonl"
    big.write_text("".join(json.dumps(event(seq, body={"note": "x" * 4000})) + "\n" for seq in range(50, 90)))
    _writes_with(monkeypatch, "PRAGMA max_page_count = {pages}")
    result = gaps("import", big, db=db)
    assert (result.exit_code, result.output) == (2, f"gaps: cannot import {big} into {db}: database or disk is full\n")


def test_import_into_a_locked_store(db, source):
    holder = sqlite3.connect(db, isolation_level=None)
    holder.execute("BEGIN EXCLUSIVE")       # another writer, holding the lock past SQLite's 5 s wait
    try:
        result = gaps("import", source, db=db)
    finally:
        holder.execute("ROLLBACK")
        holder.close()
    assert (result.exit_code, result.output) == (2, f"gaps: cannot import {source} into {db}: database is locked\n")


def _overwrite_pages(db: Path) -> None:
    """Every page past the first two (the schema's) overwritten: the store opens, its b-trees do not read."""
    page = 16384
    size = db.stat().st_size
    assert size > 3 * page
    with open(db, "r+b") as f:
        f.seek(2 * page)
        f.write(b"\xff" * (size - 2 * page))


def test_a_read_of_a_damaged_store(db):
    _overwrite_pages(db)
    result = gaps("runs", db=db)
    assert (result.exit_code, result.output) == (
        1, f"gaps: SQLite could not read the store: database disk image is malformed{DAMAGE_HINT}\n")


def test_an_export_of_a_damaged_store(tmp_path, db):
    _overwrite_pages(db)
    out = tmp_path / "out.jsonl"
    result = gaps("export", "--run", "r1", "-o", out, db=db)
    assert (result.exit_code, result.output) == (
        2, f"gaps: cannot export run r1 to {out}: database disk image is malformed\n")
