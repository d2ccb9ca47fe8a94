"""What the ingest watches on the wire besides the events: sources' liveliness tokens, the
producers' caches (ingest/cache_recovery.py asks them for what the ingest missed), and samples a
publisher's sequence numbers say were missed on a live link.

The tokens and the misses arrive in Zenoh's own bounded channels, as the events do
(ingest/inbox.py): no Python runs on Zenoh's threads for them and nothing there waits for the disk.
(A cache's token, one per producer process, is taken by a short callback: the answer to a
producer's sync must know at once that a cache is still to be asked, ingest/sync_answer.py.) The
writer thread drains them between batches (`drain`) and records what they say in the store
(store.LivelinessChange, store.WireMiss). A miss names the publisher only by its Zenoh id, which
the inbox maps to the key its samples came on.
"""
from __future__ import annotations

import logging
import time
from collections.abc import Callable
from dataclasses import dataclass

import zenoh
from zenoh import ext

from store.wire import CACHE_PREFIX, LivelinessChange, WireMiss, live_slice, source_of_live_key

from .cache_recovery import CacheRecovery
from .inbox import Inbox, Received
from .sync_answer import SyncAnswers

log = logging.getLogger(__name__)

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
    """The liveliness subscriptions of ``key_expr``'s sources and of the caches, and the misses
    the inbox's subscription noticed. Only one thread (the writer) may drain it."""

    def __init__(self, session: zenoh.Session, inbox: Inbox, key_expr: str,
                 recorded: Callable[[str], bool] | None = None) -> None:
        self._inbox = inbox
        self._recorded = recorded
        self.recovery = CacheRecovery(session, key_expr)
        self.syncs = SyncAnswers(lambda: self.recovery.idle)
        self._live = session.liveliness().declare_subscriber(
            live_slice(key_expr), zenoh.handlers.FifoChannel(CAPACITY), history=True)
        self._caches = session.liveliness().declare_subscriber(f"{CACHE_PREFIX}/*", self.recovery.on_token,
                                                               history=True)

    def drain(self, highest_seq: HighestSeq) -> Noticed:
        """Everything noticed since the last drain; ``highest_seq(run, src)`` says how far each
        source had got, which ties a change to the events. Asks the caches found meanwhile, and
        answers the syncs that waited for that."""
        now = time.time_ns()
        changes = [self._change(sample, now, highest_seq, self._recorded) for sample in _taken(self._live)]
        self.recovery.step()
        self.syncs.answer_parked()
        misses = [self._miss(miss, now, highest_seq) for miss in self._inbox.take_misses()]
        return Noticed(tuple(c for c in changes if c is not None), tuple(m for m in misses if m is not None))

    @staticmethod
    def _change(sample: zenoh.Sample, now: int, highest_seq: HighestSeq,
                recorded: Callable[[str], bool] | None) -> LivelinessChange | None:
        """A token's change, or None for a key of another shape, or (``recorded``: with signatures
        required) a source that no trusted key covers: a token carries no signature and Zenoh does
        not say who declared it, so anyone reaching the ingest could make one up; Zenoh's access
        control keeps strangers from declaring tokens at all (docs/serve.md "A hardened deployment")."""
        source = source_of_live_key(str(sample.key_expr))
        if source is None or (recorded is not None and not recorded(source[1])):
            return None
        return LivelinessChange(*source, sample.kind == zenoh.SampleKind.PUT, now, highest_seq(*source))

    def recovered(self, max_items: int) -> list[Received]:
        """Up to ``max_items`` events the caches asked have replied with so far."""
        return self.recovery.recovered(max_items)

    def _miss(self, miss: ext.Miss, now: int, highest_seq: HighestSeq) -> WireMiss | None:
        key = self._inbox.publisher_keys.get(f"{miss.source.zid}/{miss.source.eid}")
        parts = key.split("/") if key else []
        if len(parts) != 5:   # gaps/<run>/<role>/<id>/<kind>; a publisher never heard from cannot be placed
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
