"""What an export draws, so that a run plays in Foxglove or Lichtblick: a 3D scene
(foxglove.SceneUpdate) of the map, the road users and the signals, and a log (foxglove.Log) of
the decisions, potential violations and collisions.

These are views derived from the events, never evidence: an import skips them.

The messages are foxglove-sdk's own (`foxglove.messages`), encoded by it in protobuf, and the
schemas are the FileDescriptorSets it publishes (`get_schema()`): the same bytes the SDK writes
into its own MCAP files, so field names, types and enum values are Foxglove's and nothing of
them is retyped here.

A viewer that jumps to a moment shows the latest message of each topic before it, so every
message on the road-user and the signal topics is the whole live scene of that topic: a deletion
of ALL (the topic's previous drawing) and every road user alive then (spawned or moving, not
despawned) at its latest recorded position, or every signal at its latest colour. A scene is drawn
per tick: the changes (entity.state, entity.despawn, signal.state) within SCENE_PERIOD_NS of the
first change not yet drawn are drawn together, at the time of the latest of them, so that sources
that each publish at their own instant (a microsecond apart, or staggered over a simulation step)
still share one scene per step, and the number of scenes follows the run's duration, not its
number of sources. The map is drawn once, on its own topic; log lines at their event's time.

Each road user's entity is built once per change and kept (the SDK's messages are immutable) until
it changes again; a scene is the SDK's encoding of the deletion and the live entities. Encoding
each entity once and joining the bytes (protobuf reads concatenated messages as one) gave the same
bytes in the same CPU time on bench/transfer.py's generated run (0.40 s to draw 50,030 events), so
the SDK encodes whole scenes.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import foxglove.messages as fm

from ..envelope import key_for
from ..run_map import read_run_map
from .foxglove_channels import ENCODING, ENTITIES_TOPIC, LOG, LOG_TOPIC, MAP_TOPIC, SCENE_UPDATE, SIGNALS_TOPIC

FRAME = "map"
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
_DRAWN_PARTS = frozenset({"roads", "junctions", "monitors"})   # of the run map (store/run_map.py)
_APPROACH = {"west": (-1, 0), "east": (1, 0), "north": (0, 1), "south": (0, -1)}  # where a signal stands
_SIGNAL_OFFSET_M = 10.0


@dataclass(frozen=True)
class Derived:
    """One drawn message: its topic, its log time and its bytes (protobuf, encoded by foxglove-sdk)."""

    topic: str
    t: int
    data: bytes


def stamp(t: int) -> fm.Timestamp:
    """A Foxglove time (unsigned 32-bit seconds); times before 1970 (allowed in events) are drawn
    at 0, times after 2106 at the last second Foxglove's time can hold."""
    sec, nsec = divmod(max(t, 0), _NS)
    return fm.Timestamp(sec, nsec) if sec <= _UINT32 else fm.Timestamp(_UINT32, _NS - 1)


def _vec(x: float = 0.0, y: float = 0.0, z: float = 0.0) -> fm.Vector3:
    return fm.Vector3(x=x, y=y, z=z)


_HEADING_0 = fm.Quaternion(x=0.0, y=0.0, z=0.0, w=1.0)  # labels and lights: one object for all of them


def _pose(x: float, y: float, z: float = 0.0, heading_deg: float = 0.0) -> fm.Pose:
    """Heading 0 points along +x, counter-clockwise, as entity.state and the map use it."""
    if heading_deg == 0.0:
        return fm.Pose(position=fm.Vector3(x=x, y=y, z=z), orientation=_HEADING_0)
    half = math.radians(heading_deg) / 2
    return fm.Pose(position=fm.Vector3(x=x, y=y, z=z),
                   orientation=fm.Quaternion(x=0.0, y=0.0, z=math.sin(half), w=math.cos(half)))


def _rgba(rgb: tuple[float, float, float], a: float = 1.0) -> fm.Color:
    return fm.Color(r=rgb[0], g=rgb[1], b=rgb[2], a=a)


def _pairs(metadata: dict[str, Any]) -> list[fm.KeyValuePair]:
    """Metadata a viewer shows beside an entity: the fields that are there, as text."""
    return [fm.KeyValuePair(key=k, value=str(v)) for k, v in metadata.items() if v is not None]


def _entity(entity_id: str, t: int, pairs: list[fm.KeyValuePair], **primitives: list) -> fm.SceneEntity:
    """A SceneEntity in the map frame that lives until it is replaced or deleted (lifetime 0)."""
    return fm.SceneEntity(timestamp=stamp(t), frame_id=FRAME, id=entity_id, lifetime=_FOREVER,
                          frame_locked=False, metadata=pairs, **primitives)


def _label(text: str, x: float, y: float, z: float) -> fm.TextPrimitive:
    return fm.TextPrimitive(pose=_pose(x, y, z), billboard=True, font_size=14.0, scale_invariant=True,
                            color=_WHITE, text=text)


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


def _or0(value: float | None) -> float:
    """A map number (store/run_map.py), 0 where the map gave none: the drawing shows every entry."""
    return 0.0 if value is None else value


class _Look(NamedTuple):
    size: fm.Vector3
    color: fm.Color
    height: float
    beacon: bool  # on an emergency call: a blue light on the roof
    ident: str
    pairs: list[fm.KeyValuePair]  # the metadata that stays while the road user lives


_BEACON, _BEACON_SIZE = _rgba((0.1, 0.3, 1.0)), _vec(0.6, 0.6, 0.6)
_WHITE = _rgba((1.0, 1.0, 1.0))
_FOREVER = fm.Duration(0, 0)


class _Layer:
    """One scene topic's live entities, each as its latest drawing."""

    def __init__(self, topic: str) -> None:
        self.topic = topic
        self.live: dict[str, fm.SceneEntity] = {}
        self.changed = False

    def put(self, entity_id: str, entity: fm.SceneEntity) -> None:
        self.live[entity_id] = entity
        self.changed = True

    def remove(self, entity_id: str) -> None:
        if self.live.pop(entity_id, None) is not None:
            self.changed = True

    def scene(self, t: int) -> Derived:
        """The whole layer at t: clear the topic's previous drawing, then every live entity."""
        self.changed = False
        deletion = fm.SceneEntityDeletion(timestamp=stamp(t), type=fm.SceneEntityDeletionType.All, id="")
        return Derived(self.topic, t, fm.SceneUpdate(deletions=[deletion], entities=list(self.live.values())).encode())


@dataclass
class SceneBuilder:
    """Follows a run's events in time order and returns the visualisation messages they call for.

    `horizon()` is the earliest log time of a message not returned yet, so that a writer can hold
    back what comes after it and write every message in log-time order."""

    period_ns: int = SCENE_PERIOD_NS
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
        return [layer.scene(t) for layer in (self._road_users, self._signals) if layer.changed]

    def _moved(self, event: dict[str, Any]) -> list[Derived]:
        self._road_users.put(event["src"], self._road_user(event))
        self._changed(event["t"])
        return []

    def _road_user(self, event: dict[str, Any]) -> fm.SceneEntity:
        src, body = event["src"], event["body"]
        look = self._looks.get(src) or self._look(src)
        x, y, heading = _number(body.get("x")), _number(body.get("y")), _number(body.get("heading_deg"))
        cubes = [fm.CubePrimitive(pose=_pose(x, y, look.height / 2, heading), size=look.size, color=look.color)]
        spheres = ([fm.SpherePrimitive(pose=_pose(x, y, look.height + 0.3), size=_BEACON_SIZE, color=_BEACON)]
                   if look.beacon else [])
        pairs = look.pairs + _pairs({"speed_mps": body.get("speed_mps"), "road": body.get("road"),
                                     "junction": body.get("junction")})
        return _entity(src, event["t"], pairs, cubes=cubes, spheres=spheres,
                       texts=[_label(look.ident, x, y, look.height + 1.5)])

    def _look(self, src: str) -> _Look:
        """How a road user is drawn, from its spawn event; kept until it spawns again (every
        state event of a run is drawn, so this is worked out once per road user, not per event)."""
        spawn = self.spawned.get(src, {})
        named = _text(spawn.get("type"))
        kind = named if named is not None and named in _BODIES else src.partition("/")[0]
        (length, width, height), rgb = _BODIES.get(kind, _BODIES["car"])
        pairs = _pairs({"src": src, "type": spawn.get("type"), "plate": spawn.get("plate")})
        look = _Look(_vec(length, width, height), _rgba(rgb), height, spawn.get("emergency") is True,
                     src.partition("/")[2], pairs)
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

    def _signal_entity(self, event: dict[str, Any]) -> fm.SceneEntity:
        """A signal beside its junction (the map's; at the origin while no map has placed it)."""
        body = event["body"]
        junction, approach = _text(body.get("junction")), _text(body.get("approach"))
        jx, jy = self.junctions.get(junction, (0.0, 0.0)) if junction is not None else (0.0, 0.0)
        dx, dy = _APPROACH.get(approach, (0, 0)) if approach is not None else (0, 0)
        x, y = jx + dx * _SIGNAL_OFFSET_M, jy + dy * _SIGNAL_OFFSET_M
        colour = _text(body.get("colour"))
        sphere = fm.SpherePrimitive(pose=_pose(x, y, 4.0), size=_vec(1.5, 1.5, 1.5),
                                    color=_rgba(_SIGNAL_COLOURS.get(colour or "off", _SIGNAL_COLOURS["off"])))
        pole = fm.CylinderPrimitive(pose=_pose(x, y, 1.6), size=_vec(0.2, 0.2, 3.2), color=_rgba((0.2, 0.2, 0.2)),
                                    bottom_scale=1.0, top_scale=1.0)
        metadata = {"junction": body.get("junction"), "approach": body.get("approach"), "colour": colour}
        return _entity(event["src"], event["t"], _pairs(metadata), spheres=[sphere], cylinders=[pole])

    def _map(self, event: dict[str, Any]) -> list[Derived]:
        world = read_run_map(event, _DRAWN_PARTS)
        if not world.recorded:
            return []
        points, cylinders, texts, arrows = [], [], [], []
        for road in world.roads:
            if road.a is not None and road.b is not None:       # a coordinate that is not a number: 0
                points += [fm.Point3(x=_or0(road.a[0]), y=_or0(road.a[1])),
                           fm.Point3(x=_or0(road.b[0]), y=_or0(road.b[1]))]
        for junction in world.junctions:
            x, y = _or0(junction.x), _or0(junction.y)
            self.junctions[str(junction.label)] = (x, y)
            cylinders.append(fm.CylinderPrimitive(pose=_pose(x, y, 0.02), size=_vec(14.0, 14.0, 0.04),
                                                  bottom_scale=1.0, top_scale=1.0, color=_rgba((0.35, 0.35, 0.4))))
            texts.append(_label(f"{junction.label} ({junction.control_label})", x, y, 8.0))
        for monitor in world.monitors:
            x, y = _or0(monitor.x), _or0(monitor.y)
            arrows.append(fm.ArrowPrimitive(pose=_pose(x, y, 3.0, _or0(monitor.heading_deg)),
                                            shaft_length=2.0, shaft_diameter=0.3, head_length=1.0,
                                            head_diameter=0.8, color=_rgba((0.7, 0.2, 0.9))))
            texts.append(_label(f"monitor {monitor.label}", x, y, 5.0))
        roads = fm.LinePrimitive(type=fm.LinePrimitiveLineType.LineList, pose=_pose(0.0, 0.0), thickness=7.0,
                                 scale_invariant=False, points=points, color=_rgba((0.5, 0.5, 0.5)))
        entity = _entity("map", event["t"], [], lines=[roads] if points else [], cylinders=cylinders,
                         texts=texts, arrows=arrows)
        if self._signal_events:  # signals drawn before the map (at the same t) move beside their junction
            for src, signal in self._signal_events.items():
                self._signals.put(src, self._signal_entity(signal))
            self._changed(event["t"])
        return [Derived(MAP_TOPIC, event["t"], fm.SceneUpdate(entities=[entity]).encode())]

    # --- the log -----------------------------------------------------------------------------

    def _decision(self, event: dict[str, Any]) -> list[Derived]:
        body, ident = event["body"], event["src"].partition("/")[2]
        permitted = body.get("permitted")
        answer = ("permitted" if permitted is True else "not permitted" if permitted is False
                  else "no rulebook answer recorded")
        did = "proceeds" if body.get("proceeds") else "holds"
        level = fm.LogLevel.Warning if body.get("proceeds") and permitted is False else fm.LogLevel.Info
        text = f"{ident} {did} to {body.get('action')} ({answer}; goal: {body.get('goal')})"
        return [_log(event, level, text)]

    def _violation(self, event: dict[str, Any]) -> list[Derived]:
        body = event["body"]
        text = f"potential violation by vehicle {body.get('vehicle')}: {body.get('action')}"
        facts = body.get("facts")
        if isinstance(facts, list) and facts:
            text += " — " + "; ".join(map(str, facts))
        return [_log(event, fm.LogLevel.Warning, text)]

    def _collision(self, event: dict[str, Any]) -> list[Derived]:
        entities = event["body"].get("entities")
        names = ", ".join(map(str, entities)) if isinstance(entities, list) else str(entities)
        return [_log(event, fm.LogLevel.Error, f"collision between {names}")]


def _log(event: dict[str, Any], level: fm.LogLevel, text: str) -> Derived:
    """A log line that names the event it came from: file is its key, line its seq."""
    message = fm.Log(timestamp=stamp(event["t"]), level=level, message=text, name=event["src"],
                     file=key_for(event), line=min(event["seq"], _UINT32))
    return Derived(LOG_TOPIC, event["t"], message.encode())


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

_SDK_CLASSES: dict[str, Any] = {SCENE_UPDATE: fm.SceneUpdate, LOG: fm.Log}


def schema_data(name: str) -> bytes:
    """The schema of SCENE_UPDATE or LOG as foxglove-sdk publishes it: a protobuf FileDescriptorSet."""
    schema = _SDK_CLASSES[name].get_schema()
    if schema.name != name or schema.encoding != ENCODING:
        raise ValueError(f"foxglove-sdk gives {schema.name!r} in {schema.encoding!r} for {name}; expected {ENCODING}")
    return bytes(schema.data)
