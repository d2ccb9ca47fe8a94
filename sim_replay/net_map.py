"""The run.start `map` of a SUMO network: what the reasoner measures against and the pictures draw.

DESIGN's map is `{"roads", "junctions", "monitors"}` in metres; reasoner.junctions reads it. From a
network this writes, in that shape:

    roads      one per road (an edge's `name`), from end to end, with its speed limit in mph; a
               road that bends is cut where it bends, since the reasoner reads a road as a segment
    junctions  id, centre, control (lights, stop, give_way, none), the stop line of every approach
               that has one (approach, from, to, kind, and the SUMO edge and road it ends), `major`
               (the approaches without a line where others have one), the yellow `box` polygon,
               and, for pictures, SUMO's outline (`shape`), its `approaches` and its `crossings`
    monitors   the monitors file's (sim_replay.monitors)
    lanes      every lane outside the junctions as a polyline with its width and kind (road,
               sidewalk, cycle), for pictures and viewers
    network    which SUMO network this is (file name, sha256, left-hand traffic)

Coordinates are rounded to the millimetre, so the same network always gives the same map, byte for
byte, and a run's first event does not carry float noise.
"""
from __future__ import annotations

import hashlib
import math
from collections.abc import Sequence
from typing import Any

from reasoner.history import MPH_PER_MPS
from sim_replay.monitors import Monitor
from sim_replay.sumo_net import Junction, Network

__all__ = ["world_map"]

Point = tuple[float, float]
COLLINEAR_DEG = 1.0          # two stretches of a road this close in direction are one segment


def world_map(network: Network, monitors: Sequence[Monitor] = ()) -> dict[str, Any]:
    """The map run.start carries for a network and its monitors."""
    return {
        "network": {"file": network.path.name, "sha256": hashlib.sha256(network.path.read_bytes()).hexdigest(),
                    "lefthand": network.lefthand},
        "roads": _roads(network),
        "junctions": [_junction(j) for j in network.junctions.values()],
        "monitors": [m.to_json() for m in monitors],
        "lanes": [{"id": lane.id, "edge": lane.edge, "road": lane.road, "index": lane.index, "kind": lane.kind,
                   "width_m": _r(lane.width_m), "shape": [_p(p) for p in lane.shape]}
                  for lane in sorted(network.lanes.values(), key=lambda lane: lane.id) if lane.junction is None],
    }


def _r(value: float) -> float:
    return round(value, 3) + 0.0    # (+ 0.0 turns -0.0 into 0.0)


# DESIGN's stop-line kinds: the line at signals, a Stop sign's line, a Give Way line (the network
# reader's own "stop" is the Stop sign's; a bare "stop" in a map would be read by the junction's control)
MAP_KIND = {"signal": "signal", "stop": "stop_sign", "give_way": "give_way"}


def _map_kind(kind: str | None) -> str | None:
    """The map's word for an approach's line kind (an approach with a line has one)."""
    return MAP_KIND.get(kind, kind) if kind is not None else None


def _p(point: Point) -> list[float]:
    return [_r(point[0]), _r(point[1])]


def _junction(j: Junction) -> dict[str, Any]:
    lined = [(a, a.line) for a in j.approaches if a.line is not None]
    out: dict[str, Any] = {
        "id": j.id, "x": _r(j.x), "y": _r(j.y), "control": j.control,
        "stop_lines": [{"approach": a.name, "from": _p(line[0]), "to": _p(line[1]),
                        "kind": _map_kind(a.kind), "edge": a.edge, "road": a.road} for a, line in lined],
    }
    if j.control != "lights" and lined and len(lined) < len(j.approaches):
        out["major"] = sorted({a.name for a in j.approaches if a.line is None})
    if j.box is not None:
        out["box"] = [_p(p) for p in j.box]
    out["sumo_type"] = j.sumo_type
    out["shape"] = [_p(p) for p in j.shape]
    out["approaches"] = [{"name": a.name, "edge": a.edge, "road": a.road} for a in j.approaches]
    out["crossings"] = [{"id": c.id, "arm": c.arm, "shape": [_p(p) for p in c.shape], "width_m": _r(c.width_m),
                         "priority": c.priority} for c in j.crossings]
    return out


def _roads(network: Network) -> list[dict[str, Any]]:
    """One entry per straight run of a road: the road's edges (each direction counted once) joined
    end to end while they keep their direction and speed limit."""
    segments: list[tuple[str, Point, Point, float]] = []
    seen: set[tuple[str, str]] = set()
    net = network.net
    for edge in sorted(net.getEdges(withInternal=False), key=lambda e: e.getID()):
        if not any(lane.getPermissions() - {"pedestrian"} for lane in edge.getLanes()):
            continue                                   # a footpath is not a road
        ends = (edge.getFromNode().getID(), edge.getToNode().getID())
        if tuple(sorted(ends)) in seen:
            continue
        seen.add(tuple(sorted(ends)))
        shape = [(float(x), float(y)) for x, y, *_ in edge.getRawShape()]
        limit = edge.getSpeed()
        for a, b in zip(shape, shape[1:]):
            if a != b:
                segments.append((network.edges_road[edge.getID()], a, b, limit))
    merged = _merge(segments)
    return [{"id": road, "from": _p(a), "to": _p(b), "speed_limit_mph": round(limit * MPH_PER_MPS)}
            for road, a, b, limit in merged]


def _merge(segments: list[tuple[str, Point, Point, float]]) -> list[tuple[str, Point, Point, float]]:
    """Join segments of the same road and limit that meet end to end in a straight line, where no
    third segment of that road meets them."""
    ends: dict[tuple[str, Point], list[int]] = {}
    for n, (road, a, b, _) in enumerate(segments):
        ends.setdefault((road, a), []).append(n)
        ends.setdefault((road, b), []).append(n)
    alive = dict(enumerate(segments))
    changed = True
    while changed:
        changed = False
        for road, point in list(ends):
            members = [m for m in ends[road, point] if m in alive]
            ends[road, point] = members
            if len(members) != 2:
                continue
            s, t = alive[members[0]], alive[members[1]]
            if s[3] != t[3]:
                continue
            far_s = s[1] if s[2] == point else s[2]
            far_t = t[1] if t[2] == point else t[2]
            if not _straight(far_s, point, far_t):
                continue
            del alive[members[1]]
            alive[members[0]] = (road, far_s, far_t, s[3]) if far_s <= far_t else (road, far_t, far_s, s[3])
            ends[road, point] = []
            ends[road, far_t] = [members[0] if m == members[1] else m for m in ends[road, far_t]]
            changed = True
    return sorted(alive.values(), key=lambda s: (s[0], s[1], s[2]))


def _straight(a: Point, via: Point, b: Point) -> bool:
    """Whether a -> via -> b goes on without turning (within COLLINEAR_DEG)."""
    h1 = math.atan2(via[1] - a[1], via[0] - a[0])
    h2 = math.atan2(b[1] - via[1], b[0] - via[0])
    turn = abs((math.degrees(h2 - h1) + 180.0) % 360.0 - 180.0)
    return turn <= COLLINEAR_DEG
