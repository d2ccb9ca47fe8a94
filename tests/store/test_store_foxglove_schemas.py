"""The Foxglove schemas of an export come from foxglove-sdk, and what we draw is what they define:
every scene and log message can be rebuilt, field for field, with the SDK's own message classes,
and holds every field its schema declares (viewers differ in how they treat missing ones)."""

from __future__ import annotations

from importlib.metadata import version

import foxglove.messages as fm
import pytest

from store.transfer.foxglove import SceneBuilder
from store.transfer.foxglove_schemas import LOG, SCENE_UPDATE, codes, definitions, json_schema
from store.transfer.protobuf_descriptors import read_descriptor_set
from tests.helpers.viewer_run import viewer_events

_TIMES = {"google.protobuf.Timestamp": fm.Timestamp, "google.protobuf.Duration": fm.Duration}
_ENUMS = {"foxglove.LinePrimitive.Type": fm.LinePrimitiveLineType,
          "foxglove.SceneEntityDeletion.Type": fm.SceneEntityDeletionType, "foxglove.Log.Level": fm.LogLevel}


def sdk_message(value: dict, name: str, schema: str):
    """`value` (our JSON) as the SDK's message object: a field name or type the SDK does not
    have is a TypeError, and a field it has that we left out is an AssertionError."""
    message = definitions(schema).messages[name]
    fields = {f.name: f for f in message.fields}
    assert set(value) == set(fields), f"{name}: {sorted(set(value) ^ set(fields))}"
    kwargs = {}
    for key, raw in value.items():
        f = fields[key]
        convert = lambda v: _sdk_value(v, f.type, f.type_name.lstrip("."), schema)  # noqa: E731
        kwargs[key] = [convert(v) for v in raw] if f.repeated else convert(raw)
    return getattr(fm, name.rpartition(".")[2])(**kwargs)


def _sdk_value(value, kind: int, type_name: str, schema: str):
    if type_name in _TIMES:
        return _TIMES[type_name](**value)
    if kind == 11:
        return sdk_message(value, type_name, schema)
    if kind == 14:
        enum = _ENUMS[type_name]
        (member,) = [getattr(enum, n) for n in dir(enum) if isinstance(getattr(enum, n), enum) and int(getattr(enum, n)) == value]
        return member
    return value


def drawn() -> list:
    scene = SceneBuilder()
    return [item for ev in sorted(viewer_events(), key=lambda e: (e["t"], e["seq"], e["src"]))
            for item in scene.add(ev)] + scene.finish()


def test_every_drawn_message_is_one_the_sdk_can_build_and_encode():
    items = drawn()
    assert {item.topic for item in items} == {"/scene/map", "/scene/entities", "/scene/signals", "/log"}
    for item in items:
        schema = LOG if item.topic == "/log" else SCENE_UPDATE
        built = sdk_message(item.message, schema, schema)
        assert built.encode()


def test_the_schemas_are_the_sdks_descriptors_in_json():
    for name, cls in ((SCENE_UPDATE, fm.SceneUpdate), (LOG, fm.Log)):
        schema = json_schema(name)
        assert f"foxglove-sdk {version('foxglove-sdk')}" in schema["$comment"]
        top = read_descriptor_set(cls.get_schema().data).messages[name]
        assert list(schema["properties"]) == [f.name for f in top.fields]
    entity = json_schema(SCENE_UPDATE)["properties"]["entities"]["items"]
    assert entity["properties"]["timestamp"]["properties"].keys() == {"sec", "nsec"}
    line_type = entity["properties"]["lines"]["items"]["properties"]["type"]
    assert line_type["type"] == "integer" and [c["const"] for c in line_type["oneOf"]] == [0, 1, 2]
    model_data = entity["properties"]["models"]["items"]["properties"]["data"]
    assert model_data == {"type": "string", "contentEncoding": "base64"}


def test_the_enum_values_drawn_are_the_sdks():
    c = codes()
    assert c.line_list == int(fm.LinePrimitiveLineType.LineList)
    assert c.delete_all == int(fm.SceneEntityDeletionType.All)
    assert (c.info, c.warning, c.error) == (int(fm.LogLevel.Info), int(fm.LogLevel.Warning), int(fm.LogLevel.Error))


def test_a_misnamed_field_is_caught():
    """The check above bites: a field Foxglove does not define is refused."""
    log = next(item.message for item in drawn() if item.topic == "/log")
    with pytest.raises(AssertionError):
        sdk_message({**log, "colour": "red"}, LOG, LOG)
