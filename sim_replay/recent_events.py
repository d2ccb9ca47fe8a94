"""What a producer published lately, for every source and kind, in one bounded ring: the cache an
ingest that was down (or that saw a hole) asks for what it missed (store/cache_wire.py).

One ring per producer instead of one Zenoh cache per key: the per-key caches cost the ingest a
queryable declaration per source and kind (docs/serve.md "Recovery"). The ring keeps events for
``max_age_s`` (store.CACHE_S) and never more than ``max_events`` of them nor ``max_bytes`` of their
payloads, dropping the oldest first: a producer publishing faster than the bounds allow keeps less
time, never unbounded memory. The bytes kept are exactly those put on the wire (signed, if signed).

Thread-safe: the producer adds from its thread, the cache's queryable reads from another.
"""
from __future__ import annotations

import threading
import time
from collections import deque
from collections.abc import Callable

from store import SourceSpan

MAX_EVENTS = 1_000_000
MAX_BYTES = 256 * 1024 * 1024
"""The defaults bound a cache to about what a 1,000-vehicle simulation publishes in 10 s
(bench/sim.py: about 16,000 events/s of a few hundred bytes each) with room to spare."""

Source = tuple[str, str]   # (run, src)


class _Held:
    """One event held: its source, seq, key, exact bytes and when it was added (monotonic s)."""

    __slots__ = ("source", "seq", "key", "payload", "at")

    def __init__(self, source: Source, seq: int, key: str, payload: bytes, at: float) -> None:
        self.source, self.seq, self.key, self.payload, self.at = source, seq, key, payload, at


class RecentEvents:
    """The ring: events in the order added, and per source in the same order, for range queries."""

    def __init__(self, max_age_s: float, *, max_events: int = MAX_EVENTS, max_bytes: int = MAX_BYTES,
                 clock: Callable[[], float] = time.monotonic) -> None:
        if max_age_s < 0 or max_events < 1 or max_bytes < 1:
            raise ValueError(f"max_age_s must be >= 0, max_events and max_bytes >= 1, not "
                             f"{max_age_s!r}, {max_events!r}, {max_bytes!r}")
        self.max_age_s, self.max_events, self.max_bytes = max_age_s, max_events, max_bytes
        self._clock = clock
        self._lock = threading.Lock()
        self._order: deque[_Held] = deque()
        self._by_source: dict[Source, deque[_Held]] = {}
        self._bytes = 0

    def __len__(self) -> int:
        return len(self._order)

    @property
    def nbytes(self) -> int:
        """Payload bytes held."""
        return self._bytes

    def add(self, run: str, src: str, seq: int, key: str, payload: bytes) -> None:
        """Keep one published event (and drop what the bounds no longer allow)."""
        now = self._clock()
        source = (run, src)
        held = _Held(source, seq, key, payload, now)
        with self._lock:
            self._order.append(held)
            line = self._by_source.get(source)
            if line is None:
                line = self._by_source[source] = deque()
            line.append(held)
            self._bytes += len(payload)
            self._evict(now)

    def index(self, wanted: Callable[[str], bool] = lambda key: True) -> list[SourceSpan]:
        """Per source with an event whose key is ``wanted``: the lowest and highest seq held."""
        spans = []
        with self._lock:
            self._evict(self._clock())
            for (run, src), line in self._by_source.items():
                seqs = [h.seq for h in line if wanted(h.key)]
                if seqs:
                    spans.append(SourceSpan(run, src, min(seqs), max(seqs)))
        return spans

    def between(self, run: str, src: str, first: int, last: int,
                wanted: Callable[[str], bool] = lambda key: True) -> list[tuple[str, bytes]]:
        """(key, payload) of the source's events held with ``first <= seq <= last`` and a
        ``wanted`` key, in the order they were published."""
        with self._lock:
            self._evict(self._clock())
            line = self._by_source.get((run, src), ())
            return [(h.key, h.payload) for h in line if first <= h.seq <= last and wanted(h.key)]

    def _evict(self, now: float) -> None:
        """Drop the oldest while too many, too big or too old (the lock is held)."""
        order, too_old = self._order, now - self.max_age_s
        while order and (len(order) > self.max_events or self._bytes > self.max_bytes or order[0].at < too_old):
            held = order.popleft()
            self._bytes -= len(held.payload)
            line = self._by_source[held.source]
            line.popleft()          # a source's oldest is the oldest overall of its events
            if not line:
                del self._by_source[held.source]
