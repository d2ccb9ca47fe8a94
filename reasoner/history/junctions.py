"""The map as a history reads it: junctions with their stop lines, area, yellow box and major
road; roads with their speed limits (DESIGN "Events", the run.start `map`).

A producer describes a junction as it can, so each piece is read from what the map gives, and
says where it came from (`*_source`), because a derived fact cites it:

    stop lines  `stop_lines` [{approach, from, to, kind}] (DESIGN); else `stop_line_m`, the
                distance of every approach's line from the centre (a map with no line geometry); else none
    area        `box_m`, the half-size of the square "in the junction" (a map that gives only the
                junction's extent); else the
                distance of the nearest stop line from the centre (a disc); else a 10 m disc
    yellow box  `box`: a polygon [[x, y], ...], or true for the junction's whole area (HC 174);
                `box_m` is not a yellow box, only the junction's extent
    major road  `major`: the approaches (or road ids) of the major road; else, where stop lines
                carry a kind, every approach without a Stop or Give Way line; else unknown

Approaches are named, as signal.state names them, by where traffic comes from: a vehicle west of
the centre comes from the west. Coordinates are metres, headings degrees counter-clockwise from
east (the run.start map's convention, which the simulation follows). Nothing here trusts a value: a NaN, a string or a number
beyond 10,000 km is left out and the map's `problems` say so.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Iterable

from store import EventRef
from store.run_map import MapJunction, MapMonitor, MapStopLine, Pair, RunMap, read_run_map

from .sensors import Sensor, stated

Point = tuple[float, float]

COMPASS = ("east", "north", "west", "south")
UNIT = {"east": (1.0, 0.0), "north": (0.0, 1.0), "west": (-1.0, 0.0), "south": (0.0, -1.0)}
KINDS = ("signal", "stop_sign", "give_way")   # DESIGN's stop-line kinds (diagrams 1001, 1002.1, 1003)
MINOR_KINDS = ("stop_sign", "give_way")
CONTROL_OF_KIND = {"signal": "lights", "stop_sign": "stop", "give_way": "give_way"}
# A producer's word for a line, read as DESIGN's kind; "stop" alone is read by the junction's
# control (below: _kind_read), since "the stop line" is as much the line at signals as a Stop sign's.
SYNONYMS = {"give way": "give_way", "signals": "signal", "traffic_light": "signal", "stop sign": "stop_sign"}
STOP_BY_CONTROL = {"lights": "signal", "stop": "stop_sign"}
MAX_COORD_M = 1e7            # 10,000 km: anything further is not a position on a road map
DEFAULT_EXTENT_M = 10.0      # "in the junction" within 10 m of the centre, when the map says nothing
ROAD_SNAP_M = 15.0           # a position this close to a road (two lanes and a verge) is on it
MAX_JUNCTIONS = 10_000
MAX_ROADS = 100_000
MAX_LINES = 64               # stop lines of one junction
CELL_M = 200.0               # the grid that finds junctions near a position
NO_LANES = frozenset({"roads", "junctions", "monitors"})   # the lanes are the pictures'
ARM_CHECK_M = 25.0           # an arm counts as watched when a monitor's cone covers this point out along it


def finite(value: Any, bound: float = MAX_COORD_M) -> float | None:
    """A number a measurement can be: an int or float (not a bool, not a string), finite,
    within bound (NaN fails every comparison, an infinity the bound)."""
    kind = type(value)
    if kind is float:
        return value if -bound <= value <= bound else None
    if kind is int:
        return float(value) if -bound <= value <= bound else None
    return None


def point(value: Pair | None) -> Point | None:
    """A point of the store's map reading (store.read_run_map) within MAX_COORD_M, else None."""
    if value is not None:
        x, y = finite(value[0]), finite(value[1])
        if x is not None and y is not None:
            return (x, y)
    return None


def sector(dx: float, dy: float) -> str:
    """The compass approach of a point seen from the centre: where traffic there comes from."""
    angle = math.degrees(math.atan2(dy, dx))
    if -45.0 <= angle < 45.0:
        return "east"
    if 45.0 <= angle < 135.0:
        return "north"
    if -135.0 <= angle < -45.0:
        return "south"
    return "west"


def heading_sector(heading_deg: float) -> str:
    """The approach of a vehicle heading this way: heading east, it comes from the west."""
    rad = math.radians(heading_deg)
    return sector(-math.cos(rad), -math.sin(rad))


@dataclass(frozen=True)
class StopLine:
    """One approach's stop line. `outward` is the unit normal pointing away from the centre, so
    that `to_line` is positive before the line and negative past it."""

    approach: str
    a: Point
    b: Point
    kind: str              # DESIGN's kind (KINDS), "" where the map gives none, else the producer's word
    source: str
    outward: Point
    segment: bool          # a segment from the map (lateral extent known), or a whole arm
    reading: str | None = None   # how the producer's word was read, where it was not DESIGN's own

    def to_line(self, x: float, y: float) -> float:
        """Metres still to go to the line (negative: past it)."""
        return (x - self.a[0]) * self.outward[0] + (y - self.a[1]) * self.outward[1]

    def alongside(self, x: float, y: float, slack_m: float = 3.0) -> bool:
        """Whether a position lies in front of the line's extent (always, for a whole arm)."""
        if not self.segment:
            return True
        dx, dy = self.b[0] - self.a[0], self.b[1] - self.a[1]
        length = math.hypot(dx, dy)
        along = ((x - self.a[0]) * dx + (y - self.a[1]) * dy) / length
        return -slack_m <= along <= length + slack_m

    def to_json(self) -> dict[str, Any]:
        out = {"approach": self.approach, "from": list(self.a), "to": list(self.b), "kind": self.kind,
               "source": self.source}
        if self.reading:
            out["reading"] = self.reading
        return out


@dataclass(frozen=True)
class Junction:
    id: str
    x: float
    y: float
    control: str
    lines: tuple[StopLine, ...]
    extent_m: float
    extent_square: bool
    extent_source: str
    box: tuple[Point, ...] | None          # the yellow box polygon; None with boxed: the whole area
    boxed: bool
    major: frozenset[str] | None
    major_source: str
    monitors: tuple[str, ...]              # srcs of the monitors the map puts at this junction
    ref: EventRef | None = None            # the run.start that described it
    unwatched: frozenset[str] = frozenset()  # arms no monitor's cone covers (ARM_CHECK_M out from the centre)

    def distance(self, x: float, y: float) -> float:
        return math.hypot(x - self.x, y - self.y)

    def edge(self, x: float, y: float) -> float:
        """Metres outside the junction's area (negative inside), for interpolating entry."""
        if self.extent_square:
            return max(abs(x - self.x), abs(y - self.y)) - self.extent_m
        return self.distance(x, y) - self.extent_m

    def inside(self, x: float, y: float) -> bool:
        """Whether a position is in the junction's area. Most positions asked about are tens of
        metres out: a position further than the extent along either axis is outside the square
        and the disc alike (a hypotenuse is never shorter than a side), so they are turned away
        before the distance is computed."""
        dx, dy, extent = x - self.x, y - self.y, self.extent_m
        if dx > extent or dx < -extent or dy > extent or dy < -extent:
            return False
        return self.edge(x, y) <= 0.0

    def in_box(self, x: float, y: float) -> bool:
        if not self.boxed:
            return False
        return self.inside(x, y) if self.box is None else _in_polygon(x, y, self.box)

    def line_for(self, approach: str | None) -> StopLine | None:
        return next((line for line in self.lines if line.approach == approach), None)

    def control_from(self, approach: str | None) -> str:
        """The control traffic from this approach meets: its line's kind where the line has one
        (a junction may have a Stop arm and a Give Way arm, its `control` naming only one);
        "none" for an arm without a line where the other lines carry kinds (the major road of a
        Stop or Give Way junction); else the junction's control. Kinds are read as the map's
        controls: "give way" and "give_way" alike, a "signal" line as "lights"."""
        line = self.line_for(approach) if approach is not None else None
        if line is not None and line.kind:
            return CONTROL_OF_KIND.get(line.kind, line.kind)
        if approach is not None and line is None and any(other.kind for other in self.lines):
            return "none"
        return self.control

    def is_major(self, approach: str | None) -> bool | None:
        """Whether an approach is on the major road; None where the map does not say."""
        if self.major is None or approach is None:
            return None
        return approach in self.major

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "x": self.x, "y": self.y, "control": self.control,
                "stop_lines": [line.to_json() for line in self.lines], "extent_m": self.extent_m,
                "extent": ("square" if self.extent_square else "disc") + f" ({self.extent_source})",
                "box": [list(p) for p in self.box] if self.box else self.boxed,
                "major": sorted(self.major) if self.major is not None else None, "major_source": self.major_source}


@dataclass(frozen=True)
class Road:
    id: str
    a: Point
    b: Point
    limit_mph: float | None

    def distance(self, x: float, y: float) -> float:
        dx, dy = self.b[0] - self.a[0], self.b[1] - self.a[1]
        length2 = dx * dx + dy * dy
        f = 0.0 if length2 == 0 else max(0.0, min(1.0, ((x - self.a[0]) * dx + (y - self.a[1]) * dy) / length2))
        return math.hypot(x - self.a[0] - f * dx, y - self.a[1] - f * dy)


@dataclass(frozen=True)
class Map:
    junctions: tuple[Junction, ...]
    roads: tuple[Road, ...]
    ref: EventRef | None
    problems: tuple[str, ...]
    _grid: dict[tuple[int, int], tuple[int, ...]] = field(default_factory=dict, compare=False, repr=False)
    _around: dict[tuple[int, int], tuple[Junction, ...]] = field(default_factory=dict, compare=False, repr=False)
    _roads_by_id: dict[str, Road] = field(default_factory=dict, compare=False, repr=False)
    sensors: dict[str, Sensor] = field(default_factory=dict, compare=False)   # monitor src -> stated tolerance

    def junction(self, ident: str) -> Junction | None:
        return next((j for j in self.junctions if j.id == ident), None)

    def near(self, x: float, y: float, radius_m: float) -> list[Junction]:
        """The junctions within radius_m (<= CELL_M) of a position, found on a grid."""
        cell = (int(x // CELL_M), int(y // CELL_M))
        around = self._around.get(cell)
        if around is None:
            if len(self._around) > 100_000:
                self._around.clear()
            around = self._around[cell] = tuple(self.junctions[n] for i in range(cell[0] - 1, cell[0] + 2)
                                                for k in range(cell[1] - 1, cell[1] + 2)
                                                for n in self._grid.get((i, k), ()))
        return [j for j in around if j.distance(x, y) <= radius_m]

    def road(self, road_id: Any, x: float | None, y: float | None) -> Road | None:
        """The road a position is on: the one its producer named, else the nearest within
        ROAD_SNAP_M."""
        if not self._roads_by_id and self.roads:
            self._roads_by_id.update((r.id, r) for r in reversed(self.roads))    # the first of an id, as before
        named = self._roads_by_id.get(road_id) if isinstance(road_id, str) else None
        if named is not None or x is None or y is None:
            return named
        best = min(self.roads, key=lambda r: r.distance(x, y), default=None)
        return best if best is not None and best.distance(x, y) <= ROAD_SNAP_M else None


def read_map(start: dict | None) -> Map:
    """The map of a run.start event (None, or one without a map: an empty map), as the store's
    reader gives it (store.read_run_map), with what a history needs and can trust."""
    given = read_run_map(start, NO_LANES)
    problems: list[str] = []
    if not given.recorded:
        return Map((), (), given.ref, ("the run records no map",) if start is not None else ("the run has no run.start",))
    roads = tuple(_roads(given, problems))
    monitors = _monitors(given.monitors)
    junctions = tuple(_junctions(given, roads, monitors, problems))
    grid: dict[tuple[int, int], list[int]] = {}
    for n, j in enumerate(junctions):
        grid.setdefault((int(j.x // CELL_M), int(j.y // CELL_M)), []).append(n)
    return Map(junctions, roads, given.ref, tuple(problems[:50]), {k: tuple(v) for k, v in grid.items()},
               sensors=_sensors(given.monitors, given.ref))


def _cut(listed: int, limit: int, what: str, problems: list[str]) -> int:
    """How many of a list are read: at most `limit`, said in `problems` where the map lists more."""
    if listed > limit:
        problems.append(f"the map lists {listed} {what}; the first {limit} are read")
    return limit


def _roads(given: RunMap, problems: list[str]) -> Iterable[Road]:
    for raw in given.roads[:_cut(given.roads_listed, MAX_ROADS, "roads", problems)]:
        a, b = point(raw.a), point(raw.b)
        if raw.ident is None or a is None or b is None:
            problems.append(f"a road without an id and two points is left out: {raw.excerpt()}")
            continue
        limit = finite(raw.speed_limit_mph, 200.0)
        yield Road(raw.ident, a, b, limit if limit is not None and limit > 0 else None)


Cone = tuple[float, float, float, float, float]    # x, y, heading (deg), range (m), field of view (deg)


def _monitors(given: tuple[MapMonitor, ...]) -> dict[str, list[tuple[str, Cone | None]]]:
    """Per junction, its monitors' srcs and cones (None where the map gives no whole cone)."""
    found: dict[str, list[tuple[str, Cone | None]]] = {}
    for m in given:
        if m.ident is not None and m.junction is not None:
            x, y, heading, reach, fov = (finite(v) for v in (m.x, m.y, m.heading_deg, m.range_m, m.fov_deg))
            cone: Cone | None = None
            if x is not None and y is not None and heading is not None and reach is not None and fov is not None:
                cone = (x, y, heading, reach, fov)
            found.setdefault(m.junction, []).append((f"monitor/{m.ident}", cone))
    return found


def _sensors(given: tuple[MapMonitor, ...], ref: EventRef | None) -> dict[str, Sensor]:
    """Each monitor's stated tolerance (its entry's `tolerance`, reasoner/sensors.py), by src."""
    found: dict[str, Sensor] = {}
    for m in given:
        sensor = stated(m.tolerance, ref) if m.ident is not None else None
        if sensor is not None:
            found[f"monitor/{m.ident}"] = sensor
    return found


def _unwatched(x: float, y: float, cones: list[tuple[str, Cone | None]]) -> frozenset[str]:
    """The arms whose point ARM_CHECK_M out from the centre lies in no monitor's cone: the road
    users there are in no camera's record, only in their own. A monitor without a whole cone in
    the map is taken to watch every arm (nothing then says otherwise)."""
    whole = [cone for _, cone in cones if cone is not None]
    if not cones or len(whole) < len(cones):
        return frozenset()
    out = set()
    for arm, (ux, uy) in UNIT.items():
        px, py = x + ux * ARM_CHECK_M, y + uy * ARM_CHECK_M
        if not any(_in_cone(px, py, cone) for cone in whole):
            out.add(arm)
    return frozenset(out)


def _in_cone(px: float, py: float, cone: Cone) -> bool:
    cx, cy, heading, reach, fov = cone
    if math.hypot(px - cx, py - cy) > reach:
        return False
    off = (math.degrees(math.atan2(py - cy, px - cx)) - heading + 180.0) % 360.0 - 180.0
    return abs(off) <= fov / 2.0


def _junctions(given: RunMap, roads: tuple[Road, ...], monitors: dict[str, list[tuple[str, Cone | None]]],
               problems: list[str]) -> Iterable[Junction]:
    for raw in given.junctions[:_cut(given.junctions_listed, MAX_JUNCTIONS, "junctions", problems)]:
        x, y = finite(raw.x), finite(raw.y)
        if raw.ident is None or x is None or y is None:
            problems.append(f"a junction without an id and a position is left out: {raw.excerpt()}")
            continue
        control = raw.control if raw.control is not None else "none"
        lines = _lines(raw, raw.ident, (x, y), control, problems)
        extent, square, extent_source = _extent(raw, (x, y), lines)
        box, boxed = _box(raw)
        major, major_source = _major(raw, (x, y), lines, roads)
        cones = monitors.get(raw.ident, [])
        yield Junction(raw.ident, x, y, control, lines, extent, square, extent_source, box, boxed, major,
                       major_source, tuple(src for src, _ in cones), given.ref, _unwatched(x, y, cones))


def _lines(raw: MapJunction, ident: str, centre: Point, control: str, problems: list[str]) -> tuple[StopLine, ...]:
    if raw.stop_lines is not None:
        lines = []
        for item in raw.stop_lines[:_cut(raw.stop_lines_listed, MAX_LINES, f"stop lines at {ident}", problems)]:
            line = _segment_line(item, centre, ident, control)
            if line is None:
                problems.append(f"a stop line of {ident} is not a line away from its centre: {item.excerpt()}")
            else:
                lines.append(line)
        return tuple(lines)
    distance = finite(raw.stop_line_m, 1000.0)
    if distance is None or distance <= 0:
        return ()
    kind = {"stop": "stop_sign", "give_way": "give_way", "lights": "signal"}.get(control, "")
    return tuple(_arm_line(approach, centre, distance, kind) for approach in COMPASS)


def _kind_read(word: Any, junction: str, approach: str, control: str) -> tuple[str, str | None]:
    """DESIGN's kind for a producer's word, and how it was read where the word was not DESIGN's
    own (None: it was, or there was none). A bare "stop" is read by the junction's control
    (lights: the line at signals; stop: the Stop sign's line); where the control does not
    settle it, the word is read as it says (a Stop sign's line), and the reading says so."""
    if not isinstance(word, str) or not word.strip():
        return "", None
    low = word.strip().lower()
    if low in KINDS:
        return low, None
    line = f"the {approach} stop line of {junction}"
    if low == "stop":
        kind = STOP_BY_CONTROL.get(control)
        if kind is not None:
            return kind, (f"{line} has kind 'stop', read as '{kind}' by the junction's control '{control}' "
                          "(DESIGN: a bare 'stop' is read by its junction's control)")
        return "stop_sign", (f"{line} has kind 'stop' at a junction whose control '{control}' does not say which "
                             "line it is; read as 'stop_sign', the line of a Stop sign, as the word says")
    if low in SYNONYMS:
        return SYNONYMS[low], f"{line} has kind {word!r}, read as {SYNONYMS[low]!r}"
    return word, None


def _segment_line(item: MapStopLine, centre: Point, junction: str, control: str) -> StopLine | None:
    a, b = point(item.a), point(item.b)
    if a is None or b is None or item.approach is None:
        return None
    dx, dy = b[0] - a[0], b[1] - a[1]
    length = math.hypot(dx, dy)
    if length < 0.1:
        return None
    n = (-dy / length, dx / length)
    towards_centre = (centre[0] - a[0]) * n[0] + (centre[1] - a[1]) * n[1]
    if abs(towards_centre) < 0.1:
        return None
    if towards_centre > 0:
        n = (-n[0], -n[1])
    kind, reading = _kind_read(item.kind, junction, item.approach, control)
    return StopLine(item.approach, a, b, kind, "map stop_lines", n, True, reading)


def _arm_line(approach: str, centre: Point, distance: float, kind: str) -> StopLine:
    ux, uy = UNIT[approach]
    mid = (centre[0] + ux * distance, centre[1] + uy * distance)
    a, b = (mid[0] - uy * 5.0, mid[1] + ux * 5.0), (mid[0] + uy * 5.0, mid[1] - ux * 5.0)
    return StopLine(approach, a, b, kind, "map stop_line_m", (ux, uy), False)


def _extent(raw: MapJunction, centre: Point, lines: tuple[StopLine, ...]) -> tuple[float, bool, str]:
    half = finite(raw.box_m, 1000.0)
    if half is not None and half > 0:
        return half, True, "map box_m"
    if lines:
        return min(abs(line.to_line(*centre)) for line in lines), False, "the nearest stop line"
    return DEFAULT_EXTENT_M, False, f"default {DEFAULT_EXTENT_M:g} m: the map gives no area"


def _box(raw: MapJunction) -> tuple[tuple[Point, ...] | None, bool]:
    if raw.box_whole:
        return None, True
    if raw.box is not None and len(raw.box) >= 3:
        points = [point(p) for p in raw.box[:256]]
        whole = tuple(p for p in points if p is not None)
        if len(whole) == len(points):
            return whole, True
    return None, False


def _major(raw: MapJunction, centre: Point, lines: tuple[StopLine, ...], roads: tuple[Road, ...]
           ) -> tuple[frozenset[str] | None, str]:
    arms = _arms(centre, roads) | {line.approach for line in lines}
    if raw.major is not None:
        major: set[str] = set()
        for item in raw.major:
            road = next((r for r in roads if r.id == item), None)
            major |= _arms(centre, (road,)) if road is not None else {item}
        return frozenset(major), "map major"
    if any(line.kind for line in lines) and any(line.source == "map stop_lines" for line in lines):
        minor = {line.approach for line in lines if line.kind in MINOR_KINDS}
        if minor:
            return frozenset(arms - minor), "the map's stop lines: a Stop or Give Way line marks a minor approach"
    return None, "the map does not say which road is major"


def _arms(centre: Point, roads: Iterable[Road]) -> set[str]:
    """The approaches of the roads meeting at a centre: the sector of each end away from it."""
    arms = set()
    for road in roads:
        if road.distance(*centre) > 2.0:
            continue
        for end in (road.a, road.b):
            if math.hypot(end[0] - centre[0], end[1] - centre[1]) > 1.0:
                arms.add(sector(end[0] - centre[0], end[1] - centre[1]))
    return arms


def _in_polygon(x: float, y: float, polygon: tuple[Point, ...]) -> bool:
    inside = False
    for (x1, y1), (x2, y2) in zip(polygon, polygon[1:] + polygon[:1]):
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside
