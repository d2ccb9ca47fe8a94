"""What the ingest watches on the wire besides the events: sources' liveliness tokens, and samples
its advanced subscription reports as missed (sent, and neither received nor fetched from the
publisher's cache).

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

from store import LivelinessChange, WireMiss, live_slice, source_of_live_key

log = logging.getLogger(__name__)

CAPACITY = 100_000   # changes a channel holds for the writer; a full one makes Zenoh wait, not drop
ADV_MARK = "/@adv/pub/"  # a detected publisher's token: <key>/@adv/pub/<zid>/<eid>/...

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

    def __init__(self, session: zenoh.Session, subscriber: ext.AdvancedSubscriber, key_expr: str) -> None:
        self._live = session.liveliness().declare_subscriber(
            live_slice(key_expr), zenoh.handlers.FifoChannel(CAPACITY), history=True)
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
        misses = [self._miss(miss, now, highest_seq) for miss in _taken(self._misses)]
        return Noticed(tuple(c for c in changes if c is not None), tuple(m for m in misses if m is not None))

    @staticmethod
    def _change(sample: zenoh.Sample, now: int, highest_seq: HighestSeq) -> LivelinessChange | None:
        source = source_of_live_key(str(sample.key_expr))
        if source is None:
            return None
        return LivelinessChange(*source, sample.kind == zenoh.SampleKind.PUT, now, highest_seq(*source))

    def _learn(self, sample: zenoh.Sample) -> None:
        """Remember a detected publisher's key by its id (forgotten when it goes)."""
        key, mark, ids = str(sample.key_expr).partition(ADV_MARK)
        if not mark:
            return
        ident = "/".join(ids.split("/")[:2])
        if sample.kind == zenoh.SampleKind.PUT:
            self._keys[ident] = key
        else:
            self._keys.pop(ident, None)

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
