"""A producer's one cache on the wire: its liveliness token and the queryable that answers from it
(store/cache_wire.py says what is asked and answered; sim_replay/recent_events.py holds the events).

Zenoh's callback only queues a query; a thread of ours answers it, not Zenoh's: an answer of
thousands of events, sent RELIABLE with BLOCK, may wait for room on the link, and Zenoh's receive
thread must not wait with it. (A Python queue rather than Zenoh's channel: a thread blocked in a
channel's recv keeps the queryable from being undeclared.)
"""
from __future__ import annotations

import logging
import queue
import threading
import uuid

import zenoh

from store.wire import CacheQueryError, audit_qos, cache_token, parse_cache_query, write_index, zenoh_message

from .recent_events import RecentEvents

log = logging.getLogger(__name__)


class CacheQueryable:
    """Announces the cache (``gaps/@cache/<id>``) and answers ``gaps/@cache/<id>/**`` from ``recent``
    until ``close``."""

    def __init__(self, session: zenoh.Session, recent: RecentEvents) -> None:
        self.cache_id = uuid.uuid4().hex
        self._recent = recent
        key = cache_token(self.cache_id)
        self._queries: queue.SimpleQueue[zenoh.Query | None] = queue.SimpleQueue()
        self._queryable = session.declare_queryable(f"{key}/**", self._queries.put)
        self._token = session.liveliness().declare_token(key)
        self._encoding = audit_qos()["encoding"]
        self._thread = threading.Thread(target=self._serve, name="gaps-cache", daemon=True)
        self._thread.start()

    def close(self) -> None:
        """Withdraw the token and the queryable; the thread ends once the queries before are answered."""
        self._token.undeclare()
        self._queryable.undeclare()
        self._queries.put(None)
        self._thread.join(5.0)

    def _serve(self) -> None:
        while (query := self._queries.get()) is not None:
            try:
                self._answer(query)
            except zenoh.ZError as exc:   # the link went while answering: the asker gets a partial answer
                log.warning("cache: answering %s: %s", query.selector, zenoh_message(exc))
            except Exception:
                log.exception("cache: answering %s failed", query.selector)
            finally:
                query.drop()

    def _answer(self, query: zenoh.Query) -> None:
        payload = query.payload.to_bytes() if query.payload is not None else None
        try:
            asked = parse_cache_query(str(query.key_expr), str(query.parameters), payload)
        except CacheQueryError as exc:
            query.reply_err(str(exc))
            return
        wanted = _within(asked.slice)
        if asked.index:
            query.reply(cache_token(self.cache_id), write_index(self._recent.index(wanted)), encoding=self._encoding)
            return
        ranges: dict[tuple[str, str], list[tuple[int, int]]] = {}
        for run, src, first, last in asked.want:
            ranges.setdefault((run, src), []).append((first, last))
        for key, event in self._recent.wanted(ranges, wanted):
            query.reply(key, event, encoding=self._encoding)


def _within(slice_key: str):
    """A test of whether an event key is within the slice asked (remembered per key: a cache holds
    a few keys per source, asked many times)."""
    ke = zenoh.KeyExpr(slice_key)
    seen: dict[str, bool] = {}

    def wanted(key: str) -> bool:
        found = seen.get(key)
        if found is None:
            found = seen[key] = ke.includes(zenoh.KeyExpr(key))
        return found
    return wanted
