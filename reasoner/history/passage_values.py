"""One vehicle's passage through one junction, as the record shows it: the values a history
hands to derived facts, margins and (later) the investigation and the explanations.

Every figure keeps the samples or signal reports it was read from (store.EventRef), and every
moment found between two samples says so in `method`; what the record cannot settle is said in
`uncertain`, never guessed silently. reasoner/history.py builds these; nothing here computes.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from store import EventRef

from .junctions import Junction, StopLine
from .motion import Braking, Sample
from .sensors import Sensor
from .signals import Light

SECOND = 1_000_000_000


def _refs(refs) -> list[dict[str, Any]]:
    return [r.to_json() for r in refs]


@dataclass(frozen=True)
class Moment:
    """A moment of the passage, found between (or at) samples."""

    t: int
    used: tuple[Sample, ...]
    method: str
    uncertain: str | None = None

    @property
    def refs(self) -> tuple[EventRef, ...]:
        return tuple(s.ref for s in self.used)

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "method": self.method, "uncertain": self.uncertain, "evidence": _refs(self.refs)}


@dataclass(frozen=True)
class Crossing:
    """When the vehicle crossed its stop line and what its light showed then. `light_changed`
    holds the signal changes within the two samples' interval: then the colour depends on the
    interpolation, and `uncertain` says so."""

    moment: Moment
    before_m: float                 # metres before the line at the sample before
    past_m: float                   # metres past the line at the sample after
    speed_mps: float | None
    light: Light | None
    light_changed: tuple[Light, ...]
    light_uncertain: str | None

    @property
    def t(self) -> int:
        return self.moment.t

    def to_json(self) -> dict[str, Any]:
        return {**self.moment.to_json(), "before_m": round(self.before_m, 3), "past_m": round(self.past_m, 3),
                "speed_mps": _round(self.speed_mps), "light": self.light.to_json() if self.light else None,
                "light_changed_between_samples": [c.to_json() for c in self.light_changed],
                "light_uncertain": self.light_uncertain}


@dataclass(frozen=True)
class AtChange:
    """Where the vehicle was, and how fast, when its light changed during the passage."""

    light: Light
    previous: str | None
    to_line_m: float | None         # metres before the line (negative: past it)
    speed_mps: float | None
    used: tuple[Sample, ...]
    method: str

    def to_json(self) -> dict[str, Any]:
        return {"light": self.light.to_json(), "previous": self.previous, "to_line_m": _round(self.to_line_m),
                "speed_mps": _round(self.speed_mps), "method": self.method, "evidence": _refs(s.ref for s in self.used)}


@dataclass(frozen=True)
class Standstill:
    """Consecutive samples at which the vehicle stood still (speed rounds to 0 mph); the
    duration is between the first and the last of them, so a lower bound."""

    first: Sample
    last: Sample
    samples: int
    to_line_m: float | None
    at_line: bool

    @property
    def duration_s(self) -> float:
        return (self.last.t - self.first.t) / SECOND

    def to_json(self) -> dict[str, Any]:
        return {"from": self.first.t, "to": self.last.t, "duration_s": round(self.duration_s, 3),
                "samples": self.samples, "to_line_m": _round(self.to_line_m), "at_line": self.at_line,
                "evidence": [self.first.ref.to_json(), self.last.ref.to_json()]}


@dataclass(frozen=True)
class Other:
    """Another road user near the conflict point (the junction's centre) while the vehicle
    passed: where it came from, how hard it braked, whether it stopped."""

    user: str
    src: str
    samples: tuple[Sample, ...]
    arm: str | None                  # the arm it was first seen on
    closing: bool                    # ... getting closer to the centre: its approach
    main_road: bool | None
    closest_m: float
    braking: Braking | None
    stopped: Sample | None
    light: Light | None              # what its own signal showed when it braked or stopped
    type: str | None = None          # its entity.spawn's type (pedestrian, cyclist, car ...)
    spawn: EventRef | None = None    # ... and that event
    followed: str | None = None      # the road user ahead of it that explains its braking or stop
    own_stop_line: bool = False      # it braked or stopped before a Stop line of its own arm
    path: tuple[Sample, ...] = ()    # its way through the junction, read on past `samples` where
                                     # they end before it left (rebuild.PATH_AFTER_S, and STAND_ON_S
                                     # for one still standing then); else empty
    counted_from: int | None = None  # its reaction is counted from here, and so is the slowing it ended
                                     # (reaction.slowing_began): a stop of its own, apart (others.stop_apart)

    @property
    def way(self) -> tuple[Sample, ...]:
        """The samples its way through the junction is read from."""
        return self.path or self.samples

    def to_json(self) -> dict[str, Any]:
        return {"user": self.user, "src": self.src, "type": self.type, "arm": self.arm, "closing": self.closing,
                "main_road": self.main_road, "followed": self.followed, "own_stop_line": self.own_stop_line,
                "closest_m": round(self.closest_m, 2), "braking": self.braking.to_json() if self.braking else None,
                "stopped": self.stopped.ref.to_json() if self.stopped else None,
                "light": self.light.to_json() if self.light else None, "samples": len(self.samples)}


@dataclass(frozen=True)
class Passage:
    """One vehicle's passage through one junction, rebuilt from the record."""

    run: str
    vehicle: str
    junction: Junction
    approach: str | None
    approach_method: str
    line: StopLine | None
    start: int
    end: int
    series: str                     # which measurements the positions come from
    samples: tuple[Sample, ...]
    lights: tuple[Light, ...]       # facing the approach: the one showing at start, then each change
    changes: tuple[AtChange, ...]   # each change before the crossing (or the end), with where V was
    crossing: Crossing | None
    past_line_at_start: bool        # first seen already past its line: the crossing is not in the record
    standstills: tuple[Standstill, ...]
    entered: Moment | None
    left: Moment | None
    exit: str | None                # the arm it left by
    limit_mph: float | None
    limit_road: str | None
    emergency: tuple[tuple[int, bool, EventRef], ...]   # on or off an emergency call, from when
    vehicle_type: str | None
    spawn: EventRef | None
    others: tuple[Other, ...]
    uncertain: tuple[str, ...]
    map_ref: EventRef | None
    first_report: EventRef | None = None   # its signal's first report in the run: a colour showing
                                           # then began at or before it (only a bound is recorded)
    roads: tuple[tuple[int, str, float | None], ...] = ()   # (from t, road, limit mph) along lead and samples
    lead: tuple[Sample, ...] = ()   # its own samples read before the passage began, and after it
    trail: tuple[Sample, ...] = ()  # ended: a speeding stretch that reaches into or out of it
    sensors: tuple[tuple[str, Sensor], ...] = ()   # (src, its stated tolerance) of each source that states
                                                   # one (reasoner/sensors.py); the others are held to the defaults
    same_approach: tuple[Other, ...] = ()   # road users on its own approach, going its way (not among
                                            # `others`): weighed only as what another braked for (attribution.py)

    def evidence(self) -> frozenset[EventRef]:
        """Every event the passage rests on: no derived fact may cite another."""
        refs = {s.ref for s in self.samples + self.lead + self.trail} | {light.ref for light in self.lights}
        refs |= {s.ref for other in self.others + self.same_approach for s in other.way}
        refs |= {o.light.ref for o in self.others if o.light} | {ref for _, _, ref in self.emergency}
        refs |= {o.spawn for o in self.others if o.spawn is not None}
        refs |= {r for r in (self.map_ref, self.spawn) if r is not None}
        if self.crossing and self.crossing.light:
            refs.add(self.crossing.light.ref)
        return frozenset(refs)

    def to_json(self) -> dict[str, Any]:
        return {
            "run": self.run, "vehicle": self.vehicle, "junction": self.junction.to_json(),
            "approach": self.approach, "approach_method": self.approach_method,
            "stop_line": self.line.to_json() if self.line else None, "start": self.start, "end": self.end,
            "series": self.series, "samples": [s.to_json() for s in self.samples],
            "lights": [light.to_json() for light in self.lights], "changes": [c.to_json() for c in self.changes],
            "crossing": self.crossing.to_json() if self.crossing else None,
            "past_line_at_start": self.past_line_at_start,
            "standstills": [s.to_json() for s in self.standstills],
            "entered": self.entered.to_json() if self.entered else None,
            "left": self.left.to_json() if self.left else None, "exit": self.exit,
            "limit_mph": self.limit_mph, "limit_road": self.limit_road,
            "emergency": [{"t": t, "on_call": on, "evidence": ref.to_json()} for t, on, ref in self.emergency],
            "vehicle_type": self.vehicle_type, "spawn": self.spawn.to_json() if self.spawn else None,
            "others": [o.to_json() for o in self.others], "uncertain": list(self.uncertain),
            "map": self.map_ref.to_json() if self.map_ref else None,
            "first_signal_report": self.first_report.to_json() if self.first_report else None,
            "roads": [{"from": t, "road": road, "limit_mph": limit} for t, road, limit in self.roads],
            "lead": len(self.lead), "trail": len(self.trail),
            **({"sensors": {src: sensor.to_json() for src, sensor in self.sensors}} if self.sensors else {}),
        }


def _round(value: float | None, digits: int = 3) -> float | None:
    return None if value is None else round(value, digits)
