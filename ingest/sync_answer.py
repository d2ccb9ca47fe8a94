"""The answer to a producer's "has everything I put reached you?" (store.SYNC_KEY), which its close
waits for before it takes its cache away.

Zenoh hands the ingest the question after every sample put before it, so those are in the inbox.
But the cache may still hold what the ingest is about to ask for (a producer that started, or
published, before the ingest's subscription reached it, and closes at once): while the ingest
has caches to ask or answers to take, the question waits, so that the producer keeps its cache
until then (at most WAIT_S: a cache that does not answer must not hold a producer forever).
"""
from __future__ import annotations

import threading
import time
from collections.abc import Callable

import zenoh

from store.wire import SYNC_KEY

WAIT_S = 15.0   # the longest a question waits for the caches to be asked (their answer's timeout is 10 s)


class SyncAnswers:
    """Answers at once when ``idle()``; otherwise parks the question until ``answer_parked`` finds
    the ingest idle, or the question has waited WAIT_S."""

    def __init__(self, idle: Callable[[], bool]) -> None:
        self._idle = idle
        self._lock = threading.Lock()
        self._parked: list[tuple[float, zenoh.Query]] = []

    def __call__(self, query: zenoh.Query) -> None:
        """Zenoh's callback for the sync queryable."""
        if self._idle():
            _reply(query)
            return
        with self._lock:
            self._parked.append((time.monotonic(), query))

    def answer_parked(self) -> None:
        """Answer the questions that may be answered now (the writer calls this between batches)."""
        with self._lock:
            if not self._parked:
                return
            cutoff = time.monotonic() - WAIT_S
            idle = self._idle()
            due = [q for at, q in self._parked if idle or at <= cutoff]
            self._parked = [(at, q) for at, q in self._parked if not (idle or at <= cutoff)]
        for query in due:
            _reply(query)


def _reply(query: zenoh.Query) -> None:
    try:
        query.reply(SYNC_KEY, b"received")
    except zenoh.ZError:   # the asker went away meanwhile
        pass
    finally:
        query.drop()
