"""DESIGN's envelopes for the simulation: seq per source, t from world time, and the lost-event fault.

Every source numbers its events from 0 (DESIGN "Envelope"). `t` is a fixed epoch start plus the
world's time, so a seed reproduces a run's timestamps exactly; nothing here reads the wall clock.
A lost event (faults.Faults.lose) takes its seq and is never delivered: the gap in the source's
numbering is the evidence an ingest and an investigator see.
"""
from __future__ import annotations

from collections.abc import Callable
from typing import Any

__all__ = ["Envelopes", "T0", "SECOND", "Tick", "t_ns"]

T0 = 1_732_262_400_000_000_000     # 2024-11-22T08:00:00Z: fixed, so a seed reproduces the run's times
SECOND = 1_000_000_000


def t_ns(t_s: float) -> int:
    """World seconds as the envelope's t (ns since the epoch), rounded to the microsecond so that
    float noise in the step count never shows."""
    return T0 + round(t_s * 1_000_000) * 1_000


class Tick(list):
    """One tick's events (a list, as before), with `payloads`: each event's canonical bytes
    (store.canonical_json), written by the simulation as it made them, for Outlets.put_all to
    put as they are instead of encoding every event again (the encoding's check of the values is
    half its cost, and the simulation already knows what it rounded). None: not written.
    `zenoh_keys`, with payloads: each event's key (store.key_for's), as the simulation keeps them per
    source, so that a thousand keys a tick are not written out again for the put."""

    __slots__ = ("payloads", "zenoh_keys")

    def __init__(self, events=(), payloads: list[bytes] | None = None, zenoh_keys: list[str] | None = None) -> None:
        super().__init__(events)
        self.payloads = payloads
        self.zenoh_keys = zenoh_keys


class Envelopes:
    """Builds each source's events in order; `lose(src, kind, seq)` says whether one is lost (None:
    none is, without asking per event)."""

    def __init__(self, run: str, lose: Callable[[str, str, int], bool] | None = None) -> None:
        self.run = run
        self.seqs: dict[str, int] = {}
        self.count = 0
        self.lost = 0
        self._lose = lose
        self._t: tuple[float | None, int] = (None, 0)   # the latest (t_s, t): a tick's events share their t_s

    def make(self, src: str, t_s: float, kind: str, body: dict[str, Any]) -> dict[str, Any] | None:
        """The event, or None when the fault model loses it (its seq is used all the same)."""
        seq = self.seqs.get(src, 0)
        self.seqs[src] = seq + 1
        if self._lose is not None and self._lose(src, kind, seq):
            self.lost += 1
            return None
        self.count += 1
        return {"v": 1, "run": self.run, "src": src, "seq": seq, "t": self.stamp(t_s), "kind": kind, "body": body}

    @property
    def lossy(self) -> bool:
        """Whether the fault model may lose events (then each is made by `make`)."""
        return self._lose is not None

    def stamp(self, t_s: float) -> int:
        """The envelope's t for world seconds t_s (t_ns, worked out once per tick)."""
        t_s_was, t = self._t
        if t_s != t_s_was:
            t = t_ns(t_s)
            self._t = (t_s, t)
        return t

    def make_all(self, t_s: float, kind: str, bodies: list[tuple[str, dict[str, Any]]]) -> list[dict[str, Any]]:
        """The events of one kind and time, one per (src, body), in order: `make` for each, without
        its per-call lookups (a tick's entity.states are a thousand of them)."""
        if self._lose is not None or not bodies:
            made = (self.make(src, t_s, kind, body) for src, body in bodies)
            return [ev for ev in made if ev is not None]
        seqs, run, t = self.seqs, self.run, self.stamp(t_s)
        out = []
        for src, body in bodies:
            seq = seqs.get(src, 0)
            seqs[src] = seq + 1
            out.append({"v": 1, "run": run, "src": src, "seq": seq, "t": t, "kind": kind, "body": body})
        self.count += len(out)
        return out
