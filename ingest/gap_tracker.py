"""Sequence gaps seen on the wire, per (run, src).

``seq`` starts at 0 and rises by 1 per source, so a jump means events were lost between producer and ingest.
This is the live, in-memory view; it cannot see a lost tail (nothing arrives after it), which is why the
store keeps its own gap listing over what was committed.
"""
from __future__ import annotations

import bisect
import threading
import time

Range = list[int]  # [first, last], inclusive


class _Source:
    """Highest seq seen, the ranges still missing below it (sorted and disjoint), and when it last
    sent something (monotonic seconds)."""

    __slots__ = ("highest", "missing", "last_seen")

    def __init__(self) -> None:
        self.highest = -1
        self.missing: list[Range] = []
        self.last_seen = 0.0

    def observe(self, seq: int) -> bool:
        """Record ``seq``; return True if it arrived late, filling a gap below the highest seen."""
        if seq > self.highest:
            if seq > self.highest + 1:
                self.missing.append([self.highest + 1, seq - 1])
            self.highest = seq
            return False
        return self._fill(seq)

    def _fill(self, seq: int) -> bool:
        """Remove ``seq`` from the missing ranges (splitting its range); False if it was not missing."""
        i = bisect.bisect_right(self.missing, [seq, float("inf")]) - 1
        if i < 0 or not self.missing[i][0] <= seq <= self.missing[i][1]:
            return False  # seen before: a repeat, which the store counts as a duplicate
        first, last = self.missing.pop(i)
        pieces = [r for r in ([first, seq - 1], [seq + 1, last]) if r[0] <= r[1]]
        self.missing[i:i] = pieces
        return True


class GapTracker:
    """Per-source gap bookkeeping; ``observe`` is called by the writer, ``gaps`` by anyone."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._sources: dict[tuple[str, str], _Source] = {}
        self._now = time.monotonic()

    def tick(self) -> None:
        """Read the clock once for the samples observed next (a batch), not once per sample."""
        self._now = time.monotonic()

    def observe(self, run: str, src: str, seq: int) -> bool:
        """Note an event's seq; returns True if it filled a gap, i.e. arrived out of order."""
        with self._lock:
            source = self._sources.get((run, src))
            if source is None:
                source = self._sources[(run, src)] = _Source()
            source.last_seen = self._now
            return source.observe(seq)

    def observe_all(self, identities: list[tuple[str, str, int]]) -> int:
        """``observe`` each (run, src, seq) of a batch in order, under one lock; returns how many
        arrived late."""
        late = 0
        sources, now = self._sources, self._now
        with self._lock:
            for run, src, seq in identities:
                source = sources.get((run, src))
                if source is None:
                    source = sources[(run, src)] = _Source()
                source.last_seen = now
                late += source.observe(seq)
        return late

    def highest(self, run: str, src: str) -> int | None:
        """The source's highest seq seen, or None if nothing of it arrived: where a liveliness
        change or a loss on the wire sits in its sequence."""
        with self._lock:
            source = self._sources.get((run, src))
            return None if source is None else source.highest

    def sources(self, active_within_s: float) -> tuple[int, int]:
        """(sources seen, sources that sent something in the last ``active_within_s`` seconds).

        "Active" is only what arrived: a source that went quiet is not known to be gone (liveliness
        tokens would tell that), and an event whose key disagreed with its body names no source."""
        cutoff = time.monotonic() - active_within_s
        with self._lock:
            return len(self._sources), sum(s.last_seen >= cutoff for s in self._sources.values())

    def missing(self) -> tuple[int, int]:
        """(sequence numbers missing in all, sources missing any)."""
        with self._lock:
            gappy = [s for s in self._sources.values() if s.missing]
            return sum(last - first + 1 for s in gappy for first, last in s.missing), len(gappy)

    def gaps(self) -> list[dict]:
        """Sources with missing seqs: ``{run, src, missing: [[first, last], ...], highest}``, sorted."""
        with self._lock:
            return [
                {"run": run, "src": src, "missing": [list(r) for r in s.missing], "highest": s.highest}
                for (run, src), s in sorted(self._sources.items())
                if s.missing
            ]
