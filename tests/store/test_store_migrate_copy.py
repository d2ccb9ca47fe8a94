"""store.migrate_copy: an older store copied to a new file at the current schema; the source is
never changed and the destination never overwritten."""

import hashlib

import pytest
from tests.helpers.store_testkit import event, rows
from tests.helpers.store_testkit import write_v1_file

from store import MigrateReport, Store, StoreError, migrate_copy
from store.ddl import SCHEMA_VERSION


def sha(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


@pytest.fixture
def v1(tmp_path):
    path = tmp_path / "old.db"
    write_v1_file(path, [event(i) for i in range(7)], calls=[3, 4])
    return path


def test_a_v1_store_is_copied_at_the_current_version(v1, tmp_path):
    before = sha(v1)
    dst = tmp_path / "new.db"
    report = migrate_copy(v1, dst)
    assert report == MigrateReport(str(v1), str(dst), 1, SCHEMA_VERSION, 7)
    assert sha(v1) == before and rows(v1, "SELECT version FROM schema_version") == [(1,)]
    assert [v for (v,) in rows(dst, "SELECT version FROM schema_version")] == list(range(1, SCHEMA_VERSION + 1))
    with Store.open_read_only(dst) as store:
        assert store.verify().ok
        assert [ev["seq"] for ev in store.events("r1")] == list(range(7))
    assert not [p.name for p in tmp_path.iterdir() if p.name.endswith(".partial")]  # nothing half-written left


def test_an_existing_destination_is_never_overwritten(v1, tmp_path):
    dst = tmp_path / "taken.db"
    dst.write_bytes(b"mine")
    with pytest.raises(StoreError, match=f"{dst} already exists"):
        migrate_copy(v1, dst)
    assert dst.read_bytes() == b"mine"


def test_a_source_that_is_not_a_store_is_refused(tmp_path):
    empty = tmp_path / "empty.db"
    empty.touch()
    with pytest.raises(StoreError, match="not an event store"):
        migrate_copy(empty, tmp_path / "out.db")
    assert not (tmp_path / "out.db").exists()
    assert sorted(p.name for p in tmp_path.iterdir()) == ["empty.db"]
