"""What the ingest has received and not yet written: Zenoh's own bounded FIFO channel on ``gaps/**``.

The subscription is an advanced one (zenoh.ext), for what it tells besides the samples: the samples
a publisher's sequence numbers say were missed on a live link (ingest/wire_watch.py records them).

This is the "callback only enqueues" rule taken one step further: Zenoh enqueues in native code, so no
Python runs on the receive path at all and receiving never waits for the GIL (a writer busy parsing cannot
stall the link). The writer takes samples in bursts. When the channel is full Zenoh waits, which pushes
back on publishers through BLOCK congestion control instead of dropping events. Measured against a Python
callback feeding a ``queue.Queue``, throughput was the same (about 38,000 events/s here).

Closing the session closes the channel; samples already in it can still be taken (checked with zenoh
1.10.2), so a stop loses nothing that was received.

Zenoh's channel is a queue that grows to hold what waited and never shrinks (24-32 MB after a burst
of 50,000-80,000 samples waited, bench/ingest_fleet.py, tests/ingest/test_inbox_memory.py). So once the writer finds the ingest
quiet after RENEW_AFTER samples, it `renew`s the subscription: a fresh one (with its own channel) is
declared first, then the old one is emptied and undeclared, and its channel freed. Every sample reaches
one of the two: from its declaration on, the new subscription gets each sample the session receives,
and what the old one got before is taken from it before it goes (after RENEW_GRACE_S, for a delivery
already under way when the new one was declared). A sample that arrived in between reaches both; the
old one's copy is written first and the new one's is the same bytes under the same (run, src, seq),
which the store counts as a duplicate (store/batch.py), not a refusal. An undeclared subscriber's
channel can no longer be read (zenoh 1.10.2 says "Undeclared subscriber"), hence this order. The
grace covers a delivery that is quick, not one held up by a full channel: the writer renews only
when it has taken nothing for QUIET_S (ingest/idle_memory.py), when the old channel is empty.

A channel still declared and no longer read would fill, and Zenoh's receive path, which waits on a
full channel, would then stop for every subscription of the session and every publisher behind it
(a simulation stalled so, its ingest idle). So the old subscription and its miss listener are
undeclared each on its own, and one whose undeclare fails stays on a retiring list that is read
like the live one (its samples are copies: duplicates) and undeclared again at the next renewal.
"""
from __future__ import annotations

import logging
import time
from collections.abc import Iterable

import zenoh
from zenoh import ext

log = logging.getLogger(__name__)

Received = tuple[str, bytes, bool, str]  # (key, payload, is_put, encoding as Zenoh names it)
POLL_S = 0.001  # pause between looks at an empty channel while a partial batch waits for company
IDLE_S = 0.02   # how long `take` waits for a first sample before returning none (the writer looks around)
RENEW_AFTER = 10_000
"""Samples taken since the subscription was declared before a quiet inbox renews it (`renew`): what
a channel keeps after a few thousand is little, and a renewal costs a declaration on the network."""
RENEW_GRACE_S = 0.05
MISS_CAPACITY = 100_000   # misses the listener holds for the writer; a full one makes Zenoh wait, not drop


class Inbox:
    """The subscription and its channel. Only one thread (the writer) may take from it."""

    def __init__(self, session: zenoh.Session, key_expr: str, capacity: int) -> None:
        self._session = session
        self._key_expr = key_expr
        self._capacity = capacity
        self._subscriber, self._misses = self._declare()
        self._held: list[Received] = []   # taken from a renewed subscription's channel, given out first
        self._held_misses: list[ext.Miss] = []
        self._retiring: list[tuple[ext.AdvancedSubscriber | None, ext.SampleMissListener | None]] = []
        """Renewed subscriptions and miss listeners whose undeclare failed: still read (`_retire`)."""
        self._taken = 0                   # samples taken since the subscription was declared
        self._closed = False
        self.publisher_keys: dict[str, str] = {}
        """Per publisher ("<zid>/<eid>") whose samples carry sequence numbers, the key it publishes
        on, noted from its first sample taken: a miss names only the publisher."""
        self._keys_seen: set[str] = set()
        self._of_run: dict[str, list[tuple[str, str | None]]] = {}
        """Per run, its keys seen and the publisher each was noted for: letting a run go costs its
        own keys, not a walk over every key held."""
        self.first_at = 0.0  # monotonic time the last batch's first sample left Zenoh's channel

    def _declare(self) -> tuple[ext.AdvancedSubscriber, ext.SampleMissListener]:
        """A subscription with its channel, and the listener of the samples its publishers' sequence
        numbers say were missed (read by ingest/wire_watch.py through `take_misses`)."""
        subscriber = ext.declare_advanced_subscriber(self._session, self._key_expr,
                                                     zenoh.handlers.FifoChannel(self._capacity))
        return subscriber, subscriber.sample_miss_listener(zenoh.handlers.FifoChannel(MISS_CAPACITY))

    def take_misses(self) -> list[ext.Miss]:
        """The misses noticed since the last call (nothing more once the session is closed)."""
        misses, self._held_misses = self._held_misses, []
        for _, retired in self._retiring:
            misses.extend(_drained(retired))
        misses.extend(_drained(self._misses))
        return misses

    @property
    def closing(self) -> bool:
        """Whether the session was closed: the writer's cue to give up on a failing channel."""
        return self._closed or self._session.is_closed()

    def take(self, max_items: int, wait_s: float, idle_s: float = IDLE_S) -> list[Received] | None:
        """Up to ``max_items`` samples, waiting at most ``wait_s`` after the first for more to arrive.

        Waits up to ``idle_s`` for a first sample and returns an empty list if none came, so that
        the writer records liveliness changes on a quiet link too. Returns None once the session
        is closed and every sample received before has been taken.
        """
        first = self._first(idle_s)
        if first is None:
            return None if self._closed else []
        batch = [first]
        self.first_at = time.monotonic()
        deadline = self.first_at + wait_s
        while True:
            self._take_waiting(batch, max_items)
            if len(batch) >= max_items or self._closed or time.monotonic() >= deadline:
                self._taken += len(batch)
                return batch
            time.sleep(POLL_S)

    def _take_waiting(self, batch: list[Received], max_items: int) -> None:
        """Append to ``batch`` the samples waiting now (as `received` makes them), up to
        ``max_items`` in it, in one loop: the writer's hot path, and the one way samples are taken
        (those of a renewed subscription first)."""
        if self._held:
            room = max_items - len(batch)
            batch.extend(self._held[:room])
            del self._held[:room]
        if self._retiring:
            self._take_retiring(batch, max_items)
        if not self._closed and self._take_from(self._subscriber, batch, max_items):
            self._closed = True

    def _take_retiring(self, batch: list[Received], max_items: int) -> None:
        """Read the retired subscriptions whose undeclare failed (`_retire`), before the live one:
        a channel left declared must not fill. One found closed is let go."""
        self._retiring = [(subscriber, misses) for subscriber, misses in self._retiring
                          if subscriber is None or not self._take_from(subscriber, batch, max_items)]

    def _take_from(self, subscriber: ext.AdvancedSubscriber, batch: list[Received], max_items: int) -> bool:
        """`_take_waiting`'s loop on one subscription's channel; returns whether it found the channel
        closed (and empty)."""
        try_recv, seen, append = subscriber.try_recv, self._keys_seen, batch.append
        try:
            while len(batch) < max_items:
                sample = try_recv()
                if sample is None:
                    return False
                item = received(sample)
                if item[0] not in seen:
                    self._note_first(item[0], sample)
                append(item)
        except zenoh.ZError:  # "channel is empty and closed": the session was closed
            return True
        return False

    def renew(self) -> bool:
        """Declare a fresh subscription, then empty the old one and undeclare it, freeing its channel
        (module docstring); only once RENEW_AFTER samples were taken since the last, and only to be
        called when nothing has arrived for a while (the writer calls it when quiet), so that little
        is in flight. Returns whether it renewed."""
        if self._taken < RENEW_AFTER or self.closing:
            return False
        old, old_misses = self._subscriber, self._misses
        try:
            self._subscriber, self._misses = self._declare()
        except zenoh.ZError:   # the session is closing: the old channel is read to its end as before
            return False
        self._taken = 0
        time.sleep(RENEW_GRACE_S)
        self._retiring.append((old, old_misses))
        self._retire()
        return True

    def _retire(self) -> None:
        """Undeclare the retired subscriptions and their miss listeners, each on its own: a declared
        channel that nobody reads fills, and Zenoh's receive path then waits on it for every sample
        (the link stalls, publishers block). So one whose undeclare fails while the session is open
        stays here, read with the live one (`_take_waiting`, `take_misses`; what it gives is a copy,
        counted a duplicate) and tried again at the next renewal; one found closed is let go."""
        retiring, self._retiring = self._retiring, []
        for subscriber, misses in retiring:
            if subscriber is not None:   # what it held: at most a channel's worth, all at its front;
                self._take_from(subscriber, self._held, len(self._held) + self._capacity)   # what came
                # after, the live one has too
            self._held_misses.extend(_drained(misses))
            if misses is not None and not self._undeclared(misses):
                self._retiring.append((None, misses))
            if subscriber is not None and not self._undeclared(subscriber):
                self._retiring.append((subscriber, None))

    def _undeclared(self, channel: ext.AdvancedSubscriber | ext.SampleMissListener) -> bool:
        """Whether ``channel`` is undeclared or gone with the session; a failure is logged."""
        try:
            channel.undeclare()
        except zenoh.ZError as exc:
            if self.closing:   # the session's close undeclares it
                return True
            log.warning("ingest: undeclaring a renewed subscription's channel failed, still read: %r", exc)
            return False
        return True

    def release(self, runs: Iterable[str]) -> None:
        """Forget the keys (and their publishers) of runs that ended or went quiet: a fleet's keys
        come and go. A key of one seen again is noted again as a first sample."""
        for run in runs:
            for key, publisher in self._of_run.pop(run, ()):
                self._keys_seen.discard(key)
                if publisher is not None and self.publisher_keys.get(publisher) == key:
                    del self.publisher_keys[publisher]

    def _first(self, idle_s: float) -> Received | None:
        """The next sample within ``idle_s``, looking every POLL_S (Zenoh's channel has no
        receive with a timeout); None if none came or the channel is closed and empty. The
        encoding travels with it, so that a sample declared as something other than JSON is
        refused for what it claims to be, not parsed by luck."""
        deadline = time.monotonic() + idle_s
        got: list[Received] = []
        while True:
            self._take_waiting(got, 1)
            if got:
                return got[0]
            if self._closed or time.monotonic() >= deadline:
                return None
            time.sleep(POLL_S)

    def _note_first(self, key: str, sample: zenoh.Sample) -> None:
        """Note the publisher of a key's first sample (a plain publisher's carry none). A source
        despawned and spoken again gets a new publisher on the same key, whose misses then go
        unnamed (logged); that is rare, and its envelope seqs still show any hole."""
        self._keys_seen.add(key)
        info = sample.source_info
        publisher = None
        if info is not None and info.source_id is not None:
            publisher = f"{info.source_id.zid}/{info.source_id.eid}"
            self.publisher_keys[publisher] = key
        self._of_run.setdefault(run_of_key(key), []).append((key, publisher))


def _drained(misses: ext.SampleMissListener | None) -> list[ext.Miss]:
    """What a miss listener holds now (nothing once closed with the session)."""
    taken: list[ext.Miss] = []
    try:
        while misses is not None and (miss := misses.try_recv()) is not None:
            taken.append(miss)
    except zenoh.ZError:
        pass
    return taken


def run_of_key(key: str) -> str:
    """The run a key names (gaps/<run>/...), or "" for a key of another shape."""
    parts = key.split("/", 2)
    return parts[1] if len(parts) == 3 else ""


def received(sample: zenoh.Sample) -> Received:
    """A sample as the writer takes it."""
    return (str(sample.key_expr), sample.payload.to_bytes(), sample.kind == zenoh.SampleKind.PUT,
            str(sample.encoding))
