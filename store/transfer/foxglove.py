"""What an export draws, so that a run plays in Foxglove or Lichtblick: a 3D scene
(foxglove.SceneUpdate) of the map, the road users and the signals, and a log (foxglove.Log) of
the decisions, potential violations and collisions.

These are views derived from the events, never evidence: an import skips them.

A viewer that jumps to a moment shows the latest message of each topic before it, so every
message on the road-user and the signal topics is the whole live scene of that topic: a deletion
of ALL (the topic's previous drawing) and every road user alive then (spawned or moving, not
despawned) at its latest recorded position, or every signal at its latest colour. A scene is drawn
per tick: the changes (entity.state, entity.despawn, signal.state) within SCENE_PERIOD_NS of the
first change not yet drawn are drawn together, at the time of the latest of them, so that sources
that each publish at their own instant (a microsecond apart, or staggered over a simulation step)
still share one scene per step, and the number of scenes follows the run's duration, not its
number of sources. The map is drawn once, on its own topic; log lines at their event's time.

Each road user's entity is serialized once per change and reused by every scene until it changes
again, so a scene costs a join of bytes, not a serialization of the whole scene.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any, Iterable, NamedTuple

import orjson

from ..envelope import key_for
from .foxglove_schemas import LOG, SCENE_UPDATE, Codes
from .foxglove_schemas import codes as foxglove_codes

MAP_TOPIC, ENTITIES_TOPIC, SIGNALS_TOPIC, LOG_TOPIC = "/scene/map", "/scene/entities", "/scene/signals", "/log"
TOPICS = {MAP_TOPIC: SCENE_UPDATE, ENTITIES_TOPIC: SCENE_UPDATE, SIGNALS_TOPIC: SCENE_UPDATE, LOG_TOPIC: LOG}
FRAME = "map"
DERIVED_MARK = "gaps.derived"  # channel metadata key marking these channels as drawn, not evidence
SCENE_PERIOD_NS = 100_000_000  # one scene per 100 ms of world time at most: a simulation step of 10 Hz
_NS = 1_000_000_000
_UINT32 = (1 << 32) - 1

# (length, width, height) in metres and colour (r, g, b), by entity.spawn type
_BODIES: dict[str, tuple[tuple[float, float, float], tuple[float, float, float]]] = {
    "car": ((4.5, 1.8, 1.5), (0.25, 0.5, 0.85)),
    "police_car": ((4.9, 1.9, 1.5), (0.1, 0.15, 0.5)),
    "ambulance": ((6.0, 2.3, 2.7), (0.95, 0.95, 0.9)),
    "fire_engine": ((8.5, 2.5, 3.2), (0.85, 0.1, 0.1)),
    "bus": ((12.0, 2.55, 3.2), (0.95, 0.8, 0.1)),
    "cyclist": ((1.8, 0.6, 1.7), (0.2, 0.75, 0.3)),
    "pedestrian": ((0.5, 0.5, 1.75), (0.95, 0.55, 0.1)),
}
_SIGNAL_COLOURS = {"red": (1.0, 0.0, 0.0), "red_amber": (1.0, 0.35, 0.0), "amber": (1.0, 0.65, 0.0),
                   "green": (0.0, 0.85, 0.2), "off": (0.3, 0.3, 0.3)}
_APPROACH = {"west": (-1, 0), "east": (1, 0), "north": (0, 1), "south": (0, -1)}  # where a signal stands
_SIGNAL_OFFSET_M = 10.0


@dataclass(frozen=True)
class Derived:
    """One drawn message: its topic, its log time and its JSON bytes."""

    topic: str
    t: int
    data: bytes

    @property
    def message(self) -> dict[str, Any]:
        return json.loads(self.data)


def _json(value: Any) -> bytes:
    """Compact UTF-8 JSON; a NaN or an infinity (from a hostile body) becomes null, never invalid JSON."""
    return orjson.dumps(value)


def stamp(t: int) -> dict[str, int]:
    """A Foxglove time; times before 1970 (allowed in events) are drawn at 0."""
    sec, nsec = divmod(max(t, 0), _NS)
    return {"sec": sec, "nsec": nsec}


def _vec(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> dict[str, float]:
    return {"x": x, "y": y, "z": z}


def _pose(x: float, y: float, z: float = 0.0, heading_deg: float = 0.0) -> dict[str, Any]:
    """Heading 0 points along +x, counter-clockwise, as entity.state and the map use it."""
    half = math.radians(heading_deg) / 2
    return {"position": _vec(x, y, z), "orientation": {"x": 0.0, "y": 0.0, "z": math.sin(half), "w": math.cos(half)}}


def _rgba(rgb: tuple[float, float, float], a: float = 1.0) -> dict[str, float]:
    return {"r": rgb[0], "g": rgb[1], "b": rgb[2], "a": a}


def _entity(entity_id: str, t: int, metadata: dict[str, Any] | None = None, **primitives: list) -> dict[str, Any]:
    """A SceneEntity with every field present: viewers differ in how they treat missing ones."""
    entity = {"timestamp": stamp(t), "frame_id": FRAME, "id": entity_id, "lifetime": _LIFETIME_FOREVER,
              "frame_locked": False,
              "metadata": [{"key": k, "value": str(v)} for k, v in (metadata or {}).items() if v is not None]}
    for name in ("arrows", "cubes", "spheres", "cylinders", "lines", "triangles", "texts", "models"):
        entity[name] = primitives.get(name, [])
    return entity


def _label(text: str, x: float, y: float, z: float) -> dict[str, Any]:
    return {"pose": _pose(x, y, z), "billboard": True, "font_size": 14.0, "scale_invariant": True,
            "color": _WHITE, "text": text}


def _number(value: Any, default: float = 0.0) -> float:
    """A body field that should be a number, as a float (an integer too big for one is the default)."""
    if not isinstance(value, (int, float)) or isinstance(value, bool):
        return default
    try:
        number = float(value)
    except OverflowError:
        return default
    return number if math.isfinite(number) else default


def _text(value: Any) -> str | None:
    """A body field that should be a string, or None: bodies may hold anything, drawing must not fail."""
    return value if isinstance(value, str) else None


def _point(value: Any) -> tuple[float, float] | None:
    if isinstance(value, list) and len(value) == 2:
        return _number(value[0]), _number(value[1])
    return None


class _Look(NamedTuple):
    size: dict[str, float]
    color: dict[str, float]
    height: float
    beacon: bool  # on an emergency call: a blue light on the roof
    ident: str
    metadata: dict[str, Any]


_BEACON, _BEACON_SIZE = _rgba((0.1, 0.3, 1.0)), _vec(0.6, 0.6, 0.6)
_LIFETIME_FOREVER = {"sec": 0, "nsec": 0}
_WHITE = _rgba((1.0, 1.0, 1.0))


class _Layer:
    """One scene topic's live entities, each kept as the JSON bytes of its latest drawing."""

    def __init__(self, topic: str) -> None:
        self.topic = topic
        self.live: dict[str, bytes] = {}
        self.changed = False

    def put(self, entity_id: str, entity: dict[str, Any]) -> None:
        self.live[entity_id] = _json(entity)
        self.changed = True

    def remove(self, entity_id: str) -> None:
        if self.live.pop(entity_id, None) is not None:
            self.changed = True

    def scene(self, t: int, delete_all: int) -> Derived:
        """The whole layer at t: clear the topic's previous drawing, then every live entity."""
        self.changed = False
        deletions = _json([{"timestamp": stamp(t), "type": delete_all, "id": ""}])
        data = b'{"deletions":' + deletions + b',"entities":[' + b",".join(self.live.values()) + b"]}"
        return Derived(self.topic, t, data)


@dataclass
class SceneBuilder:
    """Follows a run's events in time order and returns the visualisation messages they call for.

    `horizon()` is the earliest log time of a message not returned yet, so that a writer can hold
    back what comes after it and write every message in log-time order."""

    period_ns: int = SCENE_PERIOD_NS
    codes: Codes = field(default_factory=foxglove_codes)  # the enum values, from foxglove-sdk
    junctions: dict[str, tuple[float, float]] = field(default_factory=dict)
    spawned: dict[str, dict[str, Any]] = field(default_factory=dict)  # src -> entity.spawn body
    _road_users: _Layer = field(default_factory=lambda: _Layer(ENTITIES_TOPIC))
    _signals: _Layer = field(default_factory=lambda: _Layer(SIGNALS_TOPIC))
    _signal_events: dict[str, dict[str, Any]] = field(default_factory=dict)  # src -> latest signal.state
    _first_change: int | None = None  # t of the first change not drawn yet
    _last_change: int = 0  # t of the latest change not drawn yet
    _looks: dict[str, _Look] = field(default_factory=dict)

    def add(self, event: dict[str, Any]) -> list[Derived]:
        out = self.advance(event["t"])
        handler = _HANDLERS.get(event["kind"])
        if handler is not None:
            out += handler(self, event)
        return out

    def advance(self, t: int) -> list[Derived]:
        """The scene of the pending changes, when the world has moved on a tick past the first."""
        if self._first_change is not None and t - self._first_change >= self.period_ns:
            return self._draw()
        return []

    def finish(self) -> list[Derived]:
        return self._draw()

    def horizon(self) -> int | None:
        """The earliest log time a later message may have (None: nothing is pending)."""
        return self._first_change

    # --- the scene ---------------------------------------------------------------------------

    def _changed(self, t: int) -> None:
        if self._first_change is None:
            self._first_change = self._last_change = t
        else:
            self._last_change = max(self._last_change, t)

    def _draw(self) -> list[Derived]:
        if self._first_change is None:
            return []
        t, self._first_change, self._last_change = self._last_change, None, 0
        return [layer.scene(t, self.codes.delete_all) for layer in (self._road_users, self._signals) if layer.changed]

    def _moved(self, event: dict[str, Any]) -> list[Derived]:
        self._road_users.put(event["src"], self._road_user(event))
        self._changed(event["t"])
        return []

    def _road_user(self, event: dict[str, Any]) -> dict[str, Any]:
        src, body = event["src"], event["body"]
        look = self._looks.get(src) or self._look(src)
        x, y, heading = _number(body.get("x")), _number(body.get("y")), _number(body.get("heading_deg"))
        cubes = [{"pose": _pose(x, y, look.height / 2, heading), "size": look.size, "color": look.color}]
        spheres = [{"pose": _pose(x, y, look.height + 0.3), "size": _BEACON_SIZE, "color": _BEACON}] if look.beacon else []
        metadata = {**look.metadata, "speed_mps": body.get("speed_mps"), "road": body.get("road"),
                    "junction": body.get("junction")}
        return _entity(src, event["t"], metadata, cubes=cubes, spheres=spheres,
                       texts=[_label(look.ident, x, y, look.height + 1.5)])

    def _look(self, src: str) -> _Look:
        """How a road user is drawn, from its spawn event; kept until it spawns again (every
        state event of a run is drawn, so this is worked out once per road user, not per event)."""
        spawn = self.spawned.get(src, {})
        kind = _text(spawn.get("type")) if _text(spawn.get("type")) in _BODIES else src.partition("/")[0]
        (length, width, height), rgb = _BODIES.get(kind, _BODIES["car"])
        metadata = {"src": src, "type": spawn.get("type"), "plate": spawn.get("plate")}
        look = _Look(_vec(length, width, height), _rgba(rgb), height, spawn.get("emergency") is True,
                     src.partition("/")[2], metadata)
        self._looks[src] = look
        return look

    def _despawned(self, event: dict[str, Any]) -> list[Derived]:
        self._road_users.remove(event["src"])
        self._signals.remove(event["src"])
        self._signal_events.pop(event["src"], None)
        self._changed(event["t"])
        return []

    def _spawned(self, event: dict[str, Any]) -> list[Derived]:
        self.spawned[event["src"]] = event["body"]
        self._looks.pop(event["src"], None)
        return []

    def _signal(self, event: dict[str, Any]) -> list[Derived]:
        self._signal_events[event["src"]] = event
        self._signals.put(event["src"], self._signal_entity(event))
        self._changed(event["t"])
        return []

    def _signal_entity(self, event: dict[str, Any]) -> dict[str, Any]:
        """A signal beside its junction (the map's; at the origin while no map has placed it)."""
        body = event["body"]
        jx, jy = self.junctions.get(_text(body.get("junction")), (0.0, 0.0))
        dx, dy = _APPROACH.get(_text(body.get("approach")), (0, 0))
        x, y = jx + dx * _SIGNAL_OFFSET_M, jy + dy * _SIGNAL_OFFSET_M
        colour = _text(body.get("colour"))
        sphere = {"pose": _pose(x, y, 4.0), "size": _vec(1.5, 1.5, 1.5),
                  "color": _rgba(_SIGNAL_COLOURS.get(colour, _SIGNAL_COLOURS["off"]))}
        pole = {"pose": _pose(x, y, 1.6), "size": _vec(0.2, 0.2, 3.2), "color": _rgba((0.2, 0.2, 0.2)),
                "bottom_scale": 1.0, "top_scale": 1.0}
        metadata = {"junction": body.get("junction"), "approach": body.get("approach"), "colour": colour}
        return _entity(event["src"], event["t"], metadata, spheres=[sphere], cylinders=[pole])

    def _map(self, event: dict[str, Any]) -> list[Derived]:
        world = event["body"].get("map")
        if not isinstance(world, dict):
            return []
        points, cylinders, texts, arrows = [], [], [], []
        for road in _dicts(world.get("roads")):
            ends = _point(road.get("from")), _point(road.get("to"))
            if None not in ends:
                points += [_vec(*ends[0]), _vec(*ends[1])]
        for junction in _dicts(world.get("junctions")):
            x, y = _number(junction.get("x")), _number(junction.get("y"))
            self.junctions[str(junction.get("id"))] = (x, y)
            cylinders.append({"pose": _pose(x, y, 0.02), "size": _vec(14.0, 14.0, 0.04),
                              "bottom_scale": 1.0, "top_scale": 1.0, "color": _rgba((0.35, 0.35, 0.4))})
            texts.append(_label(f"{junction.get('id')} ({junction.get('control')})", x, y, 8.0))
        for monitor in _dicts(world.get("monitors")):
            x, y = _number(monitor.get("x")), _number(monitor.get("y"))
            arrows.append({"pose": _pose(x, y, 3.0, _number(monitor.get("heading_deg"))), "shaft_length": 2.0,
                           "shaft_diameter": 0.3, "head_length": 1.0, "head_diameter": 0.8,
                           "color": _rgba((0.7, 0.2, 0.9))})
            texts.append(_label(f"monitor {monitor.get('id')}", x, y, 5.0))
        roads = {"type": self.codes.line_list, "pose": _pose(0.0, 0.0), "thickness": 7.0, "scale_invariant": False,
                 "points": points, "color": _rgba((0.5, 0.5, 0.5)), "colors": [], "indices": []}
        entity = _entity("map", event["t"], None, lines=[roads] if points else [], cylinders=cylinders,
                         texts=texts, arrows=arrows)
        if self._signal_events:  # signals drawn before the map (at the same t) move beside their junction
            for src, signal in self._signal_events.items():
                self._signals.put(src, self._signal_entity(signal))
            self._changed(event["t"])
        return [Derived(MAP_TOPIC, event["t"], _json({"deletions": [], "entities": [entity]}))]

    # --- the log -----------------------------------------------------------------------------

    def _decision(self, event: dict[str, Any]) -> list[Derived]:
        body, ident = event["body"], event["src"].partition("/")[2]
        permitted = body.get("permitted")
        answer = ("permitted" if permitted is True else "not permitted" if permitted is False
                  else "no rulebook answer recorded")
        did = "proceeds" if body.get("proceeds") else "holds"
        level = self.codes.warning if body.get("proceeds") and permitted is False else self.codes.info
        text = f"{ident} {did} to {body.get('action')} ({answer}; goal: {body.get('goal')})"
        return [_log(event, level, text)]

    def _violation(self, event: dict[str, Any]) -> list[Derived]:
        body = event["body"]
        text = f"potential violation by vehicle {body.get('vehicle')}: {body.get('action')}"
        facts = body.get("facts")
        if isinstance(facts, list) and facts:
            text += " — " + "; ".join(map(str, facts))
        return [_log(event, self.codes.warning, text)]

    def _collision(self, event: dict[str, Any]) -> list[Derived]:
        entities = event["body"].get("entities")
        names = ", ".join(map(str, entities)) if isinstance(entities, list) else str(entities)
        return [_log(event, self.codes.error, f"collision between {names}")]


def _log(event: dict[str, Any], level: int, text: str) -> Derived:
    """A log line that names the event it came from: file is its key, line its seq."""
    message = {"timestamp": stamp(event["t"]), "level": level, "message": text, "name": event["src"],
               "file": key_for(event), "line": min(event["seq"], _UINT32)}
    return Derived(LOG_TOPIC, event["t"], _json(message))


def _dicts(value: Any) -> Iterable[dict[str, Any]]:
    """The objects in a map list; producers may send anything, and a drawing must not fail on it."""
    return [item for item in value if isinstance(item, dict)] if isinstance(value, list) else []


_HANDLERS = {
    "run.start": SceneBuilder._map,
    "entity.state": SceneBuilder._moved,
    "entity.spawn": SceneBuilder._spawned,
    "entity.despawn": SceneBuilder._despawned,
    "signal.state": SceneBuilder._signal,
    "vehicle.decision": SceneBuilder._decision,
    "monitor.potential_violation": SceneBuilder._violation,
    "collision": SceneBuilder._collision,
}
DRAWN_KINDS = frozenset(_HANDLERS)  # the kinds whose bodies an export must read
