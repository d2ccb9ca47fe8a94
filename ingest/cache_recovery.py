"""Asking the producers' caches for what the ingest missed (store/cache_wire.py says how).

Two things make the ingest ask, both by envelope seqs, which every event carries:

- a cache found (its liveliness token, seen on start for the producers already there, or later):
  its index says which sources it holds, up to which seq; for each source not yet heard live
  since this ingest started, the ingest asks for what it holds above the source's highest seq
  stored (so a restart gets what was published while it was down, a despawned source's last
  events included);
- a hole in a source's seqs in the live stream (a seq above the highest stored, arrived or asked
  for, plus one): the ingest asks every cache for the missing range, the holes of a batch in one
  query (after a restart, every source's first event opens one: a query each would have every
  cache go through its ring a thousand times). Only an ingest whose key takes every kind (ends
  with ``*`` or ``**``) does: a slice by kind sees holes by design.

Replies are the events' exact bytes on their own keys; they go through the same screening as live
samples (a repeat of a stored event is a duplicate). What no cache holds any more stays a hole,
which the store lists (`gaps runs --gaps`).

Everything here runs on the writer's thread, except ``on_token`` and ``idle``, which a Zenoh
callback calls (under the lock).
"""
from __future__ import annotations

import logging
import threading
from collections.abc import Callable, Iterable

import zenoh

from store.wire import (CacheQueryError, cache_id_of_token, cache_query_options, index_selector, read_index,
                        want_payload, want_selector)

from .inbox import Received, received

log = logging.getLogger(__name__)

CAPACITY = 100_000   # replies a query's channel holds; a full one makes Zenoh wait, not drop
Source = tuple[str, str]
StoredHighest = Callable[[str, str], "int | None"]


class CacheRecovery:
    """Per source, the highest seq stored, arrived or asked for; the caches asked and their answers."""

    def __init__(self, session: zenoh.Session, key_expr: str) -> None:
        self._session = session
        self._key_expr = key_expr
        self._slice = zenoh.KeyExpr(key_expr)
        self._holes_asked = key_expr.rsplit("/", 1)[-1] in ("*", "**")
        self._known: dict[Source, int] = {}
        self._heard: set[Source] = set()          # heard live since start
        self._srcs: dict[str, list[str]] = {}     # run -> its srcs in _known: a release costs its own
        self._holes: list[tuple[str, str, int, int]] = []   # seen in the live stream, not yet asked
        self._lock = threading.Lock()
        self._found: list[str] = []               # caches whose token came, not yet asked
        self._indexes: list[zenoh.Handler[zenoh.Reply]] = []
        self._asked: list[zenoh.Handler[zenoh.Reply]] = []
        self._within: dict[str, bool] = {}
        self.stored_highest: StoredHighest = lambda run, src: None
        """Set by the writer once its store is open: where a source stood before this ingest."""

    def on_token(self, sample: zenoh.Sample) -> None:
        """A Zenoh callback: a cache's token appeared (it is asked on the writer's next look)."""
        cache_id = cache_id_of_token(str(sample.key_expr))
        if cache_id is not None and sample.kind == zenoh.SampleKind.PUT:
            with self._lock:
                self._found.append(cache_id)

    @property
    def idle(self) -> bool:
        """Whether every cache found, and every hole seen, has been asked and answered."""
        with self._lock:
            return not (self._found or self._holes or self._indexes or self._asked)

    def saw(self, run: str, src: str, seq: int, live: bool) -> None:
        """An event screened (``live``: from the stream, not a cache's answer); a hole above what
        was known of its source is asked of every cache."""
        self.saw_all(((run, src, seq),), live)

    def saw_all(self, identities: Iterable[tuple[str, str, int]], live: bool) -> None:
        """``saw`` each (run, src, seq) of a batch, in order, in one loop (the writer's hot path)."""
        known_of, heard, holes = self._known, self._heard, self._holes
        asking = live and self._holes_asked
        for run, src, seq in identities:
            source = (run, src)
            known = known_of.get(source)
            if known is None:
                highest = self.stored_highest(run, src)
                known = known_of[source] = -1 if highest is None else highest
                self._srcs.setdefault(run, []).append(src)
            if live:
                heard.add(source)
                if asking and seq > known + 1:
                    holes.append((run, src, known + 1, seq - 1))
            if seq > known:
                known_of[source] = seq

    def release(self, runs: Iterable[str]) -> None:
        """Forget the sources of runs that ended (their run.end stored): a later event of one goes
        on from its highest seq stored, as a source first heard does."""
        for run in set(runs):
            for src in self._srcs.pop(run, ()):
                self._known.pop((run, src), None)
                self._heard.discard((run, src))

    def step(self) -> None:
        """Ask every cache for the holes seen since the last look, the caches found meanwhile for
        their index, and each index's sources."""
        if self._holes:
            holes, self._holes = self._holes, []
            self._ask(want_selector(self._key_expr), holes)
        with self._lock:
            found, self._found = self._found, []
        for cache_id in found:
            handler = self._get(index_selector(cache_id, self._key_expr))
            if handler is not None:
                with self._lock:
                    self._indexes.append(handler)
        for handler, replies, done in self._poll(self._indexes_snapshot()):
            for reply in replies:
                self._follow_index(reply)
            if done:
                with self._lock:
                    self._indexes.remove(handler)

    def recovered(self, max_items: int) -> list[Received]:
        """Up to ``max_items`` events the caches have answered with so far (within this ingest's key)."""
        out: list[Received] = []
        with self._lock:
            asked = list(self._asked)
        for handler in asked:
            done = False
            while len(out) < max_items:
                try:
                    reply = handler.try_recv()
                except zenoh.ZError:   # every reply is in
                    done = True
                    break
                if reply is None:
                    break
                if reply.ok is not None:
                    item = received(reply.ok)
                    if self._in_slice(item[0]):
                        out.append(item)
                else:
                    log.warning("ingest: a cache refused a query: %s", _refusal(reply))
            if done:
                with self._lock:
                    self._asked.remove(handler)
        return out

    def _follow_index(self, reply: zenoh.Reply) -> None:
        """Ask one cache, in one query, for what it holds above each source's known seq, for the
        sources not heard live (those are followed by their live seqs)."""
        if reply.ok is None:
            log.warning("ingest: a cache refused its index: %s", _refusal(reply))
            return
        try:
            spans = read_index(reply.ok.payload.to_bytes())
        except CacheQueryError as exc:
            log.warning("ingest: %s", exc)
            return
        want = []
        for span in spans:
            source = (span.run, span.src)
            if source in self._heard:
                continue
            known = self._known.get(source)
            if known is None:
                highest = self.stored_highest(*source)
                known = -1 if highest is None else highest
            if span.last > known:
                want.append((span.run, span.src, known + 1, span.last))
                if source not in self._known:
                    self._srcs.setdefault(span.run, []).append(span.src)
                self._known[source] = span.last
        if want:
            cache_id = cache_id_of_token(str(reply.ok.key_expr))
            self._ask(want_selector(self._key_expr, cache_id), want)

    def _ask(self, selector: str, want: list[tuple[str, str, int, int]]) -> None:
        handler = self._get(selector, want_payload(want))
        if handler is not None:
            with self._lock:
                self._asked.append(handler)

    def _get(self, selector: str, payload: bytes | None = None) -> zenoh.Handler[zenoh.Reply] | None:
        """Send one query; None once the session is closed (a stopping ingest stores what it has
        and asks nothing more: what it would have asked stays a hole, listed)."""
        try:
            return self._session.get(selector, zenoh.handlers.FifoChannel(CAPACITY), payload=payload,
                                     **cache_query_options())
        except zenoh.ZError as exc:
            if not self._session.is_closed():
                log.warning("ingest: asking the caches (%s) failed: %s", selector, exc)
            return None

    def _indexes_snapshot(self) -> list[zenoh.Handler[zenoh.Reply]]:
        with self._lock:
            return list(self._indexes)

    @staticmethod
    def _poll(handlers: list[zenoh.Handler[zenoh.Reply]]):
        """Per handler: the replies in now, and whether all are in."""
        for handler in handlers:
            replies, done = [], False
            while True:
                try:
                    reply = handler.try_recv()
                except zenoh.ZError:
                    done = True
                    break
                if reply is None:
                    break
                replies.append(reply)
            yield handler, replies, done

    def _in_slice(self, key: str) -> bool:
        """Whether a reply's key is within this ingest's key (a cache answers within it; checked
        all the same, remembered per key)."""
        found = self._within.get(key)
        if found is None:
            try:
                found = self._slice.includes(zenoh.KeyExpr(key))
            except zenoh.ZError:
                found = True     # not a key expression: screening quarantines it with the reason
            self._within[key] = found
        return found


def _refusal(reply: zenoh.Reply) -> str:
    """What a cache's refusal says (Zenoh's reply holds either a sample or an error)."""
    return reply.err.payload.to_string() if reply.err is not None else "(no reason given)"
