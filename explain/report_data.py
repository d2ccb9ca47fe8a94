"""What a report draws of the scene at an incident, built once as values (explain/picture_parts.py)
from the reasoner's scene and the store's reading of the run map.

The SVG modules (svg_scene.py, svg_lanes.py) only draw these values, and the JSON report carries
their `to_json`, so what a reader sees in the picture is exactly what the data says.
Producers write the map and the states; nothing here trusts their shape: a number that is not a
finite number is left out rather than drawn somewhere wrong, and every string is kept as recorded
(the renderers escape it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Any

from reasoner.scene import Reported, scene
from store import Store
from store.run_map import MapJunction, read_map_body, whole, whole_line
from store.run_map import finite_number as number      # a finite number, else None: what a picture can place

from .picture_parts import (CrossingDrawn, JunctionDrawn, LaneDrawn, MapDrawn, MonitorDrawn, Mover, Picture,
                            RoadDrawn, SignalDrawn, StopLineDrawn)
from .presence import presence_at

SECOND = 1_000_000_000
LANES_NEAR_M = 150.0     # a picture carries the lanes this close to what it shows (svg_scene zooms closer)
NEAR_JUNCTION_M = 40.0   # a road user this close to a junction's centre is at it, for focus_junction
# approach named by where traffic comes from (as sim_replay names them): its direction from the junction
APPROACH_DIRECTIONS = {"west": 180.0, "w": 180.0, "south": 270.0, "s": 270.0, "east": 0.0, "e": 0.0,
                       "north": 90.0, "n": 90.0}


def run_start_body(store: Store, run: str) -> dict[str, Any]:
    """The body of the run's run.start (its map, its rulebooks), or {} for a run without one."""
    start = next(iter(store.events(run, kinds=["run.start"])), None)
    body = (start or {}).get("body")
    return body if isinstance(body, dict) else {}


@dataclass(frozen=True)
class RecordedRulebook:
    """A rulebook as the run's run.start recorded it: name, sha256 and version (no text); each the
    recorded value as text, or None."""

    name: str | None
    sha256: str | None
    version: str | None


def recorded_rulebooks(start_body: dict[str, Any]) -> list[RecordedRulebook]:
    """The rulebooks the run recorded in its run.start (a producer's JSON, read here once)."""
    return [RecordedRulebook(_text(b.get("name")), _text(b.get("sha256")), _text(b.get("version")))
            for b in _dicts(start_body.get("rulebooks"))]


def run_map(start_body: dict[str, Any]) -> MapDrawn:
    """The map the run recorded in its run.start (DESIGN "Events", read by store.read_map_body),
    its entries that can be drawn: roads, junctions (with their stop lines, yellow box, outline
    and crossings when the producer sent them), monitors, and the lanes as polylines with their
    widths (a SUMO run's; a map without them, like the paper's hand-written one, has none and the
    picture draws its roads)."""
    given = read_map_body(start_body)
    roads = []
    for r in given.roads:
        a, b = whole(r.a), whole(r.b)
        if a and b:
            roads.append(RoadDrawn(r.label, a, b))
    junctions = tuple(_junction(j) for j in given.junctions)
    lanes = []
    for lane in given.lanes:
        shape, width = whole_line(lane.shape), lane.width_m
        if len(shape) >= 2 and width is not None and width > 0:
            lanes.append(LaneDrawn(lane.label, lane.kind, width, shape))
    return MapDrawn(tuple(roads), tuple(j for j in junctions if j is not None),
                    tuple(m.raw for m in given.monitors), tuple(lanes), given.lefthand)


def _junction(j: MapJunction) -> JunctionDrawn | None:
    """A junction's drawable parts (None without a centre); a stop line, crossing or outline that
    is not numbers is left out."""
    if j.x is None or j.y is None:
        return None
    lines = []
    for line in j.stop_lines or ():
        a, b = whole(line.a), whole(line.b)
        if a and b:
            lines.append(StopLineDrawn(line.approach_label, a, b, _text(line.kind)))
    crossings = []
    for c in j.crossings:
        shape, width = whole_line(c.shape), c.width_m
        if len(shape) >= 2 and width is not None and width > 0:
            crossings.append(CrossingDrawn(c.label, shape, width))
    box, outline = whole_line(j.box), whole_line(j.shape)
    return JunctionDrawn(j.label, j.x, j.y, j.control_label, tuple(lines), box if len(box) >= 3 else None,
                         outline if len(outline) >= 3 else None, tuple(crossings))


# --- the picture at t -----------------------------------------------------------------------------

def scene_picture(store: Store, run: str, t: int, vehicle: str | None, the_map: MapDrawn | None = None,
                  junction: str | None = None) -> Picture:
    """Roads and lanes, junctions, signal colours per approach, vehicles and road users with
    position, heading and speed (and whether that position is fresh enough to draw: presence.py),
    and each monitor's field of view, at t. `vehicle` is the incident's (None: a scene without
    one, as `gaps scene --svg` draws it); `junction` the one to zoom to (None: the vehicle's, else
    the busiest, see focus_junction)."""
    the_map = the_map if the_map is not None else run_map(run_start_body(store, run))
    sc = scene(store, run, t, judge=False)
    vehicles = tuple(_mover(v.vehicle, v.type, v.state, t, vehicle=True, junction=_field(v.state, "junction"),
                            incident=v.vehicle == vehicle) for v in sc.vehicles)
    users = tuple(_mover(u.src, u.type, u.state, t, vehicle=False) for u in sc.road_users)
    monitors = []
    for m in sc.monitors:
        cone = m.entry
        monitors.append(MonitorDrawn(m.monitor, m.placed("junction"), cone.x if cone else None,
                                     cone.y if cone else None, cone.heading_deg if cone else None,
                                     cone.fov_deg if cone else None, cone.range_m if cone else None,
                                     tuple(m.observed), vehicle is not None and vehicle in m.observed))
    signals = tuple(SignalDrawn(s.junction, s.approach, s.colour, s.since.t, s.evidence) for s in sc.signals)
    picture = Picture(t, sc.offset, vehicle, the_map.roads, the_map.lanes, the_map.lefthand, the_map.junctions,
                      signals, tuple(monitors), vehicles, users, sc.note)
    picture = replace(picture, junction=junction if junction is not None else focus_junction(picture))
    return replace(picture, lanes=lanes_near(picture, picture.lanes))


def _field(state: Reported | None, name: str) -> Any:
    return None if state is None else state.field(name)


def _mover(ident: str, kind: Any, state: Reported | None, t: int, *, vehicle: bool, junction: Any = None,
           incident: bool = False) -> Mover:
    """A road user as the picture draws it: its position, heading and speed as numbers (or None),
    the evidence of its position and whether that is fresh enough to draw (presence.py)."""
    evidence = state.evidence if state is not None else None
    present, age_s = presence_at(evidence, t)
    return Mover(ident, kind, number(_field(state, "x")), number(_field(state, "y")),
                 number(_field(state, "heading_deg")), number(_field(state, "speed_mps")), vehicle, junction,
                 incident, evidence, present, age_s)


def name_users(picture: Picture, named: list[str], the_map: MapDrawn) -> Picture:
    """The picture with the road users the incident names (explain/act_data.named_users) marked:
    it holds them in view (svg_scene._focus), so it carries the lanes around them too."""
    marked = replace(picture, named=tuple(named))
    return replace(marked, lanes=lanes_near(marked, the_map.lanes))


def lanes_near(picture: Picture, lanes: tuple[LaneDrawn, ...]) -> tuple[LaneDrawn, ...]:
    """The lanes within LANES_NEAR_M of the focus junction, the incident's vehicle and the road
    users the incident names: the most a picture zoomed to them can show. A whole city's network
    (netconvert from OpenStreetMap) is thousands of lanes, and the JSON report carries each
    incident's picture as it is."""
    named = set(picture.named or ())
    centres = [(j.x, j.y) for j in picture.junctions if j.id == picture.junction]
    centres += [(v.x, v.y) for v in picture.movers
                if (v.incident or str(v.id) in named) and v.x is not None and v.y is not None]
    if not centres:
        return lanes

    def near(lane: LaneDrawn) -> bool:
        xs, ys = [p[0] for p in lane.shape], [p[1] for p in lane.shape]
        return any(min(xs) - LANES_NEAR_M <= x <= max(xs) + LANES_NEAR_M and
                   min(ys) - LANES_NEAR_M <= y <= max(ys) + LANES_NEAR_M for x, y in centres)
    return tuple(lane for lane in lanes if near(lane))


def focus_junction(picture: Picture) -> str | None:
    """The junction a picture zooms to: the incident vehicle's (vehicle_junction); without an
    incident vehicle, the one with the most road users present within NEAR_JUNCTION_M of it (the
    first on the map on a tie), so that `gaps scene --svg` shows where things happen."""
    if picture.vehicle is not None:
        return vehicle_junction(picture)
    if not picture.junctions:
        return None
    here = [(u.x, u.y) for u in picture.movers if u.x is not None and u.y is not None and u.present]

    def crowd(j: JunctionDrawn) -> int:
        return sum(math.hypot(x - j.x, y - j.y) <= NEAR_JUNCTION_M for x, y in here)
    return max(picture.junctions, key=crowd).id     # max keeps the first of equals


def vehicle_junction(picture: Picture) -> str | None:
    """The junction the incident is about: the one the vehicle is in, else the one of a monitor
    watching it, else the nearest on the map."""
    me = picture.me
    if me and isinstance(me.junction, str):
        return me.junction
    for m in picture.monitors:
        if m.watching and isinstance(m.junction, str):
            return m.junction
    if me and me.x is not None and me.y is not None and picture.junctions:
        x, y = me.x, me.y
        return min(picture.junctions, key=lambda j: math.hypot(j.x - x, j.y - y)).id
    return None


def facing_approach(heading_deg: float | None, approaches: list[str]) -> str | None:
    """The approach a vehicle heading this way comes in on (a vehicle heading east comes from the
    west), when the approaches are named by compass point; else None."""
    if heading_deg is None:
        return None
    came_from = (heading_deg + 180.0) % 360.0
    named = [a for a in approaches if isinstance(a, str) and a.lower() in APPROACH_DIRECTIONS]
    if not named:
        return None
    return min(named, key=lambda a: _angle_between(APPROACH_DIRECTIONS[a.lower()], came_from))


# --- helpers --------------------------------------------------------------------------------------

def _dicts(value: Any) -> list[dict]:
    return [v for v in value if isinstance(v, dict)] if isinstance(value, list) else []


def _text(value: Any) -> str | None:
    return None if value is None else str(value)


def _angle_between(a: float, b: float) -> float:
    d = abs(a - b) % 360.0
    return min(d, 360.0 - d)
