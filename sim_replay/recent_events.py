"""What a producer published lately, for every source and kind, in one bounded ring: the cache an
ingest that was down (or that saw a hole) asks for what it missed (store/cache_wire.py).

One ring per producer instead of one Zenoh cache per key: the per-key caches cost the ingest a
queryable declaration per source and kind (docs/serve.md "Recovery"). The ring keeps events for
``max_age_s`` (store.CACHE_S) and never more than ``max_events`` of them nor ``max_bytes`` of their
payloads, dropping the oldest first: a producer publishing faster than the bounds allow keeps less
time, never unbounded memory. The bytes kept are exactly those put on the wire (signed, if signed).

One thread adds (the producer's); any thread may read (the cache's queryable): a reader copies the
ring in one step, which the GIL makes atomic, and looks through the copy, so the producer's add
takes no lock. A read goes through the whole ring (about 160,000 events for 10 s of a 1,000-vehicle
simulation: tens of milliseconds), which is rare: an ingest's restart, or a hole.
"""
from __future__ import annotations

import time
from collections import deque
from collections.abc import Callable, Sequence
from typing import Final

from store.wire import SourceSpan

MAX_EVENTS = 1_000_000
MAX_BYTES = 256 * 1024 * 1024
"""The defaults bound a cache to about what a 1,000-vehicle simulation publishes in 10 s
(bench/sim.py: about 16,000 events/s of a few hundred bytes each) with room to spare."""

Source = tuple[str, str]   # (run, src)
Held = tuple[float, str, str, int, str, bytes]
"""One event held: when it was added (monotonic s), its run, src, seq, key and exact bytes. A tuple
of strings and numbers, which Python's collector stops tracking (objects of a class made each add
cost three times as much in collections, measured)."""
RUN: Final = 1      # a Held's fields by place (0 is when it was added); Final, so a checker knows each one's type
SRC: Final = 2
SEQ: Final = 3
KEY: Final = 4
PAYLOAD: Final = 5
Published = tuple[str, str, int, str, bytes]
"""One event as added: run, src, seq, key and exact bytes."""
Chunk = tuple[float, list[Published], int]
"""One add_all's events: when they were added, them, and their payloads' bytes. Kept together, so
that a tick's thousand events are dropped for their age in one step, not one by one (a popleft
an event was a fifth of a simulation's put, measured); the list is never changed once kept."""


class RecentEvents:
    """The ring, in the order events were added."""

    def __init__(self, max_age_s: float, *, max_events: int = MAX_EVENTS, max_bytes: int = MAX_BYTES,
                 clock: Callable[[], float] = time.monotonic) -> None:
        if max_age_s < 0 or max_events < 1 or max_bytes < 1:
            raise ValueError(f"max_age_s must be >= 0, max_events and max_bytes >= 1, not "
                             f"{max_age_s!r}, {max_events!r}, {max_bytes!r}")
        self.max_age_s, self.max_events, self.max_bytes = max_age_s, max_events, max_bytes
        self._clock = clock
        self._order: deque[Chunk] = deque()
        self._bytes = 0
        self._count = 0

    def __len__(self) -> int:
        return len(self._held())

    @property
    def nbytes(self) -> int:
        """Payload bytes held (dropped by age only as the producer adds)."""
        return self._bytes

    def add(self, run: str, src: str, seq: int, key: str, payload: bytes) -> None:
        """Keep one published event (and drop what the bounds no longer allow). The producer's
        thread only."""
        self.add_all(((run, src, seq, key, payload),))

    def add_all(self, published: Sequence[Published]) -> None:
        """``add`` each (run, src, seq, key, payload) of a run of puts, at one reading of the
        clock and with one look at the bounds, kept as one chunk (Chunk)."""
        if not published:
            return
        now = self._clock()
        kept = list(published)
        size = sum([len(p[4]) for p in kept])
        order = self._order
        order.append((now, kept, size))
        self._bytes += size
        self._count += len(kept)
        if self._count > self.max_events or self._bytes > self.max_bytes or order[0][0] < now - self.max_age_s:
            self._evict(now)

    def index(self, wanted: Callable[[str], bool] = lambda key: True) -> list[SourceSpan]:
        """Per source with an event whose key is ``wanted``: the lowest and highest seq held."""
        spans: dict[Source, list[int]] = {}
        for held in self._held():
            if wanted(held[KEY]):
                seq, span = held[SEQ], spans.get((held[RUN], held[SRC]))
                if span is None:
                    spans[(held[RUN], held[SRC])] = [seq, seq]
                elif seq < span[0]:
                    span[0] = seq
                elif seq > span[1]:
                    span[1] = seq
        return [SourceSpan(run, src, first, last) for (run, src), (first, last) in spans.items()]

    def between(self, run: str, src: str, first: int, last: int,
                wanted: Callable[[str], bool] = lambda key: True) -> list[tuple[str, bytes]]:
        """(key, payload) of the source's events held with ``first <= seq <= last`` and a
        ``wanted`` key, in the order they were published."""
        return self.wanted({(run, src): [(first, last)]}, wanted)

    def wanted(self, ranges: dict[Source, list[tuple[int, int]]],
               wanted: Callable[[str], bool] = lambda key: True) -> list[tuple[str, bytes]]:
        """(key, payload) of the events held whose source has a range holding their seq, in the
        order they were published (one pass for any number of sources)."""
        out: list[tuple[str, bytes]] = []
        for held in self._held():
            found = ranges.get((held[RUN], held[SRC]))
            if found and any(a <= held[SEQ] <= b for a, b in found) and wanted(held[KEY]):
                out.append((held[KEY], held[PAYLOAD]))
        return out

    def _held(self) -> list[Held]:
        """A copy of the ring without what is too old by now (the chunks copied in one C-level step,
        atomic under the GIL; a chunk's list is never changed), one Held per event."""
        chunks = list(self._order)
        too_old = self._clock() - self.max_age_s
        return [(at, *event) for at, events, _ in chunks if at >= too_old for event in events]

    def _evict(self, now: float) -> None:
        """Drop the oldest while too many, too big or too old: a chunk too old at once, else (too
        many, too big) its events from the first."""
        order, too_old = self._order, now - self.max_age_s
        while order and (self._count > self.max_events or self._bytes > self.max_bytes or order[0][0] < too_old):
            at, events, size = order[0]
            if at < too_old:
                order.popleft()
                self._count -= len(events)
                self._bytes -= size
                continue
            dropped = 0
            while dropped < len(events) and (self._count > self.max_events or self._bytes > self.max_bytes):
                gone = len(events[dropped][4])
                self._count -= 1
                self._bytes -= gone
                size -= gone
                dropped += 1
            if dropped == len(events):
                order.popleft()
            else:
                order[0] = (at, events[dropped:], size)
