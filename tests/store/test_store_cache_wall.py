"""The store's error wall holds for the cache's parts it hands out as modules too: what the
reasoner keeps of a run (store.cache.derived) and the reads of a Timeline leave as the store's own
errors, never sqlite3's (store/sqlite_errors.py). Real SQLite failures: the pages of a cache
file or a store file overwritten, so that SQLite finds them malformed."""
from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from store import Store, Timeline
from store.cache import derived, kept_recording
from store.errors import StoreDamaged
from tests.helpers.store_testkit import event

KIND, VERSION = "measurement", "test-version"


def _damage(path: str | Path, *, past_roots: bool = True) -> None:
    """Overwrite every page after the tables' root pages (the b-trees' other pages), or every
    page after the first two (the schema's: test_store_faults.py damages a store so)."""
    conn = sqlite3.connect(path)
    (page,) = conn.execute("PRAGMA page_size").fetchone()
    (last_root,) = conn.execute("SELECT max(rootpage) FROM sqlite_schema").fetchone()
    conn.close()
    start = (last_root if past_roots else 2) * page
    size = Path(path).stat().st_size
    assert size > start + 4 * page, "too few pages to damage"
    with open(path, "r+b") as f:
        f.seek(start)
        f.write(b"\xff" * (size - start))


@pytest.fixture
def damaged_cache(tmp_path: Path) -> Path:
    """A store whose cache file keeps many entries of run r1, their pages then damaged."""
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i) for i in range(20)])
        chain = derived.current_chain(store, "r1")
        assert derived.save(store, "r1", KIND, VERSION, chain, {f"case {i}": "x" * 2000 for i in range(300)})
        cache = store.cache.path
    _damage(cache)
    return path


def test_reading_a_runs_kept_entries_from_a_damaged_cache_is_storedamaged(damaged_cache):
    with Store(damaged_cache) as store:
        with pytest.raises(StoreDamaged, match="malformed") as raised:
            derived.load(store, "r1", KIND, VERSION, derived.current_chain(store, "r1"))
    assert isinstance(raised.value.__cause__, sqlite3.DatabaseError)


def test_an_entry_read_by_its_key_later_from_a_damaged_cache_is_storedamaged(damaged_cache):
    with Store(damaged_cache) as store:
        kept = derived.load(store, "r1", KIND, VERSION, derived.current_chain(store, "r1"), by_key=True)
        with pytest.raises(StoreDamaged, match="malformed"):
            kept.get("case 150")        # the read happens here, long after load returned


def test_verifys_look_at_a_damaged_caches_entries_is_storedamaged(damaged_cache):
    with Store(damaged_cache) as store:
        with pytest.raises(StoreDamaged, match="malformed"):
            derived.tampered_derived(store, "r1")


def test_a_timeline_over_a_damaged_store_is_storedamaged(tmp_path: Path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        report = store.append([event(i) for i in range(2000)])
        assert report.stored == 2000
    _damage(path, past_roots=False)
    with Store.open_read_only(path) as store:
        timeline = Timeline(store, "r1")
        with pytest.raises(StoreDamaged, match="malformed"):
            for i in range(0, 2000, 50):
                timeline.at(event(i)["t"])


def test_a_kept_recording_in_a_damaged_or_unwritable_cache_is_gone_without(tmp_path: Path):
    """kept_recording's own SQL already went without on every SQLite error (it is wrapped for the
    errors a later change might let through): a damaged file is not kept, nothing raises."""
    recording = tmp_path / "rec.jsonl"
    recording.write_text("")
    digest = kept_recording.recording_digest(recording)
    at = kept_recording.cache_file(digest)
    assert at is not None
    Path(at).parent.mkdir(parents=True, exist_ok=True)
    Path(at).write_bytes(b"not a database" * 1000)
    assert kept_recording.open_kept(digest, VERSION) is None
