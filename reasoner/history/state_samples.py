"""Road users' entity.state samples, read once per run and source however many passages ask.

The passages of a run's acts overlap: a queue crosses a junction together, and a road user is
the vehicle of one act and the other road user of the next. Each passage used to read and parse
its window of every source near the junction again; here each source's samples stay parsed, as
one stretch of time per source, and a passage reads only the part of its window not held yet.

What a window gives is what one read of it gives (`Store.source_events` and motion.samples): the
events of the source with t in the window, in (t, seq) order, cut after `cap` events, each kept
as its sample and its note (an event that gave no sample, or less than it carried). The pieces
read are disjoint in time and each in that order, so the stretch is in it too.

Memory is bounded: past MAX_KEPT events, the sources least recently asked for are let go.
"""
from __future__ import annotations

import bisect
from collections import OrderedDict
from dataclasses import dataclass, field

from store import Store

from .motion import Sample, sample_of

MAX_KEPT = 2_000_000       # events kept parsed across sources (a few hundred MB at most)
_Entry = tuple[int, "Sample | None", "str | None"]   # (t, sample, note)


@dataclass
class _Stretch:
    t_from: int
    t_to: int
    entries: list[_Entry] = field(default_factory=list)
    times: list[int] = field(default_factory=list)


@dataclass(frozen=True)
class Window:
    """A source's samples in a window, the notes on its events, and how many events it held."""

    samples: tuple[Sample, ...]
    notes: tuple[str, ...]
    events: int


class StateSamples:
    """Every source's entity.state samples asked for so far in one run."""

    def __init__(self, store: Store, run: str, max_kept: int = MAX_KEPT) -> None:
        self._store, self._run, self._max_kept = store, run, max_kept
        self._kept: OrderedDict[str, _Stretch] = OrderedDict()
        self._size = 0

    def window(self, src: str, t_from: int, t_to: int, cap: int) -> Window:
        """The source's entity.state in [t_from, t_to] (inclusive), its first `cap` events."""
        stretch = self._stretch(src, t_from, t_to)
        lo = bisect.bisect_left(stretch.times, t_from)
        hi = bisect.bisect_right(stretch.times, t_to)
        entries = stretch.entries[lo:min(hi, lo + cap)]      # in (t, seq) order: motion.samples' order
        return Window(tuple(s for _, s, _ in entries if s is not None),
                      tuple(n for _, _, n in entries if n is not None), hi - lo)

    def _stretch(self, src: str, t_from: int, t_to: int) -> _Stretch:
        """The source's stretch, grown to cover the window (or replaced by it, where the two
        are apart)."""
        stretch = self._kept.pop(src, None)
        if stretch is not None and (t_to < stretch.t_from - 1 or t_from > stretch.t_to + 1):
            self._size -= len(stretch.entries)
            stretch = None
        if stretch is None:
            stretch = _Stretch(t_from, t_to, *self._read(src, t_from, t_to))
            self._size += len(stretch.entries)
        else:
            if t_from < stretch.t_from:
                entries, times = self._read(src, t_from, stretch.t_from - 1)
                stretch.entries[:0], stretch.times[:0], stretch.t_from = entries, times, t_from
                self._size += len(entries)
            if t_to > stretch.t_to:
                entries, times = self._read(src, stretch.t_to + 1, t_to)
                stretch.entries += entries
                stretch.times += times
                stretch.t_to = t_to
                self._size += len(entries)
        self._kept[src] = stretch
        while self._size > self._max_kept and len(self._kept) > 1:
            _, gone = self._kept.popitem(last=False)
            self._size -= len(gone.entries)
        return stretch

    def _read(self, src: str, t_from: int, t_to: int) -> tuple[list[_Entry], list[int]]:
        entries: list[_Entry] = []
        for event in self._store.source_events(self._run, src, kinds=["entity.state"], t_from=t_from, t_to=t_to):
            sample, why = sample_of(event)
            entries.append((event["t"], sample,
                            None if why is None else f"{event.get('src')} #{event.get('seq')}: {why}"))
        return entries, [t for t, _, _ in entries]
