"""Duplicates are counted, not stored twice; skipped sequence numbers show up as gaps."""
from __future__ import annotations

from pathlib import Path

from tests.helpers.ingest_testkit import RUN, await_match, make_event
from ingest import IngestService
from sim_replay.publisher import EventPublisher
from store import Store


def test_duplicates_are_counted(link: tuple[EventPublisher, IngestService], db_path: Path) -> None:
    publisher, ingest = link
    events = [make_event("vehicle/173", seq) for seq in range(50)]
    await_match(publisher, events[0])
    publisher.publish_all(events)
    publisher.publish_all(events)  # a replay sent twice
    publisher.publish(make_event("vehicle/173", 7, facts=["173 has green light"]))  # same identity, other content
    assert ingest.wait_until_settled(101, timeout=10), ingest.stats()
    stats = ingest.stats()
    assert (stats["stored"], stats["duplicates"], stats["rejected"]) == (50, 50, 1)
    assert stats["late"] == 0 and ingest.gaps() == []
    ingest.stop()
    with Store(db_path) as store:
        assert store.count(RUN) == 50
        [refused] = store.quarantined()
    assert "conflicting" in refused["reason"]


def test_skipped_seq_is_a_gap_until_it_arrives(link: tuple[EventPublisher, IngestService]) -> None:
    publisher, ingest = link
    v173 = [make_event("vehicle/173", seq) for seq in [*range(10), *range(13, 25), 26]]
    s1 = [make_event("signal/s1", seq, "signal.state") for seq in range(3, 6)]  # seq 0-2 never sent
    await_match(publisher, v173[0])
    await_match(publisher, s1[0])
    publisher.publish_all(v173 + s1)
    assert ingest.wait_until_stored(len(v173) + len(s1), timeout=10), ingest.stats()
    assert ingest.gaps() == [
        {"run": RUN, "src": "signal/s1", "missing": [[0, 2]], "highest": 5},
        {"run": RUN, "src": "vehicle/173", "missing": [[10, 12], [25, 25]], "highest": 26},
    ]
    publisher.publish(make_event("vehicle/173", 11))  # a late arrival fills part of a gap
    publisher.publish(make_event("vehicle/173", 25))
    assert ingest.wait_until_stored(len(v173) + len(s1) + 2, timeout=10)
    assert ingest.gaps()[1]["missing"] == [[10, 10], [12, 12]]
    assert ingest.stats()["late"] == 2
