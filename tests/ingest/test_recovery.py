"""An ingest that was down fetches what it missed from the producers' caches (store.CACHE_S of
everything each published); what the caches no longer held is a gap the store lists, with its
source and seqs; and a publisher and an ingest may start in either order."""
from __future__ import annotations

from pathlib import Path

from ingest import IngestService
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store
from tests.helpers.ingest_testkit import RUN, free_endpoint, make_event

SRC = "vehicle/7"
WAIT_S = 15.0


def _events(first: int, last: int) -> list[dict]:
    return [make_event(SRC, seq, "entity.state") for seq in range(first, last + 1)]


def _down_and_up(db: Path, *, cache_events: int, expect: int) -> IngestService:
    """Publish 0-99 to an ingest, stop it, publish 100-199 while none runs, start a new ingest on the
    same store (it finds the cache and asks it for what it holds above seq 99), publish 200 once the
    cache has answered and, once the new ingest has stored ``expect`` events, 201-209; close once it
    has them too (a publisher that goes away takes its cache with it)."""
    endpoint = free_endpoint()
    with EventPublisher(config=zenoh_config(listen=[endpoint]), cache_events=cache_events) as publisher:
        with IngestService(db, connect=[endpoint]) as first:
            assert publisher.wait_until_matched(_events(0, 0)[0], WAIT_S)
            publisher.publish_all(_events(0, 99))
            assert first.wait_until_stored(100, WAIT_S), first.stats()
        publisher.publish_all(_events(100, 199))          # nobody listens: only the cache keeps them
        second = IngestService(db, connect=[endpoint])
        assert publisher.wait_until_matched(_events(0, 0)[0], WAIT_S)
        assert second.wait_for(lambda s: s["recovered"] >= min(100, cache_events), WAIT_S), second.stats()
        publisher.publish_all(_events(200, 200))
        assert second.wait_until_stored(expect, WAIT_S), second.stats()
        publisher.publish_all(_events(201, 209))
        assert second.wait_until_stored(expect + 9, WAIT_S), second.stats()
    return second


def test_an_ingest_restarted_within_the_cache_time_gets_everything(db_path: Path) -> None:
    second = _down_and_up(db_path, cache_events=1000, expect=101)   # all of 0-199 held
    assert (second.stats()["recovered"], second.stats()["duplicates"]) == (100, 0)   # only what it lacked: 100-199
    second.stop()
    with Store.open_read_only(db_path) as store:
        assert [e["seq"] for e in store.events(RUN)] == list(range(210))
        assert store.gaps() == [] and store.verify(RUN).ok
        assert [e for e in store.events(RUN)] == _events(0, 209)


def test_an_ingest_down_longer_than_the_cache_lists_the_gap(db_path: Path) -> None:
    second = _down_and_up(db_path, cache_events=5, expect=6)     # the cache holds the last 5: 195-199
    second.stop()
    with Store.open_read_only(db_path) as store:
        stored = [e["seq"] for e in store.events(RUN)]
        assert stored == [*range(100), *range(195, 210)]
        assert store.gaps() == [{"run": RUN, "src": SRC, "missing": [[100, 194]], "highest": 209}]
        assert store.verify(RUN).ok


def test_a_publisher_that_starts_first_is_heard_by_a_later_ingest(db_path: Path) -> None:
    endpoint = free_endpoint()
    with EventPublisher(config=zenoh_config(listen=[endpoint])) as publisher:
        publisher.publish_all(_events(0, 29))                 # no ingest yet, and no waiting for one
        with IngestService(db_path, connect=[endpoint]) as ingest:
            assert ingest.wait_until_stored(30, WAIT_S), ingest.stats()
            publisher.publish_all(_events(30, 39))
            assert ingest.wait_until_stored(40, WAIT_S), ingest.stats()
    with Store.open_read_only(db_path) as store:
        assert [e["seq"] for e in store.events(RUN)] == list(range(40)) and store.verify(RUN).ok


def test_an_ingest_that_starts_first_misses_nothing_of_a_publisher_that_does_not_wait(db_path: Path) -> None:
    endpoint = free_endpoint()
    with IngestService(db_path, listen=[endpoint]) as ingest:
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
            publisher.publish_all(_events(0, 39))            # at once, before the ingest is known here
        assert ingest.wait_until_stored(40, WAIT_S), ingest.stats()
        assert ingest.stats()["stored"] == 40
    with Store.open_read_only(db_path) as store:
        assert store.gaps() == [] and store.count(RUN) == 40
