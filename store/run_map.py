"""The map a run recorded in its run.start (DESIGN "Events"), read once into typed values.

A producer writes the map as it can, and an event from a store written before the schemas were
checked (or a file of events) may hold anything: so every part is read here the one way, and
nothing else reads the map's JSON. What cannot be read is None, never a guess:

    numbers     finite ints or floats (not a bool, not a string, not an integer beyond a
                float), as floats; else None
    points      `[x, y]`: a Pair of two numbers-or-None; anything else None
    polylines   a list of points (each a Pair, or None where an item is not a pair), at most
                MAX_POINTS of them; not a list: None
    names       `ident` the value where it is a string (an id the reasoner can match), `label`
                the value as text (str of what was sent) for a picture to show; None where absent

Each reader of the map then decides what it can use: the reasoner (reasoner/junctions.py) leaves
out what lacks an id or a position within 10,000 km, a picture (explain/report_data.py) what has
no finite coordinates, the MCAP export (store/transfer/foxglove.py) draws every entry, at 0 where
a number is missing. Lists are read up to MAX_ENTRIES (an event is at most 1 MiB, so a real map
never reaches it); `listed` keeps how many objects the map gave, so a reader can say what it cut.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Mapping

from .refs import EventRef

MAX_ENTRIES = 400_000        # objects read from one list of the map (more than 1 MiB can hold)
MAX_POINTS = 200_000         # points read from one polyline

Point = tuple[float, float]
Pair = tuple["float | None", "float | None"]


def number(value: Any) -> float | None:
    """A finite number as a float, else None (a producer's string, NaN, a bool, an integer too
    big for a float)."""
    kind = type(value)
    if kind is float:
        return value if value - value == 0.0 else None       # NaN and the infinities fail
    if kind is int:
        try:
            return float(value)
        except OverflowError:
            return None
    return None


def label(value: Any) -> str | None:
    """What was sent, as text to show (None where nothing was)."""
    return None if value is None else str(value)


def ident(value: Any) -> str | None:
    """An id the reasoner can match: the value where it is a string."""
    return value if isinstance(value, str) else None


def pair(value: Any) -> Pair | None:
    """`[x, y]` as two numbers-or-None; None where it is not a list of two."""
    if isinstance(value, (list, tuple)) and len(value) == 2:
        return (number(value[0]), number(value[1]))
    return None


def whole(p: Pair | None) -> Point | None:
    """A point with both coordinates numbers, else None."""
    if p is None or p[0] is None or p[1] is None:
        return None
    return (p[0], p[1])


def polyline(value: Any) -> tuple[Pair | None, ...] | None:
    if not isinstance(value, list):
        return None
    return tuple(pair(p) for p in value[:MAX_POINTS])


def whole_line(points: tuple[Pair | None, ...] | None) -> tuple[Point, ...]:
    """Every point of a polyline, or () where any of them is not two numbers."""
    out = [whole(p) for p in points or ()]
    return () if any(p is None for p in out) else tuple(p for p in out if p is not None)


def _objects(value: Any) -> tuple[list[dict[str, Any]], int]:
    """The objects of a map list (anything else in it is not an entry), up to MAX_ENTRIES, and
    how many it held."""
    items = [v for v in value if isinstance(v, dict)] if isinstance(value, list) else []
    return items[:MAX_ENTRIES], len(items)


@dataclass(frozen=True)
class _Entry:
    """What every entry keeps: the text of the object as sent, cut, for a message that names it."""

    raw: Any = field(repr=False, compare=False)

    def excerpt(self, limit: int = 80) -> str:
        return str(self.raw)[:limit]


@dataclass(frozen=True)
class MapRoad(_Entry):
    ident: str | None = None
    label: str | None = None
    a: Pair | None = None
    b: Pair | None = None
    speed_limit_mph: float | None = None


@dataclass(frozen=True)
class MapStopLine(_Entry):
    approach: str | None = None          # the approach where it is a string
    approach_label: str | None = None
    a: Pair | None = None
    b: Pair | None = None
    kind: Any = None                     # the producer's word, read by reasoner/junctions.py


@dataclass(frozen=True)
class MapCrossing(_Entry):
    label: str | None = None
    shape: tuple[Pair | None, ...] | None = None
    width_m: float | None = None


@dataclass(frozen=True)
class MapJunction(_Entry):
    ident: str | None = None
    label: str | None = None
    x: float | None = None
    y: float | None = None
    control: str | None = None           # where it is a string
    control_label: str | None = None
    stop_lines: tuple[MapStopLine, ...] | None = None     # None: the map gives no list of them
    stop_lines_listed: int = 0
    stop_line_m: float | None = None
    box_m: float | None = None
    box_whole: bool = False              # `box: true`: the junction's whole area is a yellow box
    box: tuple[Pair | None, ...] | None = None
    shape: tuple[Pair | None, ...] | None = None
    crossings: tuple[MapCrossing, ...] = ()
    major: tuple[str, ...] | None = None  # the strings of a non-empty `major` list (its first 64)


@dataclass(frozen=True)
class MapMonitor(_Entry):
    ident: str | None = None
    label: str | None = None
    junction: str | None = None          # where it is a string
    x: float | None = None
    y: float | None = None
    heading_deg: float | None = None
    range_m: float | None = None
    fov_deg: float | None = None
    tolerance: Any = None                # as sent; reasoner/sensors.py reads it


@dataclass(frozen=True)
class MapLane(_Entry):
    label: str | None = None
    kind: str | None = None
    width_m: float | None = None
    shape: tuple[Pair | None, ...] | None = None


@dataclass(frozen=True)
class RunMap:
    """A run's map; `recorded` False where the run.start holds none (or there is no run.start)."""

    recorded: bool
    ref: EventRef | None
    roads: tuple[MapRoad, ...] = ()
    roads_listed: int = 0
    junctions: tuple[MapJunction, ...] = ()
    junctions_listed: int = 0
    monitors: tuple[MapMonitor, ...] = ()
    lanes: tuple[MapLane, ...] = ()
    lefthand: bool = True                # `network.lefthand` unless it is false (UK traffic)


PARTS = frozenset({"roads", "junctions", "monitors", "lanes"})


def read_run_map(event: Mapping[str, Any] | None, parts: frozenset[str] = PARTS) -> RunMap:
    """The map of a run.start event (None, or an event without a map body: not recorded).
    `parts`: the lists to read (a reader that needs no lanes, a city's thousands of polylines,
    leaves them out: they are then empty)."""
    body = event.get("body") if isinstance(event, Mapping) else None
    ref = EventRef.of(event) if isinstance(body, dict) and event is not None else None
    return read_map_body(body if isinstance(body, dict) else {}, ref, parts)


def read_map_body(body: Mapping[str, Any], ref: EventRef | None = None, parts: frozenset[str] = PARTS) -> RunMap:
    """The map of a run.start's body (`parts` as read_run_map's)."""
    raw = body.get("map")
    if not isinstance(raw, dict):
        return RunMap(False, ref)
    roads, roads_listed = _objects(raw.get("roads") if "roads" in parts else None)
    junctions, junctions_listed = _objects(raw.get("junctions") if "junctions" in parts else None)
    monitors, _ = _objects(raw.get("monitors") if "monitors" in parts else None)
    lanes, _ = _objects(raw.get("lanes") if "lanes" in parts else None)
    network = raw.get("network")
    return RunMap(True, ref, tuple(_road(r) for r in roads), roads_listed,
                  tuple(_junction(j) for j in junctions), junctions_listed,
                  tuple(_monitor(m) for m in monitors), tuple(_lane(lane) for lane in lanes),
                  not (isinstance(network, dict) and network.get("lefthand") is False))


def _road(r: dict[str, Any]) -> MapRoad:
    return MapRoad(r, ident(r.get("id")), label(r.get("id")), pair(r.get("from")), pair(r.get("to")),
                   number(r.get("speed_limit_mph")))


def _junction(j: dict[str, Any]) -> MapJunction:
    lines, listed = _objects(j.get("stop_lines"))
    box, major = j.get("box"), j.get("major")
    return MapJunction(
        j, ident(j.get("id")), label(j.get("id")), number(j.get("x")), number(j.get("y")),
        ident(j.get("control")), label(j.get("control")),
        tuple(_stop_line(s) for s in lines) if isinstance(j.get("stop_lines"), list) else None, listed,
        number(j.get("stop_line_m")), number(j.get("box_m")), box is True, polyline(box), polyline(j.get("shape")),
        tuple(_crossing(c) for c in _objects(j.get("crossings"))[0]),
        tuple(m for m in major[:64] if isinstance(m, str)) if isinstance(major, list) and major else None)


def _stop_line(s: dict[str, Any]) -> MapStopLine:
    return MapStopLine(s, ident(s.get("approach")), label(s.get("approach")), pair(s.get("from")), pair(s.get("to")),
                       s.get("kind"))


def _crossing(c: dict[str, Any]) -> MapCrossing:
    return MapCrossing(c, label(c.get("id")), polyline(c.get("shape")), number(c.get("width_m")))


def _monitor(m: dict[str, Any]) -> MapMonitor:
    return MapMonitor(m, ident(m.get("id")), label(m.get("id")), ident(m.get("junction")), number(m.get("x")),
                      number(m.get("y")), number(m.get("heading_deg")), number(m.get("range_m")),
                      number(m.get("fov_deg")), m.get("tolerance"))


def _lane(lane: dict[str, Any]) -> MapLane:
    return MapLane(lane, label(lane.get("id")), label(lane.get("kind")), number(lane.get("width_m")),
                   polyline(lane.get("shape")))


finite_number = number      # the name other rooms know it by: a finite number, else None

__all__ = ["MapCrossing", "MapJunction", "MapLane", "MapMonitor", "MapRoad", "MapStopLine", "Pair", "RunMap",
           "finite_number", "read_map_body", "read_run_map", "whole", "whole_line"]
