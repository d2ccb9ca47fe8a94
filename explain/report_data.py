"""What a report draws, as plain JSON-ready data: the picture of the scene at an incident (from
the reasoner's scene and the store's reading of the run map) and the timeline of speed and signal
colour around it (the reasoner's, reasoner/timelines.py).

The SVG modules (svg_scene.py, svg_timeline.py) only draw these dicts, and the JSON report
carries them as they are, so what a reader sees in the picture is exactly what the data says.
Producers write the map and the states; nothing here trusts their shape: a number that is not a
finite number is left out rather than drawn somewhere wrong, and every string is kept as recorded
(the renderers escape it).
"""
from __future__ import annotations

import math
from typing import Any

from reasoner.scene import Reported, scene
from reasoner.timelines import timeline as speed_and_signals
from store import Store
from store.run_map import MapJunction, read_map_body, whole, whole_line
from store.run_map import finite_number as number      # a finite number, else None: what a picture can place

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


def recorded_rulebooks(start_body: dict[str, Any]) -> list[dict[str, Any]]:
    """The rulebooks the run recorded in its run.start: name, sha256 and version (no text)."""
    return [{"name": _text(b.get("name")), "sha256": _text(b.get("sha256")), "version": _text(b.get("version"))}
            for b in _dicts(start_body.get("rulebooks"))]


def run_map(start_body: dict[str, Any]) -> dict[str, Any]:
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
            roads.append({"id": r.label, "from": list(a), "to": list(b)})
    junctions = [_junction(j) for j in given.junctions if j.x is not None and j.y is not None]
    lanes = []
    for lane in given.lanes:
        shape, width = whole_line(lane.shape), lane.width_m
        if len(shape) >= 2 and width is not None and width > 0:
            lanes.append({"id": lane.label, "kind": lane.kind, "width_m": width, "shape": _listed(shape)})
    return {"roads": roads, "junctions": junctions, "monitors": [m.raw for m in given.monitors],
            "lanes": lanes, "lefthand": given.lefthand}


def _junction(j: MapJunction) -> dict[str, Any]:
    """A junction's drawable parts; a stop line, crossing or outline that is not numbers is left out."""
    lines = []
    for line in j.stop_lines or ():
        a, b = whole(line.a), whole(line.b)
        if a and b:
            lines.append({"approach": line.approach_label, "from": list(a), "to": list(b),
                          "kind": _text(line.kind)})
    crossings = []
    for c in j.crossings:
        shape, width = whole_line(c.shape), c.width_m
        if len(shape) >= 2 and width is not None and width > 0:
            crossings.append({"id": c.label, "shape": _listed(shape), "width_m": width})
    box, outline = whole_line(j.box), whole_line(j.shape)
    return {"id": j.label, "x": j.x, "y": j.y, "control": j.control_label,
            "stop_lines": lines, "box": _listed(box) if len(box) >= 3 else None,
            "shape": _listed(outline) if len(outline) >= 3 else None, "crossings": crossings}


def _listed(points: tuple[tuple[float, float], ...]) -> list[list[float]]:
    """Points as the JSON report carries them: [x, y] lists."""
    return [list(p) for p in points]


# --- the picture at t -----------------------------------------------------------------------------

def scene_picture(store: Store, run: str, t: int, vehicle: str | None, the_map: dict | None = None,
                  junction: str | None = None) -> dict[str, Any]:
    """Roads and lanes, junctions, signal colours per approach, vehicles and road users with
    position, heading and speed (and whether that position is fresh enough to draw: presence.py),
    and each monitor's field of view, at t. `vehicle` is the incident's (None: a scene without
    one, as `gaps scene --svg` draws it); `junction` the one to zoom to (None: the vehicle's, else
    the busiest, see focus_junction)."""
    the_map = the_map if the_map is not None else run_map(run_start_body(store, run))
    sc = scene(store, run, t, judge=False)
    vehicles = []
    for v in sc.vehicles:
        vehicles.append({"id": v.vehicle, "type": v.type, **_motion(v.state), "junction": _field(v.state, "junction"),
                         "incident": v.vehicle == vehicle, **_seen(v.state, t)})
    users = [{"id": u.src, "type": u.type, **_motion(u.state), **_seen(u.state, t)} for u in sc.road_users]
    monitors = []
    for m in sc.monitors:
        cone = m.entry
        monitors.append({"id": m.monitor, "junction": m.placed("junction"), "x": cone.x if cone else None,
                         "y": cone.y if cone else None, "heading_deg": cone.heading_deg if cone else None,
                         "fov_deg": cone.fov_deg if cone else None, "range_m": cone.range_m if cone else None,
                         "observed": list(m.observed), "watching": vehicle is not None and vehicle in m.observed})
    signals = [{"junction": s.junction, "approach": s.approach, "colour": s.colour,
                "since_t": s.since.t, "evidence": s.evidence.to_json()} for s in sc.signals]
    picture = {"t": t, "offset": sc.offset, "vehicle": vehicle, "roads": the_map["roads"],
               "lanes": the_map.get("lanes", []), "lefthand": the_map.get("lefthand", True),
               "junctions": the_map["junctions"], "signals": signals, "monitors": monitors,
               "vehicles": vehicles, "road_users": users, "note": sc.note}
    picture["junction"] = junction if junction is not None else focus_junction(picture)
    picture["lanes"] = lanes_near(picture, picture["lanes"])
    return picture


def _field(state: Reported | None, name: str) -> Any:
    return None if state is None else state.field(name)


def _motion(state: Reported | None) -> dict[str, float | None]:
    """A road user's position, heading and speed as the picture draws them: numbers, or None."""
    return {"x": number(_field(state, "x")), "y": number(_field(state, "y")),
            "heading_deg": number(_field(state, "heading_deg")), "speed_mps": number(_field(state, "speed_mps"))}


def _seen(state: Reported | None, t: int) -> dict[str, Any]:
    """The evidence of a road user's position, and whether it is fresh enough to draw (presence.py)."""
    evidence = state.evidence.to_json() if state is not None else None
    return {"evidence": evidence, **presence_at(evidence, t)}


def name_users(picture: dict[str, Any], named: list[str], the_map: dict[str, Any]) -> None:
    """Mark the road users the incident names (explain/act_data.named_users): the picture holds
    them in view (svg_scene._focus), so it carries the lanes around them too."""
    picture["named"] = list(named)
    picture["lanes"] = lanes_near(picture, the_map.get("lanes", []))


def lanes_near(picture: dict[str, Any], lanes: list[dict]) -> list[dict]:
    """The lanes within LANES_NEAR_M of the focus junction, the incident's vehicle and the road
    users the incident names: the most a picture zoomed to them can show. A whole city's network
    (netconvert from OpenStreetMap) is thousands of lanes, and the JSON report carries each
    incident's picture as it is."""
    named = set(picture.get("named") or ())
    centres = [(j["x"], j["y"]) for j in picture["junctions"] if j["id"] == picture["junction"]]
    centres += [(v["x"], v["y"]) for v in picture["vehicles"] + picture["road_users"]
                if (v.get("incident") or str(v["id"]) in named) and v["x"] is not None and v["y"] is not None]
    if not centres:
        return lanes

    def near(lane: dict) -> bool:
        xs, ys = [p[0] for p in lane["shape"]], [p[1] for p in lane["shape"]]
        return any(min(xs) - LANES_NEAR_M <= x <= max(xs) + LANES_NEAR_M and
                   min(ys) - LANES_NEAR_M <= y <= max(ys) + LANES_NEAR_M for x, y in centres)
    return [lane for lane in lanes if near(lane)]


def focus_junction(picture: dict[str, Any]) -> str | None:
    """The junction a picture zooms to: the incident vehicle's (vehicle_junction); without an
    incident vehicle, the one with the most road users present within NEAR_JUNCTION_M of it (the
    first on the map on a tie), so that `gaps scene --svg` shows where things happen."""
    if picture["vehicle"] is not None:
        return vehicle_junction(picture)
    if not picture["junctions"]:
        return None
    here = [u for u in picture["vehicles"] + picture["road_users"]
            if u["x"] is not None and u["y"] is not None and u.get("present", True)]

    def crowd(j: dict[str, Any]) -> int:
        return sum(math.hypot(u["x"] - j["x"], u["y"] - j["y"]) <= NEAR_JUNCTION_M for u in here)
    return max(picture["junctions"], key=crowd)["id"]     # max keeps the first of equals


def vehicle_junction(picture: dict[str, Any]) -> str | None:
    """The junction the incident is about: the one the vehicle is in, else the one of a monitor
    watching it, else the nearest on the map."""
    me = next((v for v in picture["vehicles"] if v["incident"]), None)
    if me and isinstance(me.get("junction"), str):
        return me["junction"]
    for m in picture["monitors"]:
        if m["watching"] and isinstance(m.get("junction"), str):
            return m["junction"]
    if me and me["x"] is not None and picture["junctions"]:
        return min(picture["junctions"], key=lambda j: math.hypot(j["x"] - me["x"], j["y"] - me["y"]))["id"]
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


# --- the timeline around t ------------------------------------------------------------------------

def timeline(store: Store, run: str, t: int, vehicle: str, junction: str | None) -> dict[str, Any]:
    """The vehicle's speed and its junction's signal colours around t, as the reasoner reads them
    (reasoner/timelines.py), in the JSON the report carries and svg_timeline.py draws."""
    return speed_and_signals(store, run, t, vehicle, junction).to_json()


# --- helpers --------------------------------------------------------------------------------------

def _dicts(value: Any) -> list[dict]:
    return [v for v in value if isinstance(v, dict)] if isinstance(value, list) else []


def _text(value: Any) -> str | None:
    return None if value is None else str(value)


def _angle_between(a: float, b: float) -> float:
    d = abs(a - b) % 360.0
    return min(d, 360.0 - d)
