"""The inbox renews its subscription when quiet, to free Zenoh's channel (which never shrinks), and
loses nothing by it: the new subscription is declared before the old one is emptied and undeclared,
so a sample in flight reaches one or both, and the store counts the second copy as the duplicate it
is (issue 40; ingest/inbox.py)."""
from __future__ import annotations

import threading
import time
from pathlib import Path

import pytest
import zenoh

from ingest import inbox as inbox_module
from ingest.idle_memory import QUIET_S
from ingest.inbox import Inbox
from sim_replay.publisher import zenoh_config
from store import Store
from tests.helpers.ingest_testkit import await_match, free_endpoint, linked, make_event
from tests.helpers.store_testkit import event

STREAM = 30_000


def test_a_renewal_in_the_middle_of_a_stream_loses_nothing_and_keeps_each_keys_order() -> None:
    endpoint = free_endpoint()
    ingest = zenoh.open(zenoh_config(listen=[endpoint]))
    producer = zenoh.open(zenoh_config(connect=[endpoint]))
    try:
        inbox = Inbox(ingest, "gaps/**", 100_000)
        time.sleep(1.0)                                       # the subscription reached the producer
        put = [(f"gaps/r/vehicle/{n % 7}/entity.state", str(n).encode()) for n in range(STREAM)]

        def stream() -> None:
            for key, payload in put:
                producer.put(key, payload, congestion_control=zenoh.CongestionControl.BLOCK)

        putting = threading.Thread(target=stream)
        putting.start()
        taken: list[tuple[str, bytes]] = []
        renewed = False
        deadline = time.monotonic() + 60
        while len(set(taken)) < STREAM and time.monotonic() < deadline:
            taken += [(key, payload) for key, payload, _, _ in inbox.take(2_000, 0.0, idle_s=0.5) or []]
            if not renewed and len(taken) >= inbox_module.RENEW_AFTER:
                old = inbox._subscriber
                assert inbox.renew() and inbox._subscriber is not old
                renewed = True
                assert putting.is_alive(), "the stream ended before the renewal: nothing was in flight"
        putting.join()
        assert renewed
        first_seen = list(dict.fromkeys(taken))
        assert sorted(first_seen) == sorted(put)               # every sample, once at least
        for src in range(7):                                   # each key's samples in the order put
            key = f"gaps/r/vehicle/{src}/entity.state"
            assert [p for k, p in first_seen if k == key] == [p for k, p in put if k == key]
        later = {}
        for n, item in enumerate(taken):                       # a second copy only right after the renewal
            later.setdefault(item, []).append(n)
        assert all(len(places) <= 2 for places in later.values())
    finally:
        producer.close()
        ingest.close()


def test_a_quiet_ingest_renews_and_the_copies_a_renewal_can_make_are_counted_duplicates(
        db_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(inbox_module, "RENEW_AFTER", 10)
    run = [event(0, run="r1", kind="run.start"), *(make_event(f"vehicle/{n % 3}", n // 3, "entity.state", run="r1")
                                                  for n in range(30)), event(1, run="r1", kind="run.end")]
    with linked(db_path, "pub-listens") as (publisher, ingest):
        subscription = ingest._writer._inbox._subscriber
        await_match(publisher, run[0])
        publisher.publish_all(run)
        assert ingest.wait_until_stored(len(run), timeout=20), ingest.stats()
        deadline = time.monotonic() + 10 * QUIET_S
        while ingest._writer._inbox._subscriber is subscription and time.monotonic() < deadline:
            time.sleep(0.05)
        assert ingest._writer._inbox._subscriber is not subscription, "no renewal once quiet"
        time.sleep(0.5)                                     # the old one emptied and undeclared
        publisher.publish_all(run)                          # the copies: a run already ended and let go
        after = [event(0, run="r2", kind="run.start"), make_event("vehicle/9", 0, "entity.state", run="r2")]
        publisher.publish_all(after)                        # the new subscription takes what comes next
        assert ingest.wait_until_settled(2 * len(run) + len(after), timeout=20), ingest.stats()
        stats = ingest.stats()
        assert (stats["stored"], stats["duplicates"], stats["rejected"], stats["failed"]) == (
            len(run) + len(after), len(run), 0, 0)
    with Store(db_path) as store:
        assert (store.count("r1"), store.count("r2")) == (len(run), len(after))
        assert store.quarantined() == []
        assert store.verify().ok


def test_what_arrives_while_a_renewal_is_under_way_reaches_both_and_is_stored_once(
        db_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(inbox_module, "RENEW_AFTER", 10)
    monkeypatch.setattr(inbox_module, "RENEW_GRACE_S", 1.0)   # both subscriptions declared for a second
    first = [event(0, run="r1", kind="run.start"), *(make_event("vehicle/1", n, "entity.state", run="r1")
                                                    for n in range(20))]
    during = [make_event("vehicle/1", n, "entity.state", run="r1") for n in range(20, 40)] + [
        event(1, run="r1", kind="run.end")]
    with linked(db_path, "pub-listens") as (publisher, ingest):
        subscription = ingest._writer._inbox._subscriber
        await_match(publisher, first[0])
        publisher.publish_all(first)
        assert ingest.wait_until_stored(len(first), timeout=20), ingest.stats()
        deadline = time.monotonic() + 10 * QUIET_S
        while ingest._writer._inbox._subscriber is subscription and time.monotonic() < deadline:
            time.sleep(0.01)
        publisher.publish_all(during)                       # the old subscription not yet emptied
        assert ingest.wait_until_stored(len(first) + len(during), timeout=20), ingest.stats()
        time.sleep(0.5)
        stats = ingest.stats()
        assert (stats["stored"], stats["duplicates"], stats["rejected"], stats["failed"]) == (
            len(first) + len(during), len(during), 0, 0)
        assert stats["late"] == 0 and ingest.missing() == (0, 0)
    with Store(db_path) as store:
        assert store.count("r1") == len(first) + len(during)
        assert store.quarantined() == [] and store.verify().ok
