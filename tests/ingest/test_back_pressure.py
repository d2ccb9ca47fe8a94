"""A store that cannot write holds the ingest back; it never costs what was accepted (issue 15, finding 7).

On a full disk the ingest used to count whole batches "failed" and drop them (14,810 of 17,814
events). Now the writer keeps the batch and waits; Zenoh's channel fills, publishers block (BLOCK),
and when the disk has room again every event published meanwhile is stored.

The full disk is SQLite's own: ``PRAGMA max_page_count`` at the file's page count makes every insert
that needs a page fail with SQLITE_FULL, as a full file system does, and raising it is the room coming
back. An I/O error is injected at Store.append_candidates (SQLite gives no way to cause one without root).
"""
from __future__ import annotations

import sqlite3
import threading
from collections.abc import Iterable, Iterator
from pathlib import Path

import pytest

import ingest.writer
from ingest import IngestService
from ingest.serve_status import StatusMeter
from sim_replay.publisher import EventPublisher
from store import AppendReport, Candidate, Store
from tests.helpers.ingest_testkit import RUN, await_match, linked, make_event

EVENTS = 6_000
PADDING = "x" * 1000  # about a kilobyte an event: the channel and the link's buffers fill soon


class Disk:
    """A disk the test fills and frees, as seen by the writer's own connection (its thread)."""

    def __init__(self) -> None:
        self.full = threading.Event()
        self.freed = threading.Event()

    def store_class(self) -> type[Store]:
        disk = self

        class OnDisk(Store):
            def append_candidates(self, candidates: Iterable[Candidate]) -> AppendReport:
                pages = self.connection.execute("PRAGMA page_count").fetchone()[0]
                if disk.freed.is_set():
                    self.connection.execute("PRAGMA max_page_count = 1073741823")
                elif disk.full.is_set():
                    self.connection.execute(f"PRAGMA max_page_count = {pages}")
                return super().append_candidates(candidates)

        return OnDisk


@pytest.fixture
def disk(monkeypatch: pytest.MonkeyPatch) -> Disk:
    disk = Disk()
    monkeypatch.setattr(ingest.writer, "Store", disk.store_class())
    return disk


@pytest.fixture
def small_link(db_path: Path) -> Iterator[tuple[EventPublisher, IngestService]]:
    """An ingest whose channel holds little, so that a stalled writer pushes back at once."""
    with linked(db_path, "pub-listens", batch_size=50, max_pending=100) as pair:
        yield pair


def publish_in_background(publisher: EventPublisher, events: list[dict]) -> threading.Thread:
    thread = threading.Thread(target=publisher.publish_all, args=(events,), daemon=True)
    thread.start()
    return thread


def stored_seqs(db_path: Path) -> list[int]:
    with Store.open_read_only(db_path) as store:
        assert store.verify().ok
        return [ev["seq"] for ev in store.events(RUN)]


def test_a_full_disk_holds_publishers_back_and_loses_nothing(
    disk: Disk, small_link: tuple[EventPublisher, IngestService], db_path: Path
) -> None:
    publisher, service = small_link
    events = [make_event("vehicle/173", seq, note=PADDING) for seq in range(EVENTS)]
    await_match(publisher, events[0])
    disk.full.set()
    sending = publish_in_background(publisher, events)
    assert service.wait_for(lambda s: s["stall"] is not None, timeout=10), service.stats()
    sending.join(1.0)
    assert sending.is_alive(), "the publisher should be held back while the disk is full"
    status = StatusMeter(service).read()
    assert status.stall == "the disk is full" and "STALLED" in status.line()
    held = service.stats()
    assert held["failed"] == 0 and held["stored"] < EVENTS and held["write_failures"] >= 1

    disk.freed.set()
    sending.join(30)
    assert not sending.is_alive()
    assert service.wait_until_stored(EVENTS, timeout=30), service.stats()
    stats = service.stats()
    assert stats["failed"] == 0 and stats["stall"] is None and stats["stalled_s"] > 0.5
    service.stop()
    assert stored_seqs(db_path) == list(range(EVENTS))


def test_an_io_error_is_waited_out(monkeypatch: pytest.MonkeyPatch,
                                   small_link: tuple[EventPublisher, IngestService], db_path: Path) -> None:
    broken = threading.Event()
    real = Store.append_candidates

    def append(store: Store, candidates: Iterable[Candidate]) -> AppendReport:
        if broken.is_set():
            error = sqlite3.OperationalError("disk I/O error")
            error.sqlite_errorcode = 10 | (3 << 8)  # SQLITE_IOERR_WRITE, as SQLite reports it
            raise error
        return real(store, candidates)

    monkeypatch.setattr(Store, "append_candidates", append)
    publisher, service = small_link
    events = [make_event("vehicle/9", seq, note=PADDING) for seq in range(EVENTS)]
    await_match(publisher, events[0])
    broken.set()
    sending = publish_in_background(publisher, events)
    assert service.wait_for(lambda s: s["write_failures"] >= 3, timeout=10), service.stats()
    assert service.stats()["stall"] == "disk I/O error"
    broken.clear()
    sending.join(30)
    assert service.wait_until_stored(EVENTS, timeout=30), service.stats()
    assert service.stats()["failed"] == 0
    service.stop()
    assert stored_seqs(db_path) == list(range(EVENTS))


def test_a_stop_during_a_stall_gives_up_after_the_grace_and_says_how_many(
    disk: Disk, monkeypatch: pytest.MonkeyPatch, db_path: Path
) -> None:
    monkeypatch.setattr(ingest.writer, "STOP_GRACE_S", 0.3)
    with linked(db_path, "pub-listens") as (publisher, service):
        events = [make_event("vehicle/5", seq, note=PADDING) for seq in range(200)]
        await_match(publisher, events[0])
        disk.full.set()
        publisher.publish_all(events)
        assert service.wait_for(lambda s: s["stall"] is not None, timeout=10), service.stats()
        service.stop()
        stats = service.stats()
    assert stats["failed"] > 0 and stats["stored"] + stats["failed"] == stats["received"]
    assert "the disk is full" in stats["stall"]  # still so when it gave up
