"""What each signal showed and when: the signal.state record of a run as timelines per junction
and approach (DESIGN: `approach` names where traffic comes from; a signal.state without one
speaks for every approach of its junction).

A timeline keeps the changes only: a signal that repeats its colour every second has changed
once, at its first report of it, and that report is the evidence for "since when".
"""
from __future__ import annotations

import bisect
from dataclasses import dataclass, field
from typing import Any, Iterable

from store import EventRef

COLOURS = ("red", "red_amber", "amber", "green", "off")
WORDS = {"red": ("red",), "red_amber": ("red", "amber"), "amber": ("amber",), "green": ("green",), "off": ()}
MAX_SIGNAL_EVENTS = 500_000
ANY = ""                      # the approach of a signal.state that names none


@dataclass(frozen=True)
class Light:
    """A signal began showing `colour` at t (the report `ref`)."""

    t: int
    colour: str
    ref: EventRef

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "colour": self.colour, "evidence": self.ref.to_json()}


@dataclass(frozen=True)
class Signals:
    """The run's signal timelines by (junction, approach), each a tuple of changes in time order."""

    lines: dict[tuple[str, str], tuple[Light, ...]] = field(default_factory=dict)
    problems: tuple[str, ...] = ()

    def timeline(self, junction: str, approach: str | None) -> tuple[Light, ...]:
        """The lights facing an approach: its own signal's, and any signal of the junction that
        names no approach."""
        own = self.lines.get((junction, approach or ANY), ()) if approach else ()
        shared = self.lines.get((junction, ANY), ())
        if not shared or not own:
            return own or shared
        return _changes(sorted(own + shared, key=lambda light: (light.t, light.ref.seq)))

    def sources(self, junction: str, approach: str | None) -> set[str]:
        return {light.ref.src for light in self.timeline(junction, approach)}


def read_signals(events: Iterable[dict]) -> Signals:
    """Timelines from signal.state events (any order; others ignored, at most MAX_SIGNAL_EVENTS)."""
    reports: dict[tuple[str, str], list[Light]] = {}
    problems: list[str] = []
    for n, event in enumerate(events):
        if n >= MAX_SIGNAL_EVENTS:
            problems.append(f"more than {MAX_SIGNAL_EVENTS} signal reports: the rest are not read")
            break
        body = event.get("body") if isinstance(event, dict) else None
        if event.get("kind") != "signal.state" or not isinstance(body, dict):
            continue
        junction, colour, approach = body.get("junction"), body.get("colour"), body.get("approach")
        if not isinstance(junction, str) or colour not in COLOURS:
            problems.append(f"{event.get('src')} #{event.get('seq')}: not a junction and a colour")
            continue
        key = (junction, approach if isinstance(approach, str) and approach else ANY)
        reports.setdefault(key, []).append(Light(event["t"], colour, EventRef.of(event)))
    lines = {key: _changes(sorted(found, key=lambda light: (light.t, light.ref.seq, light.ref.src)))
             for key, found in reports.items()}
    return Signals(lines, tuple(problems[:20]))


def _changes(reports: list[Light]) -> tuple[Light, ...]:
    out: list[Light] = []
    for light in reports:
        if not out or out[-1].colour != light.colour:
            out.append(light)
    return tuple(out)


def shown(timeline: tuple[Light, ...], t: int) -> Light | None:
    """The light showing at t: the latest change at or before it."""
    i = bisect.bisect_right(timeline, t, key=lambda light: light.t)
    return timeline[i - 1] if i else None


def changed_between(timeline: tuple[Light, ...], t_from: int, t_to: int) -> tuple[Light, ...]:
    """The changes within (t_from, t_to]."""
    lo = bisect.bisect_right(timeline, t_from, key=lambda light: light.t)
    hi = bisect.bisect_right(timeline, t_to, key=lambda light: light.t)
    return timeline[lo:hi]
