"""The scene picture's parts as values: what report_data.py builds once from the reasoner's scene
and the store's reading of the run map, and what svg_scene.py, svg_lanes.py, report_html.py and
report_md.py draw or list, by attribute.

Each part's `to_json` is the JSON the report carries (docs/report.md), key for key and in the
same order, so `gaps report -o r.json` holds exactly what the picture draws. Recorded strings
(ids, kinds, types, colours) are kept as recorded: the renderers escape them.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from store import EventRef

Point = tuple[float, float]


def listed(points: tuple[Point, ...]) -> list[list[float]]:
    """Points as the JSON report carries them: [x, y] lists."""
    return [list(p) for p in points]


@dataclass(frozen=True)
class RoadDrawn:
    """A road of a map without lanes, drawn as a band from `a` to `b`."""

    id: str | None
    a: Point
    b: Point

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "from": list(self.a), "to": list(self.b)}


@dataclass(frozen=True)
class StopLineDrawn:
    """An approach's stop line: `a` at the centre line, `b` at the kerb."""

    approach: str | None
    a: Point
    b: Point
    kind: str | None

    def to_json(self) -> dict[str, Any]:
        return {"approach": self.approach, "from": list(self.a), "to": list(self.b), "kind": self.kind}


@dataclass(frozen=True)
class CrossingDrawn:
    """A pedestrian crossing: its centre line and width."""

    id: str | None
    shape: tuple[Point, ...]
    width_m: float

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "shape": listed(self.shape), "width_m": self.width_m}


@dataclass(frozen=True)
class JunctionDrawn:
    """A junction's centre and the parts of it the map gives: stop lines, yellow box, outline
    (None: not given as three points or more) and crossings."""

    id: str | None
    x: float
    y: float
    control: str | None
    stop_lines: tuple[StopLineDrawn, ...] = ()
    box: tuple[Point, ...] | None = None
    shape: tuple[Point, ...] | None = None
    crossings: tuple[CrossingDrawn, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "x": self.x, "y": self.y, "control": self.control,
                "stop_lines": [line.to_json() for line in self.stop_lines],
                "box": listed(self.box) if self.box is not None else None,
                "shape": listed(self.shape) if self.shape is not None else None,
                "crossings": [c.to_json() for c in self.crossings]}


@dataclass(frozen=True)
class LaneDrawn:
    """A lane as a polyline at its width; `kind` as the map names it ("road", "sidewalk", ...)."""

    id: str | None
    kind: str | None
    width_m: float
    shape: tuple[Point, ...]

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "kind": self.kind, "width_m": self.width_m, "shape": listed(self.shape)}


@dataclass(frozen=True)
class MapDrawn:
    """The run's map as a picture can draw it (report_data.run_map)."""

    roads: tuple[RoadDrawn, ...] = ()
    junctions: tuple[JunctionDrawn, ...] = ()
    monitors: tuple[Any, ...] = ()         # the map's monitor entries as recorded
    lanes: tuple[LaneDrawn, ...] = ()
    lefthand: bool = True

    def to_json(self) -> dict[str, Any]:
        return {"roads": [r.to_json() for r in self.roads], "junctions": [j.to_json() for j in self.junctions],
                "monitors": list(self.monitors), "lanes": [lane.to_json() for lane in self.lanes],
                "lefthand": self.lefthand}


@dataclass(frozen=True)
class SignalDrawn:
    """The colour one approach of a junction showed at the moment, since when, and its report."""

    junction: str
    approach: str
    colour: str
    since_t: int
    evidence: EventRef | None = None

    def to_json(self) -> dict[str, Any]:
        return {"junction": self.junction, "approach": self.approach, "colour": self.colour,
                "since_t": self.since_t, "evidence": self.evidence.to_json() if self.evidence else None}


@dataclass(frozen=True)
class MonitorDrawn:
    """A monitor's place and field of view (None where the map gives none), what it observed and
    whether it watched the incident's vehicle."""

    id: str
    junction: Any                 # the map entry's, as recorded
    x: float | None
    y: float | None
    heading_deg: float | None
    fov_deg: float | None
    range_m: float | None
    observed: tuple[str, ...] = ()
    watching: bool = False

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "junction": self.junction, "x": self.x, "y": self.y,
                "heading_deg": self.heading_deg, "fov_deg": self.fov_deg, "range_m": self.range_m,
                "observed": list(self.observed), "watching": self.watching}


@dataclass(frozen=True)
class Mover:
    """A vehicle (`vehicle` True) or another road user at the moment: position, heading and speed
    (numbers, or None), the event they were reported in, and whether that report is fresh enough
    to draw (presence.py: `present`, `age_s`). Only a vehicle has a `junction` and can be the
    incident's."""

    id: str
    type: Any
    x: float | None
    y: float | None
    heading_deg: float | None = None
    speed_mps: float | None = None
    vehicle: bool = True
    junction: Any = None
    incident: bool = False
    evidence: EventRef | None = None
    present: bool = True
    age_s: float | None = None

    @property
    def placed(self) -> bool:
        return self.x is not None and self.y is not None

    @property
    def drawn(self) -> bool:
        """Placed, and present at the moment (presence.py): what a picture shows."""
        return self.placed and self.present

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"id": self.id, "type": self.type, "x": self.x, "y": self.y,
                               "heading_deg": self.heading_deg, "speed_mps": self.speed_mps}
        if self.vehicle:
            out.update(junction=self.junction, incident=self.incident)
        return {**out, "evidence": self.evidence.to_json() if self.evidence else None, "present": self.present,
                "age_s": self.age_s}


@dataclass(frozen=True)
class Picture:
    """The scene at t as the report draws it: the map's parts near what it shows, the signals,
    monitors, vehicles and road users; `vehicle` the incident's (None: `gaps scene --svg`),
    `junction` the one it zooms to, `named` the road users the incident names (None: not asked)."""

    t: int
    offset: str
    vehicle: str | None
    roads: tuple[RoadDrawn, ...] = ()
    lanes: tuple[LaneDrawn, ...] = ()
    lefthand: bool = True
    junctions: tuple[JunctionDrawn, ...] = ()
    signals: tuple[SignalDrawn, ...] = ()
    monitors: tuple[MonitorDrawn, ...] = ()
    vehicles: tuple[Mover, ...] = ()
    road_users: tuple[Mover, ...] = ()
    note: str | None = None
    junction: str | None = None
    named: tuple[str, ...] | None = None

    @property
    def movers(self) -> tuple[Mover, ...]:
        """The vehicles, then the other road users."""
        return self.vehicles + self.road_users

    @property
    def me(self) -> Mover | None:
        """The incident's vehicle, if the scene holds it."""
        return next((v for v in self.vehicles if v.incident), None)

    def to_json(self) -> dict[str, Any]:
        out = {"t": self.t, "offset": self.offset, "vehicle": self.vehicle,
               "roads": [r.to_json() for r in self.roads], "lanes": [lane.to_json() for lane in self.lanes],
               "lefthand": self.lefthand, "junctions": [j.to_json() for j in self.junctions],
               "signals": [s.to_json() for s in self.signals], "monitors": [m.to_json() for m in self.monitors],
               "vehicles": [v.to_json() for v in self.vehicles],
               "road_users": [u.to_json() for u in self.road_users], "note": self.note, "junction": self.junction}
        if self.named is not None:
            out["named"] = list(self.named)
        return out
