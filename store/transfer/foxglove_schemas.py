"""The Foxglove well-known schemas our exports draw with (foxglove.SceneUpdate, foxglove.Log), as
JSON Schemas derived from Foxglove's own published definitions: the `foxglove-sdk` package.

What is taken from foxglove-sdk: `foxglove.messages.SceneUpdate.get_schema()` and
`foxglove.messages.Log.get_schema()`, the schemas the SDK itself writes into MCAP files: each a
protobuf FileDescriptorSet holding every message of the schema (SceneEntity, the primitives, Pose,
Color, ...) with its fields and enumerations. The SDK exposes no JSON Schemas, so the descriptor is
read (protobuf_descriptors.py) and written out in Foxglove's JSON conventions: a time or duration
(google.protobuf.Timestamp, Duration) is {"sec", "nsec"}, an enum is its integer value (typed
"integer", its names as `oneOf` consts), bytes are a base64 string, a repeated field an array, a
double a number. Field names, nesting and enum values therefore come from Foxglove, never from
here; the enum values the drawing uses (LINE_LIST, the log levels, the deletion of ALL) are read
from the same descriptors (`codes()`). Every field is optional, as in protobuf: the drawing fills
them all anyway, because viewers differ in how they treat missing ones.

The result is also what Lichtblick's JSON Schema parser needs (every field one type, enums typed),
which Foxglove's own published JSON Schema files are not (their enums have no "type").

foxglove-sdk is imported on first use, not with the store: only an MCAP export with its drawing
needs it, and loading it costs a tenth of a second.
"""

from __future__ import annotations

import copy
import json
from dataclasses import dataclass
from functools import lru_cache
from importlib.metadata import version
from typing import Any

from .protobuf_descriptors import Definitions, FieldDef, read_descriptor_set

SCENE_UPDATE = "foxglove.SceneUpdate"
LOG = "foxglove.Log"
_SDK_CLASS = {SCENE_UPDATE: "SceneUpdate", LOG: "Log"}  # in foxglove.messages
SDK = "foxglove-sdk"

_NSEC = {"type": "integer", "minimum": 0, "maximum": 999_999_999}
_TIMES = {
    "google.protobuf.Timestamp": {"title": "time", "type": "object",
                                  "properties": {"sec": {"type": "integer", "minimum": 0}, "nsec": _NSEC}},
    "google.protobuf.Duration": {"title": "duration", "type": "object",
                                 "properties": {"sec": {"type": "integer"}, "nsec": _NSEC}},
}
_UNSIGNED = {"type": "integer", "minimum": 0}
# FieldDescriptorProto.Type -> JSON Schema (11 message and 14 enum are handled apart)
_SCALARS: dict[int, dict[str, Any]] = {
    1: {"type": "number"}, 2: {"type": "number"},  # double, float
    3: {"type": "integer"}, 5: {"type": "integer"}, 15: {"type": "integer"}, 16: {"type": "integer"},
    17: {"type": "integer"}, 18: {"type": "integer"},  # int64, int32, sfixed32, sfixed64, sint32, sint64
    4: _UNSIGNED, 6: _UNSIGNED, 7: _UNSIGNED, 13: _UNSIGNED,  # uint64, fixed64, fixed32, uint32
    8: {"type": "boolean"},
    9: {"type": "string"},
    12: {"type": "string", "contentEncoding": "base64"},  # bytes
}
_MESSAGE, _ENUM = 11, 14


@lru_cache(maxsize=None)
def definitions(name: str) -> Definitions:
    """The messages and enums of one of Foxglove's schemas, from foxglove-sdk's descriptor."""
    from foxglove import messages  # see the module docstring: loaded only when drawing

    schema = getattr(messages, _SDK_CLASS[name]).get_schema()
    if schema.name != name or schema.encoding != "protobuf":
        raise ValueError(f"{SDK} gives {schema.name!r} in {schema.encoding!r} for {name}; expected a protobuf schema")
    return read_descriptor_set(schema.data)


def _message(defs: Definitions, name: str, within: tuple[str, ...]) -> dict[str, Any]:
    if name in _TIMES:
        return copy.deepcopy(_TIMES[name])
    if name in within:
        raise ValueError(f"{name} contains itself; a JSON Schema for viewers cannot")
    message = defs.messages[name]
    return {"title": name, "type": "object",
            "properties": {f.name: _field(defs, f, (*within, name)) for f in message.fields}}


def _field(defs: Definitions, field: FieldDef, within: tuple[str, ...]) -> dict[str, Any]:
    target = field.type_name.lstrip(".")
    if field.type == _MESSAGE:
        item = _message(defs, target, within)
    elif field.type == _ENUM:
        enum = defs.enums[target]
        item = {"title": enum.name, "type": "integer",
                "oneOf": [{"title": label, "const": number} for label, number in enum.values]}
    elif field.type in _SCALARS:
        item = dict(_SCALARS[field.type])
    else:
        raise ValueError(f"field {field.name} of type {field.type} has no JSON form here")
    return {"type": "array", "items": item} if field.repeated else item


@lru_cache(maxsize=None)
def json_schema(name: str) -> dict[str, Any]:
    """The JSON Schema of SCENE_UPDATE or LOG, as written into MCAP Schema records."""
    schema = _message(definitions(name), name, ())
    schema["$comment"] = (f"Derived from the protobuf descriptor of {name} in {SDK} {version(SDK)} "
                          f"(foxglove.messages.{_SDK_CLASS[name]}.get_schema()), in Foxglove's JSON conventions.")
    return schema


def schema_bytes(name: str) -> bytes:
    return json.dumps(json_schema(name), separators=(",", ":")).encode("utf-8")


def enum_value(name: str, enum: str, label: str) -> int:
    """The number of `label` in the enum `enum` (full name) of the schema `name`."""
    return dict(definitions(name).enums[enum].values)[label]


@dataclass(frozen=True)
class Codes:
    """The enum values the drawing writes, as Foxglove's descriptors number them."""

    line_list: int
    delete_all: int
    info: int
    warning: int
    error: int


@lru_cache(maxsize=None)
def codes() -> Codes:
    line, deletion, level = "foxglove.LinePrimitive.Type", "foxglove.SceneEntityDeletion.Type", "foxglove.Log.Level"
    return Codes(
        line_list=enum_value(SCENE_UPDATE, line, "LINE_LIST"),
        delete_all=enum_value(SCENE_UPDATE, deletion, "ALL"),
        info=enum_value(LOG, level, "INFO"),
        warning=enum_value(LOG, level, "WARNING"),
        error=enum_value(LOG, level, "ERROR"),
    )
