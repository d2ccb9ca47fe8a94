"""The producer's one cache (sim_replay/recent_events.py, answered by sim_replay/cache_queryable.py):
bounded by count, bytes and age; answers by source and seq range within the slice asked; out of
reach of gaps/** queries; and what the ingest gets from it, after a restart (a despawned source
included) and for a hole in the live stream."""
from __future__ import annotations

from pathlib import Path

import pytest
import zenoh

from ingest import IngestService
from sim_replay.publisher import EventPublisher, zenoh_config
from sim_replay.recent_events import RecentEvents
from store import Store, canonical_json
from store.wire import cache_query_options, index_selector, key_for, read_index, want_payload, want_selector
from tests.helpers.ingest_testkit import RUN, await_match, free_endpoint, make_event

WAIT_S = 15.0


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


def _add(ring: RecentEvents, src: str, seq: int, size: int = 10) -> None:
    ring.add(RUN, src, seq, f"gaps/{RUN}/{src}/entity.state", b"x" * size)


def test_the_ring_keeps_at_most_its_count_dropping_the_oldest() -> None:
    ring = RecentEvents(10, max_events=3)
    for seq in range(5):
        _add(ring, "vehicle/1", seq)
    assert len(ring) == 3 and [s.first for s in ring.index()] == [2]
    assert [p for _, p in ring.between(RUN, "vehicle/1", 0, 9)] == [b"x" * 10] * 3


def test_the_ring_keeps_at_most_its_bytes() -> None:
    ring = RecentEvents(10, max_bytes=250)
    for seq in range(5):
        _add(ring, "vehicle/1", seq, size=100)
    assert len(ring) == 2 and ring.nbytes == 200
    assert ring.index()[0].first == 3


def test_a_run_of_puts_is_dropped_from_its_oldest_event_by_count_and_bytes_and_whole_by_age() -> None:
    clock = Clock()
    ring = RecentEvents(10, max_events=7, max_bytes=1_000, clock=clock)
    key = f"gaps/{RUN}/vehicle/1/entity.state"
    ring.add_all([(RUN, "vehicle/1", seq, key, b"x" * 10) for seq in range(5)])
    clock.now += 6
    ring.add_all([(RUN, "vehicle/1", seq, key, b"x" * 10) for seq in range(5, 9)])   # 9 held: two too many
    assert len(ring) == 7 and ring.nbytes == 70 and ring.index()[0].first == 2
    ring.add_all([(RUN, "vehicle/1", 9, key, b"x" * 900)])       # 970 bytes: within; the count drops seq 2
    assert ring.nbytes == 960 and ring.index()[0].first == 3
    ring.add_all([(RUN, "vehicle/1", 10, key, b"x" * 30)])       # 990 bytes, 8 events: seq 3 goes
    assert (len(ring), ring.nbytes, ring.index()[0].first) == (7, 980, 4)
    clock.now += 5                      # the first run of puts is 11 s old, the rest 5 s
    ring.add_all([(RUN, "vehicle/1", 11, key, b"x")])
    assert [(s.first, s.last) for s in ring.index()] == [(5, 11)] and ring.nbytes == 40 + 900 + 30 + 1


def test_the_ring_forgets_what_is_older_than_its_age() -> None:
    clock = Clock()
    ring = RecentEvents(10, clock=clock)
    _add(ring, "vehicle/1", 0)
    _add(ring, "vehicle/2", 0)
    clock.now += 6
    _add(ring, "vehicle/1", 1)
    clock.now += 5                      # the first two are 11 s old, the third 5 s
    assert [(s.src, s.first, s.last) for s in ring.index()] == [("vehicle/1", 1, 1)]
    assert ring.between(RUN, "vehicle/2", 0, 9) == [] and len(ring) == 1


def test_the_ring_answers_by_source_seq_range_and_key() -> None:
    ring = RecentEvents(10)
    for seq in range(6):
        _add(ring, "vehicle/1", seq)
        _add(ring, "vehicle/2", seq)
    ring.add(RUN, "vehicle/1", 6, f"gaps/{RUN}/vehicle/1/vehicle.perception", b"p")
    assert len(ring.between(RUN, "vehicle/1", 2, 4)) == 3
    assert ring.between(RUN, "vehicle/1", 2, 6, lambda key: key.endswith("perception")) == [
        (f"gaps/{RUN}/vehicle/1/vehicle.perception", b"p")]
    assert {(s.src, s.first, s.last) for s in ring.index()} == {("vehicle/1", 0, 6), ("vehicle/2", 0, 5)}
    with pytest.raises(ValueError, match="max_events"):
        RecentEvents(10, max_events=0)


@pytest.fixture
def producer() -> EventPublisher:
    publisher = EventPublisher(config=zenoh_config(listen=[endpoint := free_endpoint()]))
    publisher.endpoint = endpoint
    yield publisher
    publisher.close()


def _ask(endpoint: str, selector: str, payload: bytes | None = None) -> list[zenoh.Reply]:
    with zenoh.open(zenoh_config(connect=[endpoint])) as session:
        # declarations reach a new session one by one: ask once the cache's token is here
        tokens = session.liveliness().get("gaps/@cache/*", timeout=5)
        assert [r.ok for r in tokens if r.ok is not None]
        return list(session.get(selector, payload=payload, **cache_query_options(timeout=5)))


def test_the_cache_answers_by_source_and_seq_range_within_the_slice(producer: EventPublisher) -> None:
    events = [make_event(f"vehicle/{v}", seq, "entity.state") for seq in range(6) for v in (1, 2)]
    producer.publish_all(events)
    index = _ask(producer.endpoint, index_selector(producer.cache_id, "gaps/**"))
    assert {(s.src, s.first, s.last) for s in read_index(index[0].ok.payload.to_bytes())} == {
        ("vehicle/1", 0, 5), ("vehicle/2", 0, 5)}
    got = _ask(producer.endpoint, want_selector("gaps/**"), want_payload([(RUN, "vehicle/1", 2, 4)]))
    assert [(str(r.ok.key_expr), r.ok.payload.to_bytes()) for r in got] == [
        (key_for(e), canonical_json(e)) for e in events if e["src"] == "vehicle/1" and 2 <= e["seq"] <= 4]
    assert _ask(producer.endpoint, want_selector("gaps/other-run/**"), want_payload([(RUN, "vehicle/1", 0, 9)])) == []
    refused = _ask(producer.endpoint, want_selector("gaps/**"), b"not json")
    assert "neither ?_index nor a payload" in refused[0].err.payload.to_string()


def test_gaps_queries_do_not_reach_the_cache(producer: EventPublisher) -> None:
    producer.publish(make_event("vehicle/1", 0, "entity.state"))
    with zenoh.open(zenoh_config(connect=[producer.endpoint])) as session:
        assert [r for r in session.liveliness().get("gaps/@cache/*", timeout=5) if r.ok is not None]
        assert list(session.get("gaps/**", **cache_query_options(timeout=2))) == []
        assert [r for r in session.liveliness().get("gaps/**", timeout=2) if r.ok is not None] == []


def _despawn(src: str, seq: int) -> dict:
    return {**make_event(src, seq, "entity.state"), "kind": "entity.despawn", "body": {"reason": "left the map"}}


def test_a_restarted_ingest_gets_a_despawned_source_from_the_cache(db_path: Path) -> None:
    endpoint = free_endpoint()
    with EventPublisher(config=zenoh_config(listen=[endpoint])) as publisher:
        with IngestService(db_path, connect=[endpoint]) as first:
            await_match(publisher, make_event("vehicle/1", 0))
            publisher.publish_all([make_event("vehicle/1", seq, "entity.state") for seq in range(3)])
            assert first.wait_until_stored(3, WAIT_S), first.stats()
        # while no ingest runs: vehicle/1 goes on, vehicle/5 comes and goes (its token gone with it)
        publisher.publish_all([make_event("vehicle/1", seq, "entity.state") for seq in range(3, 6)])
        publisher.publish_all([make_event("vehicle/5", 0, "entity.state"), _despawn("vehicle/5", 1)])
        with IngestService(db_path, connect=[endpoint]) as second:
            assert second.wait_until_stored(5, WAIT_S), second.stats()
            assert second.stats()["recovered"] == 5 and second.stats()["duplicates"] == 0
    with Store.open_read_only(db_path) as store:
        assert sorted((e["src"], e["seq"]) for e in store.events(RUN)) == [
            *(("vehicle/1", s) for s in range(6)), ("vehicle/5", 0), ("vehicle/5", 1)]
        assert store.gaps() == [] and store.verify(RUN).ok


def test_a_hole_in_the_live_stream_is_filled_from_the_cache(db_path: Path) -> None:
    endpoint = free_endpoint()
    events = [make_event("vehicle/3", seq, "entity.state") for seq in range(8)]
    with IngestService(db_path, listen=[endpoint]) as ingest:
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
            await_match(publisher, events[0])
            publisher.publish_all(events[:3])
            assert ingest.wait_until_stored(3, WAIT_S), ingest.stats()
            for event in events[3:6]:       # lost on the wire: in the cache, never put
                publisher.cache.add(RUN, "vehicle/3", event["seq"], key_for(event), canonical_json(event))
            publisher.publish_all(events[6:])
            assert ingest.wait_until_stored(8, WAIT_S), ingest.stats()
            assert ingest.stats()["recovered"] == 3 and ingest.gaps() == []
    with Store.open_read_only(db_path) as store:
        assert store.gaps() == [] and store.verify(RUN).ok
        assert sorted(e["seq"] for e in store.events(RUN)) == list(range(8))


def test_a_hole_no_cache_holds_stays_a_listed_gap(db_path: Path) -> None:
    endpoint = free_endpoint()
    with IngestService(db_path, listen=[endpoint]) as ingest:
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
            await_match(publisher, make_event("vehicle/4", 0))
            publisher.publish_all([make_event("vehicle/4", 0, "entity.state"), make_event("vehicle/4", 4, "entity.state")])
        # its close waited for the ingest to have asked the cache for 1-3 and taken the (empty) answer
        assert ingest.wait_until_stored(2, WAIT_S), ingest.stats()
        assert ingest.stats()["recovered"] == 0 and ingest.gaps()[0]["missing"] == [[1, 3]]
    with Store.open_read_only(db_path) as store:
        assert store.gaps() == [{"run": RUN, "src": "vehicle/4", "missing": [[1, 3]], "highest": 4}]
