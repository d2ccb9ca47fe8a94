"""A despawned source's publishers are undeclared, and nothing it published is lost by that."""
from __future__ import annotations

from ingest import IngestService
from sim_replay.publisher import EventPublisher
from tests.helpers.ingest_testkit import RUN, T0, await_match, make_event


def _despawn(src: str, seq: int, run: str = RUN) -> dict:
    return {"v": 1, "run": run, "src": src, "seq": seq, "t": T0 + seq * 100_000_000, "kind": "entity.despawn",
            "body": {"reason": "left the map"}}


def _sources(publisher: EventPublisher) -> set[str]:
    return {key.rsplit("/", 1)[0] for key in publisher.keys}


def test_a_despawn_releases_its_sources_publishers_and_loses_nothing(link: tuple[EventPublisher, IngestService]) -> None:
    publisher, ingest = link
    first = make_event("vehicle/9", 0, "entity.state")
    await_match(publisher, first)
    events = [first, make_event("vehicle/9", 1), make_event("vehicle/10", 0, "entity.state"), _despawn("vehicle/9", 2)]
    publisher.publish_all(events)
    assert _sources(publisher) == {f"gaps/{RUN}/vehicle/10"}
    publisher.publish(make_event("vehicle/9", 3, "entity.state"))       # it speaks again: declared anew
    assert f"gaps/{RUN}/vehicle/9" in _sources(publisher)
    assert ingest.wait_until_stored(5, timeout=10), ingest.stats()
    assert ingest.stats()["stored"] == 5 and ingest.gaps() == []


def test_a_despawn_among_written_events_with_their_keys_releases_its_sources_publishers(
        link: tuple[EventPublisher, IngestService]) -> None:
    """The simulation's road (publish_all with each event's bytes and key, as a Tick carries
    them): the same runs as without, a despawn's source released, every event stored."""
    from store import canonical_json
    from store.wire import key_for
    publisher, ingest = link
    first = make_event("vehicle/9", 0, "entity.state")
    await_match(publisher, first)
    events = [first, make_event("vehicle/9", 1), make_event("vehicle/10", 0, "entity.state"), _despawn("vehicle/9", 2)]
    assert publisher.publish_all(events, [canonical_json(e) for e in events], [key_for(e) for e in events]) == 4
    assert _sources(publisher) == {f"gaps/{RUN}/vehicle/10"}
    assert ingest.wait_until_stored(4, timeout=10), ingest.stats()
    assert ingest.stats()["stored"] == 4 and ingest.gaps() == [] and len(publisher.cache) == 4


def test_a_despawn_in_one_run_keeps_the_same_source_of_another(link: tuple[EventPublisher, IngestService]) -> None:
    publisher, ingest = link
    other = make_event("vehicle/9", 0, "entity.state", run="other-run")
    await_match(publisher, other)
    publisher.publish_all([other, make_event("vehicle/9", 0, "entity.state"), _despawn("vehicle/9", 1)])
    assert _sources(publisher) == {"gaps/other-run/vehicle/9"}
    assert ingest.wait_until_stored(3, timeout=10), ingest.stats()


def test_close_still_waits_for_confirmation_when_every_publisher_was_released(
        link: tuple[EventPublisher, IngestService]) -> None:
    publisher, ingest = link
    event = make_event("vehicle/9", 0, "entity.state")
    await_match(publisher, event)
    publisher.publish_all([event, _despawn("vehicle/9", 1)])
    assert publisher.keys == ()
    publisher.close()
    assert publisher.confirmed_by == 1                 # the ingest has both (it stores them in its own time)
    assert ingest.wait_until_stored(2, timeout=10), ingest.stats()
