"""Sequence gaps seen on the wire, per (run, src).

``seq`` starts at 0 and rises by 1 per source, so a jump means events were lost between producer and ingest.
This is the live, in-memory view; it cannot see a lost tail (nothing arrives after it), which is why the
store keeps its own gap listing over what was committed.
"""
from __future__ import annotations

import bisect
import threading
import time
from collections.abc import Callable, Iterable

Range = list[int]  # [first, last], inclusive


class _Source:
    """Highest seq seen, the ranges still missing below it (sorted and disjoint), when it last
    sent something (monotonic seconds), and its highest seq as the writer's last look at the
    wire found it (``before``, valid in look ``look``: see GapTracker.highest_before)."""

    __slots__ = ("highest", "missing", "last_seen", "before", "look")

    def __init__(self) -> None:
        self.highest = -1
        self.missing: list[Range] = []
        self.last_seen = 0.0
        self.before = -1
        self.look = -1

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
        self._srcs: dict[str, list[str]] = {}   # run -> its srcs in _sources: releasing a run costs its own
        self._let_go = 0   # sources of ended runs released with nothing missing (still counted as seen)
        self._now = time.monotonic()
        self._look = 0   # how many times the writer looked at the wire (new_look)
        self.stored_highest: Callable[[str, str], int | None] = lambda run, src: None
        """Set by the writer once its store is open: a source first heard after a restart goes on
        from its highest seq stored, so what an earlier ingest stored is not counted missing."""

    def tick(self) -> None:
        """Read the clock once for the samples observed next (a batch), not once per sample."""
        self._now = time.monotonic()

    def observe(self, run: str, src: str, seq: int) -> bool:
        """Note an event's seq; returns True if it filled a gap, i.e. arrived out of order."""
        with self._lock:
            source = self._sources.get((run, src)) or self._new_source(run, src)
            source.last_seen = self._now
            if source.look != self._look:
                source.before, source.look = source.highest, self._look
            return source.observe(seq)

    def observe_all(self, identities: list[tuple[str, str, int]]) -> int:
        """``observe`` each (run, src, seq) of a batch in order, under one lock; returns how many
        arrived late."""
        late = 0
        sources, now, look = self._sources, self._now, self._look
        with self._lock:
            for run, src, seq in identities:
                source = sources.get((run, src)) or self._new_source(run, src)
                source.last_seen = now
                if source.look != look:
                    source.before, source.look = source.highest, look
                late += source.observe(seq)
        return late

    def _new_source(self, run: str, src: str) -> _Source:
        """A source first heard, going on from its highest seq stored (under the lock)."""
        source = self._sources[(run, src)] = _Source()
        self._srcs.setdefault(run, []).append(src)
        stored = self.stored_highest(run, src)
        if stored is not None:
            source.highest = stored
        return source

    def release(self, runs: Iterable[str]) -> None:
        """Forget the sources of runs that ended (their run.end stored) or went quiet, keeping those
        with seqs missing (what `gaps()` lists): a fleet's ended runs must cost nothing for ever. A
        later event of such a source goes on from its highest seq stored, as after a restart. Costs
        the released runs' own sources, however many other runs are held."""
        sources = self._sources
        with self._lock:
            for run in set(runs):
                kept = []
                for src in self._srcs.pop(run, ()):
                    if sources[(run, src)].missing:
                        kept.append(src)
                    else:
                        del sources[(run, src)]
                        self._let_go += 1
                if kept:
                    self._srcs[run] = kept

    def quiet_runs(self, quiet_s: float) -> list[str]:
        """Runs none of whose sources has sent anything for ``quiet_s`` seconds (by the clock of
        the batches observed): a run that never sends its run.end is released once it is this
        quiet. A walk over the sources held, made once in a while (BatchWriter), not per event."""
        cutoff = time.monotonic() - quiet_s
        sources = self._sources
        with self._lock:
            return [run for run, srcs in self._srcs.items()
                    if all(sources[(run, src)].last_seen < cutoff for src in srcs)]

    def highest(self, run: str, src: str) -> int | None:
        """The source's highest seq seen (or stored, if nothing of it arrived since the start), or
        None if there is none: the upper bound of where a liveliness change sits in its
        sequence, once every sample received before the change is written."""
        with self._lock:
            source = self._sources.get((run, src))
            return self.stored_highest(run, src) if source is None else _seq_or_none(source.highest)

    def highest_before(self, run: str, src: str) -> int | None:
        """The source's highest seq as it stood at the writer's previous look at the wire
        (``new_look``): the lower bound of where a change noticed at this look sits. Every event
        written before that look arrived before the change did (the change was not there yet),
        while events written since may have arrived after it, in the same take."""
        with self._lock:
            source = self._sources.get((run, src))
            if source is None:
                return self.stored_highest(run, src)
            return _seq_or_none(source.before if source.look == self._look else source.highest)

    def new_look(self) -> None:
        """The writer has looked at the wire: what is observed from now on is after this look."""
        with self._lock:
            self._look += 1

    def sources(self, active_within_s: float) -> tuple[int, int]:
        """(sources seen, sources that sent something in the last ``active_within_s`` seconds).

        "Active" is only what arrived: a source that went quiet is not known to be gone (liveliness
        tokens would tell that), and an event whose key disagreed with its body names no source."""
        cutoff = time.monotonic() - active_within_s
        with self._lock:
            return len(self._sources) + self._let_go, sum(s.last_seen >= cutoff for s in self._sources.values())

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


def _seq_or_none(seq: int) -> int | None:
    return None if seq < 0 else seq
