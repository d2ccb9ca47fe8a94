"""Valid events cross Zenoh into the store: none lost, per-source order kept, chain intact."""
from __future__ import annotations

import sqlite3
import threading
import time
from itertools import zip_longest
from pathlib import Path

import pytest

from tests.helpers.ingest_testkit import RUN, await_match, free_endpoint, linked, make_event
from ingest import IngestService
from store import Store
from store.errors import DiskFailed

SOURCES = {  # src -> the kinds it cycles through
    "vehicle/173": ("vehicle.perception", "vehicle.decision", "entity.state"),
    "vehicle/174": ("vehicle.perception", "entity.state"),
    "signal/s1": ("signal.state",),
    "monitor/m1": ("monitor.observation",),
}
PER_SOURCE = 500  # 2,000 events in all


def interleaved_events() -> list[dict]:
    """Round-robin over sources, as a simulation tick would publish them; seq rises per source."""
    streams = [
        [make_event(src, seq, kinds[seq % len(kinds)]) for seq in range(PER_SOURCE)]
        for src, kinds in SOURCES.items()
    ]
    return [ev for tick in zip_longest(*streams) for ev in tick if ev is not None]


def chain_order(db_path: Path) -> list[tuple[str, int]]:
    """(src, seq) in the order the store chained them, i.e. the order the ingest received them.

    Reads the store file's events table directly: Store.events() sorts by (t, seq), which would hide
    a reordering on the wire.
    """
    with sqlite3.connect(f"file:{db_path}?mode=ro", uri=True) as conn:
        return conn.execute("SELECT src, seq FROM events WHERE run = ? ORDER BY chain_pos", (RUN,)).fetchall()


@pytest.mark.parametrize("topology", ["pub-listens", "ingest-listens", "ingest-client"])
def test_every_event_arrives_in_order(db_path: Path, topology: str) -> None:
    events = interleaved_events()
    with linked(db_path, topology) as (publisher, ingest):
        for src in SOURCES:  # every source's first key, so no first event races the subscription
            await_match(publisher, make_event(src, 0, SOURCES[src][0]))
        publisher.publish_all(events)
        assert ingest.wait_until_stored(len(events), timeout=10), ingest.stats()
        stats, gaps = ingest.stats(), ingest.gaps()
    assert (stats["received"], stats["stored"], stats["duplicates"], stats["rejected"]) == (len(events), len(events), 0, 0)
    assert stats["late"] == stats["errors"] == stats["failed"] == 0
    assert gaps == []
    with Store(db_path) as store:
        assert store.count(RUN) == len(events)
        for src in SOURCES:
            assert [ev["seq"] for ev in store.events(RUN, srcs=[src])] == list(range(PER_SOURCE))
        assert store.verify().ok
        assert store.quarantined() == []
    order = chain_order(db_path)
    for src in SOURCES:
        assert [seq for s, seq in order if s == src] == list(range(PER_SOURCE))


def test_stop_flushes_what_was_received(db_path: Path) -> None:
    """A batch still waiting for its flush interval is written by stop(), not lost."""
    events = [make_event("vehicle/9", seq) for seq in range(10)]
    with linked(db_path, "pub-listens", batch_size=10_000, flush_interval_s=30.0) as (publisher, ingest):
        await_match(publisher, events[0])
        publisher.publish_all(events)
        time.sleep(0.5)  # let them arrive; the writer now waits 30 s for a fuller batch
        assert ingest.stats()["stored"] == 0
        started = time.monotonic()
        ingest.stop()
        assert time.monotonic() - started < 5
        assert ingest.stats()["stored"] == len(events)
    with Store(db_path) as store:
        assert store.count(RUN) == len(events)


def test_unusable_store_fails_at_start(tmp_path: Path) -> None:
    """A bad path is reported to the caller, not left in a dead thread; the session is closed again.
    It is the store's own error (a file that cannot be opened: check the path), not SQLite's."""
    with pytest.raises(DiskFailed, match="unable to open database file"):
        IngestService(tmp_path / "no-such-dir" / "gaps.db", listen=[free_endpoint()])


def test_stop_drains_samples_still_in_zenohs_channel(db_path: Path) -> None:
    """Samples queued in Zenoh's channel while the writer is stuck are still stored after stop().

    A second SQLite connection holds the write lock, so the writer blocks on its first batch while the
    rest wait in the channel; the lock is released only after stop() has closed the session.
    """
    events = [make_event("vehicle/5", seq) for seq in range(100)]
    with linked(db_path, "pub-listens") as (publisher, ingest):
        await_match(publisher, events[0])
        blocker = sqlite3.connect(db_path, isolation_level=None, check_same_thread=False)
        blocker.execute("BEGIN IMMEDIATE")
        publisher.publish(events[0])
        time.sleep(0.3)  # the writer has taken it and now waits for the lock
        publisher.publish_all(events[1:])
        time.sleep(0.3)  # these arrive and wait in the channel
        assert ingest.stats()["received"] == 1
        release = threading.Timer(0.5, lambda: (blocker.execute("ROLLBACK"), blocker.close()))
        release.start()
        ingest.stop()
        release.join()
        assert ingest.stats()["stored"] == len(events)
    with Store(db_path) as store:
        assert store.count(RUN) == len(events)
