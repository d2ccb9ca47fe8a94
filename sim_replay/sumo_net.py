"""What the simulation needs to know of a SUMO network, read once with sumolib.

SUMO knows lanes, junctions and signal links; the audit speaks of roads, approaches and stop lines
(DESIGN "Events", the run.start map). This module is the one translation between the two, so that
the world (sim_replay.sumo_world), the map (sim_replay.net_map) and the agents all name the same
approach of the same junction the same way:

    road       an edge's `name` (the plain files name edges after the road they belong to); an
               unnamed edge is its own road
    junction   a node where at least three arms meet, or one with signals that two or more roads
               (or directions) come into (a dead end or a bend is not a junction, nor a road end
               that a generator gave a signal)
    approach   an incoming edge of a junction, named as signal.state and the reasoner name it: by
               where its traffic comes from, the compass sector of its stop line seen from the
               junction's centre (reasoner.junctions.sector)
    stop line  across the end of an approach's vehicle lanes, where SUMO stops a vehicle for a red
               light; its kind: "signal" at a signal junction, "stop" or "give_way" where SUMO's link
               says the approach is minor (a priority_stop junction's minor links are Stop lines, a
               priority junction's are Give Way lines); a node's `stop` and `give_way` parameters
               (incoming edge ids) set the kind where SUMO cannot (it has no per-approach sign). A
               major road's approach has no line.
    yellow box a node's `box` parameter, the polygon "x,y x,y ..." (SUMO has no box)

Coordinates are SUMO's (metres, x east, y north); headings here are the map's, degrees
counter-clockwise from east.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import sumolib

from reasoner.history import sector

__all__ = ["Approach", "Crossing", "Junction", "Lane", "Network", "SignalLink", "read_network"]

Point = tuple[float, float]
SIGNAL_TYPES = ("traffic_light", "traffic_light_right_on_red", "traffic_light_unregulated")
MINOR_KIND = {"priority_stop": "stop", "allway_stop": "stop", "priority": "give_way"}
MINOR_STATES = ("s", "m", "w")     # link states of a road that yields (stop, minor, all-way stop)
MAIN_DIRS = ("s", "l", "r", "L", "R", "t")   # which link of an approach shows its colour: straight on first


@dataclass(frozen=True)
class Lane:
    """A lane as the world reads a vehicle's position on it."""

    id: str
    edge: str
    road: str | None          # None inside a junction
    index: int
    width_m: float
    length_m: float
    shape: tuple[Point, ...]
    kind: str                 # road, sidewalk, cycle, crossing, walkingarea, internal
    junction: str | None      # the junction it is inside (internal lanes, crossings, walking areas)
    ahead: str | None         # the junction at its end (a normal lane that ends at one)
    approach: str | None      # the approach it is on at that junction
    line_kind: str | None     # the kind of stop line at its end, None where there is none


@dataclass(frozen=True)
class Approach:
    """One incoming edge of a junction."""

    junction: str
    name: str                 # compass: where its traffic comes from
    edge: str
    road: str | None
    kind: str | None          # signal, stop, give_way; None: a major road's approach, no line
    line: tuple[Point, Point] | None   # across its vehicle lanes' ends
    lanes: tuple[str, ...]    # its vehicle lanes, kerb first


@dataclass(frozen=True)
class Crossing:
    """A pedestrian crossing on one arm of a junction."""

    id: str                   # SUMO's crossing edge (":j1_c0")
    junction: str
    arm: str                  # compass sector of its middle seen from the centre
    shape: tuple[Point, ...]  # its centre line, kerb to kerb
    width_m: float
    priority: bool            # pedestrians have priority over vehicles on it


@dataclass(frozen=True)
class SignalLink:
    """One controlled link of a traffic light: the colour at index `index` of its state."""

    tls: str
    index: int
    junction: str
    approach: str | None      # the vehicle approach it belongs to; None for a crossing
    crossing: str | None
    direction: str            # SUMO's: s straight, l left, r right, t turn, w walk


@dataclass(frozen=True)
class Junction:
    id: str
    x: float
    y: float
    sumo_type: str
    control: str              # lights, stop, give_way, none (the map's)
    shape: tuple[Point, ...]
    approaches: tuple[Approach, ...]
    crossings: tuple[Crossing, ...]
    box: tuple[Point, ...] | None
    tls: str | None

    def approach(self, name: str) -> Approach | None:
        return next((a for a in self.approaches if a.name == name), None)


@dataclass(frozen=True)
class Network:
    """The network's junctions, lanes and signal links, looked up by id."""

    path: Path
    lefthand: bool
    junctions: dict[str, Junction]
    lanes: dict[str, Lane]
    edges_road: dict[str, str]                      # normal edge -> road
    approaches: dict[str, Approach]                 # incoming edge -> its approach
    links: dict[str, tuple[SignalLink, ...]]        # tls -> its links by index
    net: sumolib.net.Net

    def approach_links(self, tls: str) -> dict[str, int]:
        """(junction, approach) key "j1/west" -> the link index whose colour the approach shows."""
        chosen: dict[str, SignalLink] = {}
        for link in self.links.get(tls, ()):
            if link.approach is None:
                continue
            key = f"{link.junction}/{link.approach}"
            best = chosen.get(key)
            if best is None or _rank(link.direction) < _rank(best.direction):
                chosen[key] = link
        return {key: link.index for key, link in chosen.items()}


def read_network(path: str | Path) -> Network:
    """Read a .net.xml (with its internal lanes and crossings) into the simulation's terms."""
    path = Path(path)
    net = sumolib.net.readNet(str(path), withInternal=True, withPedestrianConnections=True)
    junction_ids = {n.getID() for n in net.getNodes() if _is_junction(n)}
    approaches: dict[str, Approach] = {}
    junctions: dict[str, Junction] = {}
    for node in sorted(net.getNodes(), key=lambda n: n.getID()):
        if node.getID() not in junction_ids:
            continue
        node_approaches = tuple(_approach(node, edge) for edge in _incoming(node))
        approaches.update({a.edge: a for a in node_approaches})
        x, y = node.getCoord()[:2]
        junctions[node.getID()] = Junction(
            node.getID(), x, y, node.getType(), _control(node, node_approaches),
            tuple(_xy(p) for p in node.getShape()), node_approaches, _crossings(net, node),
            _polygon(node.getParam("box")), node.getID() if node.getType() in SIGNAL_TYPES else None)
    lanes = {lane.getID(): _lane(lane, junction_ids, approaches) for edge in net.getEdges(withInternal=True)
             for lane in edge.getLanes()}
    roads = {e.getID(): _road(e) for e in net.getEdges(withInternal=False)}
    links = {tls.getID(): _links(tls, approaches) for tls in net.getTrafficLights()}
    return Network(path, _lefthand(path), junctions, lanes, roads, approaches, links, net)


def _rank(direction: str) -> int:
    return MAIN_DIRS.index(direction) if direction in MAIN_DIRS else len(MAIN_DIRS)


def _xy(p) -> Point:
    return (float(p[0]), float(p[1]))


def _is_junction(node) -> bool:
    if node.getType() in ("dead_end", "internal"):
        return False
    neighbours = {e.getFromNode().getID() for e in node.getIncoming() if not e.isSpecial()} | \
                 {e.getToNode().getID() for e in node.getOutgoing() if not e.isSpecial()}
    if node.getType() in SIGNAL_TYPES:      # signals where two ways in meet, or on a road (not at its end)
        return len(_incoming(node)) >= 2
    return len(neighbours - {node.getID()}) >= 3


def _incoming(node) -> list:
    """The incoming edges that carry vehicles, in a stable order."""
    return sorted((e for e in node.getIncoming() if not e.isSpecial() and _vehicle_lanes(e)), key=lambda e: e.getID())


def _vehicle_lanes(edge) -> list:
    return [lane for lane in edge.getLanes() if _lane_kind(lane) in ("road", "cycle")]


def _lane_kind(lane) -> str:
    function = lane.getEdge().getFunction()
    if function in ("crossing", "walkingarea", "internal"):
        return function
    return _permitted_kind(lane)


def _permitted_kind(lane) -> str:
    """road, sidewalk or cycle, by who may use the lane."""
    allowed = lane.getPermissions()
    if allowed == {"pedestrian"}:
        return "sidewalk"
    if allowed <= {"bicycle", "pedestrian"} and "bicycle" in allowed:
        return "cycle"
    return "road"


def _road(edge) -> str:
    return edge.getName() or edge.getID()


def _approach(node, edge) -> Approach:
    lanes = _vehicle_lanes(edge)
    line = _line(lanes)
    mid = ((line[0][0] + line[1][0]) / 2, (line[0][1] + line[1][1]) / 2)
    name = sector(mid[0] - node.getCoord()[0], mid[1] - node.getCoord()[1])
    kind = _kind(node, edge)
    return Approach(node.getID(), name, edge.getID(), _road(edge), kind, line if kind else None,
                    tuple(lane.getID() for lane in lanes))


def _line(lanes) -> tuple[Point, Point]:
    """Across the ends of an approach's lanes: the two outermost of the points half a lane's width
    either side of each lane's end, along the normal to the first lane's last stretch."""
    (x0, y0), (x1, y1) = (p[:2] for p in lanes[0].getShape()[-2:])
    length = math.hypot(x1 - x0, y1 - y0) or 1.0
    nx, ny = -(y1 - y0) / length, (x1 - x0) / length      # the normal (lanes of one edge are parallel at their end)
    points: list[Point] = []
    for lane in lanes:
        ex, ey = lane.getShape()[-1][:2]
        half = lane.getWidth() / 2
        points += [(ex + nx * half, ey + ny * half), (ex - nx * half, ey - ny * half)]
    ordered = sorted(points, key=lambda p: p[0] * nx + p[1] * ny)
    return tuple((round(p[0], 3), round(p[1], 3)) for p in (ordered[0], ordered[-1]))  # type: ignore[return-value]


def _kind(node, edge) -> str | None:
    """The kind of line at the end of an incoming edge (module docstring)."""
    for param, kind in (("stop", "stop"), ("give_way", "give_way")):
        if edge.getID() in (node.getParam(param) or "").split():
            return kind
    if node.getType() in SIGNAL_TYPES:
        return "signal"
    minor = MINOR_KIND.get(node.getType())
    if minor is None:
        return None
    states = {c.getState() for lane in _vehicle_lanes(edge) for c in lane.getOutgoing()}
    return minor if states and states <= set(MINOR_STATES) else None


def _control(node, approaches: tuple[Approach, ...]) -> str:
    kinds = {a.kind for a in approaches}
    if node.getType() in SIGNAL_TYPES:
        return "lights"
    return "stop" if "stop" in kinds else "give_way" if "give_way" in kinds else "none"


def _crossings(net, node) -> tuple[Crossing, ...]:
    found = []
    for edge in sorted(net.getEdges(withInternal=True), key=lambda e: e.getID()):
        if edge.getFunction() != "crossing" or edge.getFromNode().getID() != node.getID():
            continue
        lane = edge.getLanes()[0]
        shape = tuple(_xy(p) for p in lane.getShape())
        mid = ((shape[0][0] + shape[-1][0]) / 2, (shape[0][1] + shape[-1][1]) / 2)
        arm = sector(mid[0] - node.getCoord()[0], mid[1] - node.getCoord()[1])
        found.append(Crossing(edge.getID(), node.getID(), arm, shape, lane.getWidth(),
                              _crossing_priority(net, node, edge)))
    return tuple(found)


def _crossing_priority(net, node, crossing) -> bool:
    """Whether pedestrians have priority on a crossing: SUMO marks the walking area's link onto it
    major ('M') where they have, minor where they wait for a gap (at signals, the light decides)."""
    for edge in net.getEdges(withInternal=True):
        if edge.getFunction() != "walkingarea" or edge.getToNode().getID() != node.getID():
            continue
        for lane in edge.getLanes():
            for c in lane.getOutgoing():
                if c.getToLane().getEdge().getID() == crossing.getID():
                    return c.getState() == "M"
    return False


def _polygon(value: str | None) -> tuple[Point, ...] | None:
    if not value:
        return None
    points = tuple((float(x), float(y)) for x, y in (p.split(",")[:2] for p in value.split()))
    return points if len(points) >= 3 else None


def _lane(lane, junction_ids: set[str], approaches: dict[str, Approach]) -> Lane:
    edge = lane.getEdge()
    kind = _lane_kind(lane)
    if edge.getFunction():
        junction = edge.getID()[1:].rsplit("_", 1)[0]   # SUMO's ":<junction>_<n>"
        if edge.getFunction() == "internal" and junction not in junction_ids:
            return _bend_lane(lane)
        return Lane(lane.getID(), edge.getID(), None, lane.getIndex(), lane.getWidth(), lane.getLength(),
                    tuple(_xy(p) for p in lane.getShape()), kind, junction, None, None, None)
    to = edge.getToNode().getID()
    approach = approaches.get(edge.getID()) if kind in ("road", "cycle") else None
    return Lane(lane.getID(), edge.getID(), _road(edge), lane.getIndex(), lane.getWidth(), lane.getLength(),
                tuple(_xy(p) for p in lane.getShape()), kind, None, to if to in junction_ids else None,
                approach.name if approach else None, approach.kind if approach else None)


def _bend_lane(lane) -> Lane:
    """A lane through a node that is no junction (a bend, or where a road changes its lanes): part of
    the road it comes from, as a driver reads it."""
    before = lane.getIncoming()
    edge = before[0].getEdge() if before else lane.getEdge()
    return Lane(lane.getID(), lane.getEdge().getID(), _road(edge), lane.getIndex(), lane.getWidth(), lane.getLength(),
                tuple(_xy(p) for p in lane.getShape()), _permitted_kind(lane), None, None, None, None)


def _links(tls, approaches: dict[str, Approach]) -> tuple[SignalLink, ...]:
    found: dict[int, SignalLink] = {}
    for in_lane, out_lane, index in tls.getConnections():
        edge = in_lane.getEdge()
        junction = edge.getToNode().getID()
        if edge.getFunction() == "walkingarea":
            crossing = out_lane.getEdge().getID()
            found.setdefault(index, SignalLink(tls.getID(), index, junction, None, crossing, "w"))
            continue
        approach = approaches.get(edge.getID())
        direction = next((c.getDirection() for c in in_lane.getOutgoing() if c.getToLane() is out_lane), "s")
        found.setdefault(index, SignalLink(tls.getID(), index, junction, approach.name if approach else None,
                                           None, direction))
    return tuple(found[i] for i in sorted(found))


def _lefthand(path: Path) -> bool:
    with open(path, encoding="utf-8") as f:
        head = f.read(8192)
    start = head.find("<net ")
    return start >= 0 and 'lefthand="true"' in head[start:head.find(">", start)]
