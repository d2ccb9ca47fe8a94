"""SQLite's conditions leave the store as its own errors (store/sqlite_errors.py): each kind named
for what the user must do, SQLite's words its message, and, where the file or disk is the cause,
the condition the ingest waits out. Real SQLite failures: a page limit (SQLite's own full disk),
a held lock, a connection made read-only, a file that is not a database, a damaged page."""
from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from ingest.store_faults import store_condition
from store import Store, StoreFault, store_fault, translating
from store.errors import DiskFull, RowRefused, StoreBusy, StoreDamaged, StoreReadOnly
from tests.helpers.store_testkit import event


@pytest.fixture
def db(tmp_path: Path) -> Path:
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i) for i in range(50)])
    return path


def test_a_full_disk_is_diskfull_and_a_condition(db):
    with Store(db) as store:
        pages = store.connection.execute("PRAGMA page_count").fetchone()[0]
        store.connection.execute(f"PRAGMA max_page_count = {pages}")
        with pytest.raises(DiskFull, match="database or disk is full") as raised:
            store.append([event(i, body={"note": "x" * 4000}) for i in range(50, 300)])
    assert raised.value.condition == "the disk is full" == store_condition(raised.value)
    assert raised.value.code is not None and raised.value.code & 0xFF == 13
    assert isinstance(raised.value.__cause__, sqlite3.OperationalError)


def test_a_read_only_store_is_storereadonly(db):
    with Store(db) as store:
        store.connection.execute("PRAGMA query_only = 1")
        with pytest.raises(StoreReadOnly, match="readonly database") as raised:
            store.append([event(50)])
    assert store_condition(raised.value) == "the store is read-only"


def test_a_locked_store_is_storebusy(db):
    holder = sqlite3.connect(db, isolation_level=None)
    holder.execute("BEGIN EXCLUSIVE")
    try:
        with pytest.raises(StoreBusy, match="database is locked") as raised:
            Store(db, durable=True).close()
    finally:
        holder.execute("ROLLBACK")
        holder.close()
    assert store_condition(raised.value) in ("the store is busy", "the store is locked")


def test_a_damaged_page_read_is_storedamaged_not_a_condition(db):
    size = db.stat().st_size
    page = 16384
    assert size > 3 * page
    with open(db, "r+b") as f:         # every page past the schema's overwritten: the b-trees' pages
        f.seek(2 * page)
        f.write(b"\xff" * (size - 2 * page))
    with pytest.raises(StoreFault) as raised:
        with Store.open_read_only(db) as store:
            list(store.events("r1"))   # met while iterating: the stream translates too
    assert isinstance(raised.value, StoreDamaged), raised.value
    assert "malformed" in str(raised.value) and store_condition(raised.value) is None


def test_an_integrity_violation_is_rowrefused_not_a_condition(tmp_path):
    conn = sqlite3.connect(tmp_path / "x.db")
    conn.execute("CREATE TABLE t (k INTEGER PRIMARY KEY)")
    conn.execute("INSERT INTO t VALUES (1)")
    with pytest.raises(RowRefused, match="UNIQUE constraint failed") as raised:
        with translating():
            conn.execute("INSERT INTO t VALUES (1)")
    conn.close()
    assert store_condition(raised.value) is None


def test_an_error_without_a_code_is_read_from_its_words():
    """As an injected error (tests/ingest) carries no result code."""
    fault = store_fault(sqlite3.OperationalError("database is locked (injected)"))
    assert isinstance(fault, StoreBusy) and fault.condition == "the store is locked"
    assert isinstance(store_fault(sqlite3.DataError("string or blob too big")), RowRefused)
    assert store_fault(ValueError("not the store's")) is None
