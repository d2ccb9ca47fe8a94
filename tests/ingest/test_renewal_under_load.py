"""Renewals mid-stream never stall the link (issue 40): a run of bench/sim.py once stood for 13
minutes with the producer blocked in put and the writer idle, on a loaded machine where a pause
longer than QUIET_S lets the writer renew its subscription (ingest/inbox.py `renew`) while samples
are in flight. Here the pauses are made on purpose, around a lowered QUIET_S, with a small channel so
that a channel left declared and unread fills within a burst and blocks the receive path."""
from __future__ import annotations

import random
import threading
import time
from pathlib import Path

import pytest
import zenoh

from ingest import inbox as inbox_module
from ingest import writer as writer_module
from ingest.inbox import Inbox
from store import Store
from sim_replay.publisher import zenoh_config
from tests.helpers.ingest_testkit import await_match, free_endpoint, linked, make_event
from tests.helpers.store_testkit import event

QUIET_S = 0.05
BURSTS = 40
SOURCES = 12
PUT_BOUND_S = 30.0   # a burst of a few hundred puts takes milliseconds; a stall never ends


class FailingUndeclare:
    """A miss listener or subscription whose undeclare fails ``failures`` times for a reason other
    than a closed session (zenoh may raise ZError for any), and is the real one otherwise."""

    def __init__(self, real: object, failures: int = 1_000_000) -> None:
        self.real, self.failures, self.undeclared = real, failures, False

    def try_recv(self) -> object:
        return self.real.try_recv()

    def undeclare(self) -> None:
        if self.failures > 0:
            self.failures -= 1
            raise zenoh.ZError("undeclare failed (injected)")
        self.real.undeclare()
        self.undeclared = True


def failing(monkeypatch: pytest.MonkeyPatch, which: str, failures: int = 1_000_000) -> list[tuple]:
    """Make the ``which`` ("misses" or "subscriber") of every declaration fail to undeclare; returns
    the declarations made, which keeps each referenced as a caller (a traceback, a log record) can:
    main's renew left an old subscription it failed to undeclare to Python's dropping it."""
    declare, made = Inbox._declare, []

    def declared(self: Inbox) -> tuple:
        subscriber, misses = declare(self)
        if which == "misses":
            misses = FailingUndeclare(misses, failures)
        else:
            subscriber = FailingUndeclare(subscriber, failures)
        made.append((subscriber, misses))
        return subscriber, misses

    monkeypatch.setattr(Inbox, "_declare", declared)
    return made


@pytest.mark.parametrize("fault", ["none", "misses", "subscriber"])
def test_bursts_with_pauses_around_quiet_s_renew_many_times_and_every_event_is_stored(
        db_path: Path, monkeypatch: pytest.MonkeyPatch, fault: str) -> None:
    """With an undeclare failing at every renewal, main's renew left the old channel declared and
    unread: it filled, and the ingest stored nothing more (seen: 297 of 7,017 stored, the writer idle)."""
    if fault != "none":
        failing(monkeypatch, fault)
    monkeypatch.setattr(writer_module, "QUIET_S", QUIET_S)
    monkeypatch.setattr(inbox_module, "RENEW_AFTER", 20)
    renewals = []
    renew = Inbox.renew

    def counted(self: Inbox) -> bool:
        done = renew(self)
        renewals.append(done)
        return done

    monkeypatch.setattr(Inbox, "renew", counted)
    pace = random.Random(40)
    start = event(0, run="r1", kind="run.start")
    sizes = [pace.randrange(50, 300) for _ in range(BURSTS)]
    flat = [make_event(f"vehicle/{n % SOURCES}", n // SOURCES, "entity.state", run="r1") for n in range(sum(sizes))]
    bursts = [flat[sum(sizes[:b]):sum(sizes[:b + 1])] for b in range(BURSTS)]
    total = 1 + sum(map(len, bursts))
    with linked(db_path, "pub-listens", max_pending=64) as (publisher, ingest):
        await_match(publisher, start)
        publisher.publish(start)
        failed: list[BaseException] = []

        def produce() -> None:
            try:
                for burst in bursts:
                    publisher.publish_all(burst)
                    time.sleep(QUIET_S * pace.uniform(0.8, 3.0))   # just under, at, and past quiet
            except BaseException as exc:       # noqa: BLE001 - reported by the test thread
                failed.append(exc)

        producing = threading.Thread(target=produce, daemon=True)
        producing.start()
        producing.join(PUT_BOUND_S + BURSTS * QUIET_S * 3.0)
        assert not producing.is_alive(), f"a put blocked: stored {ingest.stats()}, renewals {len(renewals)}"
        assert not failed, failed
        assert ingest.wait_until_stored(total, timeout=30), ingest.stats()
        stats = ingest.stats()
        assert (stats["rejected"], stats["failed"]) == (0, 0), stats
        assert ingest.missing() == (0, 0)
    assert sum(renewals) >= BURSTS // 8, f"too few renewals to test them: {renewals}"
    with Store(db_path) as store:
        assert store.count("r1") == total
        assert store.quarantined() == [] and store.verify().ok


def test_a_renewed_subscription_whose_undeclare_fails_is_still_read_and_undeclared_at_the_next(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(inbox_module, "RENEW_AFTER", 1)
    made = failing(monkeypatch, "subscriber", failures=1)
    endpoint = free_endpoint()
    ingest = zenoh.open(zenoh_config(listen=[endpoint]))
    producer = zenoh.open(zenoh_config(connect=[endpoint]))
    try:
        inbox = Inbox(ingest, "gaps/**", 4)
        time.sleep(1.0)                                       # the subscription reached the producer
        producer.put("gaps/r/vehicle/1/entity.state", b"0")
        assert [p for _, p, _, _ in taken(inbox, 1)] == [b"0"]
        assert inbox.renew()
        first = made[0][0]
        assert not first.undeclared                           # it failed: still declared ...
        putting = threading.Thread(target=lambda: [producer.put(
            "gaps/r/vehicle/1/entity.state", str(n).encode(), congestion_control=zenoh.CongestionControl.BLOCK)
            for n in range(1, 13)], daemon=True)
        putting.start()                                       # ... and read, or its 4 places would block
        got = [payload for _, payload, _, _ in taken(inbox, 24)]   # each from both: the writer counts
        putting.join(10)
        assert not putting.is_alive(), "a put blocked on the old channel"
        assert sorted(set(got), key=int) == [str(n).encode() for n in range(1, 13)]   # the copy a duplicate
        assert len(got) == 24
        assert inbox.renew()
        assert first.undeclared                               # tried again at the next renewal
        assert made[1][0].undeclared is False and made[1][0].failures == 0   # the second failed once too
    finally:
        producer.close()
        ingest.close()


def test_a_miss_listener_whose_undeclare_fails_leaves_its_subscription_undeclared_and_is_still_read(
        monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(inbox_module, "RENEW_AFTER", 1)
    made = failing(monkeypatch, "misses")
    endpoint = free_endpoint()
    ingest = zenoh.open(zenoh_config(listen=[endpoint]))
    producer = zenoh.open(zenoh_config(connect=[endpoint]))
    try:
        inbox = Inbox(ingest, "gaps/**", 4)
        time.sleep(1.0)
        producer.put("gaps/r/vehicle/1/entity.state", b"0")
        assert taken(inbox, 1)
        old_subscriber, old_misses = made[0]
        assert inbox.renew()
        with pytest.raises(zenoh.ZError, match="Undeclared"):
            old_subscriber.try_recv()                         # undeclared whatever its listener did
        assert (None, old_misses) in inbox._retiring          # the listener, still read by take_misses
        inbox.take_misses()
    finally:
        producer.close()
        ingest.close()


def taken(inbox: Inbox, n: int, timeout_s: float = 10.0) -> list:
    """At least ``n`` samples from ``inbox``, within ``timeout_s``."""
    got: list = []
    deadline = time.monotonic() + timeout_s
    while len(got) < n and time.monotonic() < deadline:
        got += inbox.take(n, 0.01, idle_s=0.1) or []
    return got
