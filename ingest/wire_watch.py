"""What the ingest watches on the wire besides the events: sources' liveliness tokens, the
publishers its advanced subscription detects, whose caches it asks for what they hold, and
samples a publisher's sequence numbers say were missed.

Every publisher found, on start (its token is there already) or later, is asked once for what its
cache holds from before the first sample the ingest received from it (store.cache_query_options,
``_sn=..N``; all of it if none arrived within DEFER_S): an ingest that was down gets what was
published meanwhile, as long as the cache still holds it (store.CACHE_S), and a publisher that put
before the ingest's subscription reached it loses nothing. The replies go through the same screening
as the rest (a repeat of a stored event is counted as a duplicate). What the cache no longer held leaves a hole
in the source's seqs, which the store lists (`gaps runs --gaps`).

Both arrive in Zenoh's own bounded channels, as the events do (ingest/inbox.py): no Python runs on
Zenoh's threads and nothing there waits for the disk. The writer thread drains them between
batches (`drain`) and records what they say in the store (store.LivelinessChange, store.WireMiss).
A miss names the publisher only by its Zenoh id, so the publishers announced by the subscription's
publisher detection are kept, id to key, to say which source and kind the lost samples were.
"""
from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass

import zenoh
from zenoh import ext

from store import ADV_MARK, LivelinessChange, WireMiss, cache_query_options, live_slice, source_of_live_key

from .inbox import Inbox, Received, received

log = logging.getLogger(__name__)

DEFER_S = 0.5
"""How long a newly found publisher's cache is left unasked while its first sample may still arrive:
with it, the ingest asks only for what came before (no duplicates); without, for everything."""
CAPACITY = 100_000   # changes a channel holds for the writer; a full one makes Zenoh wait, not drop

HighestSeq = Callable[[str, str], "int | None"]


@dataclass(frozen=True, slots=True)
class Noticed:
    """What one drain found: liveliness changes and lost samples, ready for the store."""

    changes: tuple[LivelinessChange, ...] = ()
    misses: tuple[WireMiss, ...] = ()

    def __bool__(self) -> bool:
        return bool(self.changes or self.misses)


class WireWatch:
    """The liveliness subscription of ``key_expr``'s sources and the miss listener of ``subscriber``.
    Only one thread (the writer) may drain it."""

    def __init__(self, session: zenoh.Session, inbox: Inbox, key_expr: str) -> None:
        self._session = session
        self._inbox = inbox
        self._asked: list[zenoh.Handler[zenoh.Reply]] = []   # caches asked whose replies are not all in
        self._unasked: dict[str, tuple[str, str, float]] = {}  # id -> (token, key, when found)
        self._live = session.liveliness().declare_subscriber(
            live_slice(key_expr), zenoh.handlers.FifoChannel(CAPACITY), history=True)
        subscriber = inbox.subscriber
        self._publishers = subscriber.detect_publishers(zenoh.handlers.FifoChannel(CAPACITY), history=True)
        self._misses = subscriber.sample_miss_listener(zenoh.handlers.FifoChannel(CAPACITY))
        self._keys: dict[str, str] = {}   # "<zid>/<eid>" of an advanced publisher -> its key

    def drain(self, highest_seq: HighestSeq) -> Noticed:
        """Everything noticed since the last drain; ``highest_seq(run, src)`` says how far each
        source had got, which ties a change to the events."""
        now = time.time_ns()
        changes = [self._change(sample, now, highest_seq) for sample in _taken(self._live)]
        for sample in _taken(self._publishers):
            self._learn(sample)
        self._ask_caches()
        misses = [self._miss(miss, now, highest_seq) for miss in _taken(self._misses)]
        return Noticed(tuple(c for c in changes if c is not None), tuple(m for m in misses if m is not None))

    @staticmethod
    def _change(sample: zenoh.Sample, now: int, highest_seq: HighestSeq) -> LivelinessChange | None:
        source = source_of_live_key(str(sample.key_expr))
        if source is None:
            return None
        return LivelinessChange(*source, sample.kind == zenoh.SampleKind.PUT, now, highest_seq(*source))

    def recovered(self, max_items: int) -> list[Received]:
        """Up to ``max_items`` samples the caches asked have replied with so far."""
        out: list[Received] = []
        still: list[zenoh.Handler[zenoh.Reply]] = []
        for replies in self._asked:
            done = False
            while len(out) < max_items:
                try:
                    reply = replies.try_recv()
                except zenoh.ZError:   # every reply is in
                    done = True
                    break
                if reply is None:
                    break
                if reply.ok is not None:
                    out.append(received(reply.ok))
            if not done:
                still.append(replies)
        self._asked = still
        return out

    def _learn(self, sample: zenoh.Sample) -> None:
        """Remember a detected publisher's key by its id (forgotten when it goes), and ask a new
        one's cache for what it holds."""
        token = str(sample.key_expr)
        key, mark, ids = token.partition(ADV_MARK)
        if not mark:
            return
        ident = "/".join(ids.split("/")[:2])
        if sample.kind != zenoh.SampleKind.PUT:
            self._keys.pop(ident, None)
            self._unasked.pop(ident, None)
        elif ident not in self._keys:
            self._keys[ident] = key
            self._unasked[ident] = (token, key, time.monotonic())

    def _ask_caches(self) -> None:
        """Ask each found publisher's cache for what preceded its first sample received, once that
        sample is in, or for everything once DEFER_S has passed without it."""
        now = time.monotonic()
        for ident, (token, key, found_at) in list(self._unasked.items()):
            first = self._inbox.first_seen.get(key)
            if first is not None and first[0] == ident:
                selector = f"{token}?_sn=..{first[1] - 1}" if first[1] > 0 else None
            elif now - found_at >= DEFER_S:
                selector = token
            else:
                continue
            del self._unasked[ident]
            if selector is not None:
                self._asked.append(self._session.get(selector, zenoh.handlers.FifoChannel(CAPACITY),
                                                     **cache_query_options()))

    def _miss(self, miss: ext.Miss, now: int, highest_seq: HighestSeq) -> WireMiss | None:
        key = self._keys.get(f"{miss.source.zid}/{miss.source.eid}")
        parts = key.split("/") if key else []
        if len(parts) != 5:   # gaps/<run>/<role>/<id>/<kind>; a publisher never announced cannot be placed
            log.warning("ingest: %d samples of publisher %s were lost on the wire; its key is unknown",
                        miss.nb, miss.source)
            return None
        run, src, kind = parts[1], f"{parts[2]}/{parts[3]}", parts[4]
        return WireMiss(run, src, kind, miss.nb, now, highest_seq(run, src))


def _taken(channel: zenoh.Subscriber | ext.SampleMissListener) -> list:
    """Whatever the channel holds now, without waiting (nothing once it is closed)."""
    out = []
    try:
        while (item := channel.try_recv()) is not None:
            out.append(item)
    except zenoh.ZError:   # closed with the session
        pass
    return out
