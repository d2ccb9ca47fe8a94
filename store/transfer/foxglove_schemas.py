"""JSON Schemas of the two Foxglove well-known schemas our exports use, foxglove.SceneUpdate and
foxglove.Log, built from the fields Foxglove documents for them.

Foxglove and Lichtblick recognise these by schema name ("foxglove.SceneUpdate", "foxglove.Log")
with schema encoding jsonschema and message encoding json, and then draw the 3D scene and fill
the Log panel. In JSON, times and durations are {sec, nsec} objects and enums are integers.
"""

from __future__ import annotations

import json
from typing import Any

SCENE_UPDATE = "foxglove.SceneUpdate"
LOG = "foxglove.Log"

LINE_STRIP, LINE_LOOP, LINE_LIST = 0, 1, 2
UNKNOWN, DEBUG, INFO, WARNING, ERROR, FATAL = range(6)  # foxglove.LogLevel
MATCHING_ID, ALL = 0, 1  # foxglove.SceneEntityDeletionType


def _object(title: str, description: str, **properties: Any) -> dict[str, Any]:
    return {"title": title, "description": description, "type": "object", "properties": properties}


def _number(description: str = "") -> dict[str, Any]:
    return {"type": "number", "description": description} if description else {"type": "number"}


def _array(items: dict[str, Any], description: str) -> dict[str, Any]:
    return {"type": "array", "items": items, "description": description}


def _enum(title: str, description: str, names: list[str]) -> dict[str, Any]:
    return {"title": title, "description": description,
            "oneOf": [{"title": name, "const": value} for value, name in enumerate(names)]}


def _time(description: str) -> dict[str, Any]:
    return {"type": "object", "title": "time", "description": description, "properties": {
        "sec": {"type": "integer", "minimum": 0},
        "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999}}}


def _duration(description: str) -> dict[str, Any]:
    return {"type": "object", "title": "duration", "description": description, "properties": {
        "sec": {"type": "integer"},
        "nsec": {"type": "integer", "minimum": 0, "maximum": 999_999_999}}}


def _xyz(title: str, description: str) -> dict[str, Any]:
    return _object(title, description, x=_number(), y=_number(), z=_number())


def _quaternion() -> dict[str, Any]:
    return _object("foxglove.Quaternion", "A quaternion representing a rotation in 3D space",
                   x=_number(), y=_number(), z=_number(), w=_number())


def _pose(description: str) -> dict[str, Any]:
    return _object("foxglove.Pose", description,
                   position=_xyz("foxglove.Vector3", "Point denoting position in 3D space"),
                   orientation=_quaternion())


def _color(description: str = "Color") -> dict[str, Any]:
    channel = {"type": "number", "minimum": 0, "maximum": 1}
    return _object("foxglove.Color", description, r=channel, g=channel, b=channel, a=channel)


def _point3() -> dict[str, Any]:
    return _xyz("foxglove.Point3", "A point representing a position in 3D space")


def _primitive(name: str, description: str, **properties: Any) -> dict[str, Any]:
    return _object(f"foxglove.{name}", description, **properties)


def _primitives() -> dict[str, dict[str, Any]]:
    """The primitive arrays of a SceneEntity, by field name."""
    size = _xyz("foxglove.Vector3", "Size of the shape along each axis")
    indices = _array({"type": "integer", "minimum": 0}, "Indices into the points and colors attribute arrays")
    return {
        "arrows": _primitive("ArrowPrimitive", "A primitive representing an arrow",
                             pose=_pose("Position of the arrow's tail and orientation of the arrow"),
                             shaft_length=_number(), shaft_diameter=_number(), head_length=_number(),
                             head_diameter=_number(), color=_color()),
        "cubes": _primitive("CubePrimitive", "A primitive representing a cube or rectangular prism",
                            pose=_pose("Position of the center of the cube and orientation of the cube"),
                            size=size, color=_color()),
        "spheres": _primitive("SpherePrimitive", "A primitive representing a sphere or ellipsoid",
                              pose=_pose("Position of the center of the sphere and orientation of the sphere"),
                              size=size, color=_color()),
        "cylinders": _primitive("CylinderPrimitive", "A primitive representing a cylinder, elliptic cylinder, or truncated cone",
                                pose=_pose("Position of the center of the cylinder and orientation of the cylinder"),
                                size=size, bottom_scale=_number(), top_scale=_number(), color=_color()),
        "lines": _primitive("LinePrimitive", "A primitive representing a series of points connected by lines",
                            type=_enum("foxglove.LineType", "Drawing primitive to use for lines",
                                       ["LINE_STRIP", "LINE_LOOP", "LINE_LIST"]),
                            pose=_pose("Origin of lines relative to reference frame"),
                            thickness=_number("Line thickness"), scale_invariant={"type": "boolean"},
                            points=_array(_point3(), "Points along the line"), color=_color(),
                            colors=_array(_color(), "Per-point colors"), indices=indices),
        "triangles": _primitive("TriangleListPrimitive", "A primitive representing a set of triangles",
                                pose=_pose("Origin of triangles relative to reference frame"),
                                points=_array(_point3(), "Vertices to use for triangles"), color=_color(),
                                colors=_array(_color(), "Per-vertex colors"), indices=indices),
        "texts": _primitive("TextPrimitive", "A primitive representing a text label",
                            pose=_pose("Position of the center of the text box and orientation of the text"),
                            billboard={"type": "boolean"}, font_size=_number(), scale_invariant={"type": "boolean"},
                            color=_color(), text={"type": "string"}),
        "models": _primitive("ModelPrimitive", "A primitive representing a 3D model file loaded from an external URL or embedded data",
                             pose=_pose("Origin of model relative to reference frame"),
                             scale=_xyz("foxglove.Vector3", "Scale factor to apply to the model along each axis"),
                             color=_color(), override_color={"type": "boolean"}, url={"type": "string"},
                             media_type={"type": "string"},
                             data={"type": "string", "contentEncoding": "base64"}),
    }


def scene_update_schema() -> dict[str, Any]:
    entity = _object(
        "foxglove.SceneEntity",
        "A visual element in a 3D scene. An entity may be composed of multiple primitives which all share the same frame of reference.",
        timestamp=_time("Timestamp of the entity"),
        frame_id={"type": "string", "description": "Frame of reference"},
        id={"type": "string", "description": "Identifier for the entity; replaces any prior entity on the same topic with the same id"},
        lifetime=_duration("How long after timestamp the entity is removed; zero keeps it until replaced or deleted"),
        frame_locked={"type": "boolean"},
        metadata=_array(_object("foxglove.KeyValuePair", "A key with its associated value",
                                key={"type": "string"}, value={"type": "string"}), "Additional user-provided metadata"),
        **{name: _array(item, item["description"]) for name, item in _primitives().items()},
    )
    deletion = _object(
        "foxglove.SceneEntityDeletion", "Command to remove previously published entities",
        timestamp=_time("Only matching entities earlier than this timestamp are deleted"),
        type=_enum("foxglove.SceneEntityDeletionType", "Type of deletion action to perform", ["MATCHING_ID", "ALL"]),
        id={"type": "string", "description": "Identifier which must match if type is MATCHING_ID"},
    )
    return _object(SCENE_UPDATE, "An update to the entities displayed in a 3D scene",
                   deletions=_array(deletion, "Scene entities to delete"),
                   entities=_array(entity, "Scene entities to add or replace"))


def log_schema() -> dict[str, Any]:
    schema = _object(LOG, "A log message",
                     timestamp=_time("Timestamp of log message"),
                     level=_enum("foxglove.LogLevel", "Log level",
                                 ["UNKNOWN", "DEBUG", "INFO", "WARNING", "ERROR", "FATAL"]),
                     message={"type": "string", "description": "Log message"},
                     name={"type": "string", "description": "Process or node name"},
                     file={"type": "string", "description": "Filename"},
                     line={"type": "integer", "minimum": 0, "description": "Line number in the file"})
    schema["required"] = ["timestamp", "level", "message", "name", "file", "line"]
    return schema


def schema_bytes(schema: dict[str, Any]) -> bytes:
    return json.dumps(schema, separators=(",", ":")).encode("utf-8")
