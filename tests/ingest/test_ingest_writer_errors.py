"""A failing store costs retries and, at worst, the samples it cannot take: never the writer thread.

A failure of the store's condition (locked, full, I/O error) is waited out with the batch held
(tests/ingest/test_back_pressure.py). A failure on a sample of its own (SQLite's "too big") is retried,
then the sample is quarantined with the error if the store still takes that; only if it takes not even
that are samples counted as failed.

The failures are injected at Store.append_candidates (real Zenoh, real SQLite otherwise): the one real
SQLite failure that is easy to cause here, a held write lock, only fails after the store's 5 s busy timeout.
"""
from __future__ import annotations

import sqlite3
from collections.abc import Callable, Iterable
from pathlib import Path

import pytest

import ingest.screen
import ingest.writer
from ingest import IngestService
from tests.helpers.ingest_testkit import RUN, await_match, make_event
from sim_replay.publisher import EventPublisher
from store import AppendReport, Candidate, Store, canonical_json


LOCKED = sqlite3.OperationalError("database is locked (injected)")
TOO_BIG = sqlite3.DataError("string or blob too big (injected)")


def failing_when(monkeypatch: pytest.MonkeyPatch, should_fail: Callable[[list], bool],
                 error: Exception = TOO_BIG) -> None:
    """Make the writer's store call raise ``error`` whenever ``should_fail(candidates)``."""
    real = Store.append_candidates

    def append(store: Store, candidates: Iterable[Candidate]) -> AppendReport:
        candidates = list(candidates)
        if should_fail(candidates):
            raise error
        return real(store, candidates)

    monkeypatch.setattr(Store, "append_candidates", append)
    monkeypatch.setattr(ingest.writer, "RETRY_PAUSE_S", 0.01)


def test_transient_failure_is_retried(
    monkeypatch: pytest.MonkeyPatch, link: tuple[EventPublisher, IngestService], db_path: Path
) -> None:
    calls = []
    failing_when(monkeypatch, lambda candidates: calls.append(1) or len(calls) == 1, LOCKED)
    publisher, ingest = link
    events = [make_event("vehicle/173", seq) for seq in range(20)]
    await_match(publisher, events[0])
    publisher.publish_all(events)
    assert ingest.wait_until_stored(20, timeout=10), ingest.stats()
    stats = ingest.stats()
    assert (stats["errors"], stats["write_failures"], stats["failed"], stats["rejected"]) == (1, 1, 0, 0)
    assert "database is locked" in stats["last_errors"][0] and stats["stall"] is None


def test_poison_sample_costs_only_itself(
    monkeypatch: pytest.MonkeyPatch, link: tuple[EventPublisher, IngestService], db_path: Path
) -> None:
    failing_when(monkeypatch, lambda candidates: any(c.event and c.event["seq"] == 3 for c in candidates))
    publisher, ingest = link
    events = [make_event("vehicle/173", seq) for seq in range(20)]
    await_match(publisher, events[0])
    publisher.publish_all(events)
    assert ingest.wait_until_settled(20, timeout=10), ingest.stats()
    stats = ingest.stats()
    assert (stats["stored"], stats["rejected"], stats["failed"]) == (19, 1, 0)
    publisher.publish(make_event("vehicle/173", 20))  # and the writer is still alive
    assert ingest.wait_until_stored(20, timeout=10)
    ingest.stop()
    with Store(db_path) as store:
        assert [ev["seq"] for ev in store.events(RUN)] == [s for s in range(21) if s != 3]
        [kept] = store.quarantined()
    assert kept["raw"] == canonical_json(events[3]) and "too big" in kept["reason"]


def test_a_store_that_takes_not_even_quarantine_loses_counted_samples_and_the_writer_lives_on(
    monkeypatch: pytest.MonkeyPatch, link: tuple[EventPublisher, IngestService]
) -> None:
    broken = [True]
    failing_when(monkeypatch, lambda candidates: broken[0])
    publisher, ingest = link
    events = [make_event("vehicle/173", seq) for seq in range(3)]
    await_match(publisher, events[0])
    publisher.publish_all(events)
    assert ingest.wait_until_settled(3, timeout=10), ingest.stats()
    stats = ingest.stats()
    assert (stats["stored"], stats["failed"]) == (0, 3)
    assert stats["errors"] >= 2 and all("too big" in e for e in stats["last_errors"])
    broken[0] = False  # the store recovers
    publisher.publish(make_event("vehicle/173", 3))
    assert ingest.wait_until_stored(1, timeout=10), ingest.stats()


def test_a_sample_that_breaks_screening_is_quarantined_and_costs_only_itself(
    monkeypatch: pytest.MonkeyPatch, link: tuple[EventPublisher, IngestService], db_path: Path
) -> None:
    events = [make_event("vehicle/173", seq) for seq in range(20)]
    poison = canonical_json(events[3])
    real = ingest.screen.plain_event

    def plain_event(raw: bytes):
        if raw == poison:
            raise RuntimeError("a screening bug (injected)")
        return real(raw)

    monkeypatch.setattr(ingest.screen, "plain_event", plain_event)
    publisher, ingest_service = link
    await_match(publisher, events[0])
    publisher.publish_all(events)
    assert ingest_service.wait_until_settled(20, timeout=10), ingest_service.stats()
    stats = ingest_service.stats()
    assert (stats["stored"], stats["rejected"], stats["failed"], stats["errors"]) == (19, 1, 0, 1)
    assert "screening: RuntimeError" in stats["last_errors"][0]
    ingest_service.stop()
    with Store(db_path) as store:
        assert [ev["seq"] for ev in store.events(RUN)] == [s for s in range(20) if s != 3]
        [kept] = store.quarantined()
    assert kept["raw"] == poison and "ingest could not screen this sample" in kept["reason"]
