"""The report's timeline of an act as values: the reasoner's window of speeds and signal colours
(reasoner/timelines.py's `Timeline`) with what the report adds to it (the vehicle's heading at
the incident, the moments of its passage, its distance to the stop line and the other road
user's speed: explain/act_data.py), built once in explain/report.py and drawn by
svg_timeline.py, report_html.py and report_md.py by attribute.

`to_json` is the JSON the report carries, key for key and in the same order.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from reasoner.timelines import Timeline


@dataclass(frozen=True)
class Moment:
    """A moment of the passage the history found ("crossed the stop line") and when."""

    what: str
    t: int

    def to_json(self) -> dict[str, Any]:
        return {"what": self.what, "t": self.t}


@dataclass(frozen=True)
class LinePoint:
    """The distance `m` before the stop line (negative: past it) at a sample of the passage."""

    t: int
    m: float
    src: str
    seq: int

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "m": self.m, "src": self.src, "seq": self.seq}


@dataclass(frozen=True)
class ToLine:
    """The vehicle's distance to the stop line of its approach over the window."""

    junction: str
    approach: Any
    kind: Any
    points: tuple[LinePoint, ...]

    def to_json(self) -> dict[str, Any]:
        return {"junction": self.junction, "approach": self.approach, "kind": self.kind,
                "points": [p.to_json() for p in self.points]}


@dataclass(frozen=True)
class OtherSpeed:
    """A speed of the other road user, from the event `src` #`seq`."""

    t: int
    speed_mps: float
    src: str
    seq: int

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "speed_mps": self.speed_mps, "src": self.src, "seq": self.seq}


@dataclass(frozen=True)
class OtherParty:
    """The road user the incident's vehicle would force or endanger (`how`, the legend's words),
    with its speed over the window."""

    user: str
    type: Any
    how: str
    vehicle: str
    speed: tuple[OtherSpeed, ...]

    def to_json(self) -> dict[str, Any]:
        return {"user": self.user, "type": self.type, "how": self.how, "vehicle": self.vehicle,
                "speed": [s.to_json() for s in self.speed]}


@dataclass(frozen=True)
class ActTimeline:
    """The reasoner's window around the incident (`window`: its times, speeds and signals) and
    what the report draws beside it."""

    window: Timeline
    heading_deg: float | None = None
    moments: tuple[Moment, ...] = ()
    to_line: ToLine | None = None
    other: OtherParty | None = None

    def to_json(self) -> dict[str, Any]:
        return {**self.window.to_json(), "heading_deg": self.heading_deg,
                "moments": [m.to_json() for m in self.moments],
                "to_line": self.to_line.to_json() if self.to_line else None,
                "other": self.other.to_json() if self.other else None}
