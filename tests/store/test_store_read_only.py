"""Opening a store to read it changes nothing in the file: no lock for writing, no migration, no
WAL switch, no schema created, no -wal or -shm file; what cannot be read says why."""

import hashlib
import os
import shutil
import sqlite3
import stat

import pytest
from tests.helpers.store_testkit import T0, event
from tests.helpers.store_testkit import write_v1_file

from store import GapsError, Store, StoreError
from store.state import state_at


def fingerprint(path):
    """The file's bytes and mtime, and which sidecar files exist beside it."""
    data = hashlib.sha256(path.read_bytes()).hexdigest()
    sidecars = sorted(p.name for p in path.parent.iterdir() if p.name.startswith(path.name + "-"))
    return data, path.stat().st_mtime_ns, sidecars


@pytest.fixture
def written(db_path):
    with Store(db_path) as store:
        store.append([event(i, kind="entity.state", t=T0 + i * 1_000_000) for i in range(50)])
    return db_path


def test_a_closed_store_is_left_without_wal_files(written):
    assert fingerprint(written)[2] == []
    with sqlite3.connect(written) as conn:
        assert conn.execute("PRAGMA journal_mode").fetchone() == ("delete",)


def test_reading_changes_nothing_in_the_file(written):
    before = fingerprint(written)
    with Store.open_read_only(written) as store:
        assert store.count("r1") == 50
        assert store.verify("r1").ok
        assert state_at(store, "r1", T0 + 30_000_000).events == 31  # snapshots go to the cache
        assert [r.run for r in store.runs()] == ["r1"]
    assert fingerprint(written) == before
    assert (written.parent / (written.name + ".cache")).is_file()


def test_writing_through_a_read_only_store_is_a_store_error(written):
    with Store(written, read_only=True) as store:
        with pytest.raises(StoreError, match="open read-only"):
            store.append([event(99)])
        with pytest.raises(StoreError, match="open read-only"):
            store.put_rulebook("hc", "1", "text")
    with Store.open_read_only(written) as store:
        assert store.count() == 50


def test_a_missing_file_is_named(tmp_path):
    missing = tmp_path / "nope.db"
    with pytest.raises(StoreError, match=f"no event store at {missing}: the file does not exist"):
        Store.open_read_only(missing)
    assert not missing.exists()


def test_an_empty_file_is_not_an_event_store(tmp_path):
    empty = tmp_path / "empty.db"
    empty.touch()
    with pytest.raises(StoreError, match=f"{empty}: not an event store \\(the file is empty\\)") as raised:
        Store.open_read_only(empty)
    assert isinstance(raised.value, GapsError) and raised.value.exit_code == 2
    assert empty.stat().st_size == 0


def test_a_file_that_is_not_sqlite_is_not_an_event_store(tmp_path):
    junk = tmp_path / "junk.db"
    junk.write_bytes(b"these are not the pages you are looking for\n" * 200)
    with pytest.raises(StoreError, match="not an event store \\(file is not a database\\)"):
        Store.open_read_only(junk)
    with pytest.raises(StoreError, match="not an event store \\(file is not a database\\)"):
        Store(junk)


def test_an_sqlite_file_without_the_log_is_not_an_event_store(tmp_path):
    other = tmp_path / "other.db"
    with sqlite3.connect(other) as conn:
        conn.execute("CREATE TABLE notes (text TEXT)")
    with pytest.raises(StoreError, match="not an event store \\(it holds no event log\\)"):
        Store.open_read_only(other)


def test_an_old_schema_is_refused_with_the_way_to_migrate(db_path):
    write_v1_file(db_path, [event(i) for i in range(5)], calls=[5])
    before = fingerprint(db_path)
    with pytest.raises(StoreError) as raised:
        Store.open_read_only(db_path)
    message = str(raised.value)
    assert "schema version 1 is older" in message and "run `gaps migrate SRC DST` to write a migrated copy" in message
    assert fingerprint(db_path) == before


@pytest.fixture
def read_only_copy(written, tmp_path, monkeypatch):
    """A copy left in WAL mode (as a writer still running would leave it) in a folder and file
    without write permission, like read-only media."""
    with sqlite3.connect(written) as conn:
        conn.execute("PRAGMA journal_mode=WAL")
    folder = tmp_path / "media"
    folder.mkdir()
    copy = folder / "gaps.db"
    shutil.copyfile(written, copy)
    copy.chmod(stat.S_IRUSR | stat.S_IRGRP)
    folder.chmod(stat.S_IRUSR | stat.S_IXUSR)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    yield copy
    folder.chmod(stat.S_IRWXU)
    copy.chmod(stat.S_IRUSR | stat.S_IWUSR)


def test_a_store_on_read_only_media_is_read_immutable(read_only_copy, tmp_path):
    before = fingerprint(read_only_copy)
    with Store.open_read_only(read_only_copy) as store:
        assert store.count("r1") == 50 and store.verify().ok
        assert state_at(store, "r1", T0 + 40_000_000).events == 41
        cache = store.cache.path
    assert fingerprint(read_only_copy) == before  # no -wal or -shm made beside it either
    assert os.listdir(read_only_copy.parent) == ["gaps.db"]
    assert cache.startswith(str(tmp_path / "xdg" / "mind-the-gaps")) and os.path.isfile(cache)
