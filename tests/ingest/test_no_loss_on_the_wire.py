"""Two ways Zenoh itself lost published events, found when the simulation published 840,000 events
into an ingest that fell behind, and what keeps them now (a slow disk stands for that ingest):

- a put that waited for room longer than Zenoh's 5 s default closed the link, and the puts after it
  vanished without an error (store.BLOCK_FOR_US, in the wire contract store/wire.py);
- a session closed while samples were still queued dropped them (EventPublisher.close asks the
  ingests to confirm first, store.SYNC_KEY).

Both are checked the way a producer would see them: everything published is in the store."""
from __future__ import annotations

import time
from pathlib import Path

import pytest
import zenoh

from ingest import IngestService
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store
from store.wire import SYNC_KEY
from tests.helpers.ingest_testkit import RUN, await_match, free_endpoint, make_event


@pytest.fixture
def slow_disk(monkeypatch: pytest.MonkeyPatch):
    """Every commit of the ingest's store takes `delay[0]` seconds longer (the first one may be made
    much slower, to stand for a stall)."""
    delay = [0.0]
    real = Store.append_candidates

    def slowed(self, *args, **kwargs):
        time.sleep(delay.pop(0) if len(delay) > 1 else delay[0])
        return real(self, *args, **kwargs)

    monkeypatch.setattr(Store, "append_candidates", slowed)
    return delay


def _publish(events: list[dict], db: Path, **ingest_options) -> tuple[int, int | None, dict]:
    endpoint = free_endpoint()
    with IngestService(db, listen=[endpoint], durable=False, **ingest_options) as ingest:
        publisher = EventPublisher(config=zenoh_config(connect=[endpoint]))
        await_match(publisher, events[0])
        publisher.publish_all(events)
        publisher.close()            # at once, with whatever is still on its way
        ingest.wait_until_settled(len(events), 30)
        stats = ingest.stats()
    with Store(db) as store:
        return store.count(RUN), publisher.confirmed_by, stats


def _events(n: int) -> list[dict]:
    return [make_event("vehicle/173", seq, "entity.state") for seq in range(n)]


def test_closing_right_after_the_last_put_loses_nothing(tmp_path: Path, slow_disk: list[float]) -> None:
    slow_disk[0] = 0.02
    events = _events(20_000)
    stored, confirmed_by, stats = _publish(events, tmp_path / "a.db", batch_size=200, max_pending=200)
    assert stored == len(events), stats
    assert confirmed_by == 1


def test_an_ingest_that_stalls_longer_than_zenohs_default_wait_loses_nothing(tmp_path: Path,
                                                                            slow_disk: list[float]) -> None:
    slow_disk[:] = [0.0, 0.0, 6.5, 0.0]        # the third commit takes 6.5 s: longer than Zenoh's 5 s
    events = _events(30_000)
    stored, _, stats = _publish(events, tmp_path / "b.db", batch_size=500, max_pending=500)
    assert stored == len(events), stats


def test_close_does_not_wait_where_no_ingest_answers() -> None:
    endpoint = free_endpoint()
    with zenoh.open(zenoh_config(listen=[endpoint])) as session:
        session.declare_subscriber("gaps/**", lambda sample: None)     # a foreign subscriber
        publisher = EventPublisher(config=zenoh_config(connect=[endpoint]))
        await_match(publisher, make_event("vehicle/1", 0))
        publisher.publish(make_event("vehicle/1", 0))
        started = time.monotonic()
        publisher.close()
        assert time.monotonic() - started < 5.0
        assert publisher.confirmed_by == 0


def test_close_waits_for_an_ingests_sync_queryable_that_is_still_on_its_way() -> None:
    """An ingest declares its subscriber, then its sync queryable: a publisher that has just matched
    the subscriber and closes at once must still be confirmed (a fresh-clone test run once closed
    before the queryable's declaration had arrived, and was told nobody confirmed)."""
    endpoint = free_endpoint()
    with zenoh.open(zenoh_config(listen=[endpoint])) as session:
        session.declare_subscriber("gaps/**", lambda sample: None)
        publisher = EventPublisher(config=zenoh_config(connect=[endpoint]))
        await_match(publisher, make_event("vehicle/1", 0))
        publisher.publish(make_event("vehicle/1", 0))
        time.sleep(0.05)
        session.declare_queryable(SYNC_KEY, lambda query: query.reply(SYNC_KEY, b"ok"))   # late, as it can be
        publisher.close()
        assert publisher.confirmed_by == 1
