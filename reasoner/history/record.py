"""What a history is rebuilt from: one vehicle's measurements, the run's map and signals, the
sequence gaps of the sources, and a way to find the other road users near a junction.

A `Record` is filled either from a store (reasoner/history.py, through the store's public reads)
or from a list of events (tests, a file being looked at before import); reasoner/rebuild.py
reads only the Record, so both give the same passages.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Mapping

from .junctions import Junction, Map
from .motion import Sample
from .signals import Signals
from ..when import format_time

SECOND = 1_000_000_000

Track = tuple[str, tuple[Sample, ...]]                       # (src, samples) of one road user
Others = Callable[[Junction, int, int], Mapping[str, Track]]  # junction, t_from, t_to -> user -> track


@dataclass(frozen=True)
class Gap:
    """Seqs first..last of a source are missing from the record, lost between the events at
    t_before and t_after (None: before its first or after its last stored event)."""

    src: str
    first: int
    last: int
    t_before: int | None
    t_after: int | None

    def overlaps(self, t_from: int, t_to: int) -> bool:
        return (self.t_before is None or self.t_before <= t_to) and (self.t_after is None or self.t_after >= t_from)

    def between(self, seq_a: int, seq_b: int) -> bool:
        """Whether the gap lies between two of the source's events."""
        return seq_a < self.first and self.last < seq_b

    @property
    def words(self) -> str:
        when = (f"between {format_time(self.t_before) if self.t_before is not None else 'its first event'} and "
                f"{format_time(self.t_after) if self.t_after is not None else 'its last event'}")
        span = f"event {self.first}" if self.first == self.last else f"events {self.first} to {self.last}"
        return f"{self.src} {span} missing, {when}"


Spawns = Callable[[str], "dict | None"]                      # road user (id or src) -> its entity.spawn event


def no_others(junction: Junction, t_from: int, t_to: int) -> Mapping[str, Track]:
    return {}


def no_spawns(user: str) -> dict | None:
    return None


Track_of = Callable[[str, int, int], "tuple[Sample, ...] | None"]   # a source's own samples in a window


def no_track(src: str, t_from: int, t_to: int) -> tuple[Sample, ...] | None:
    return None          # None: not read this way (the others of a longer window are looked at)


@dataclass(frozen=True)
class Record:
    """Everything read for one vehicle (its own series are in (t, src, seq) order)."""

    run: str
    vehicle: str
    map: Map
    signals: Signals
    own: tuple[Sample, ...]                 # its entity.state series
    seen: tuple[Sample, ...]                # the monitors' measurements of it
    spawn: dict | None                      # its entity.spawn event
    gaps: tuple[Gap, ...]
    notes: tuple[str, ...] = ()             # values left out, reads cut short
    others: Others = no_others
    window: tuple[int | None, int | None] = (None, None)
    spawns: Spawns = no_spawns              # the other road users' entity.spawn (their type)
    track: Track_of = no_track              # one road user's own entity.state in a window

    def gaps_of(self, srcs: set[str], t_from: int, t_to: int) -> tuple[Gap, ...]:
        return tuple(g for g in self.gaps if g.src in srcs and g.overlaps(t_from, t_to))
