"""The per-kind JSON Schemas: one per v1 kind, required = DESIGN's bold fields, enums as given."""

import json
from importlib.resources import files

import pytest

from store import KINDS
from store.kinds import SCHEMAS

# DESIGN.md, "Kinds (v1)": the bold fields of each kind.
REQUIRED = {
    "run.start": [],
    "run.end": [],
    "entity.spawn": ["type"],
    "entity.state": ["x", "y", "speed_mps"],
    "entity.despawn": [],
    "signal.state": ["junction", "colour"],
    "vehicle.perception": ["facts"],
    "vehicle.decision": ["goal", "action", "proceeds"],
    "vehicle.trace": ["query", "answer"],
    "ads.event": ["event"],
    "monitor.observation": ["vehicle", "facts"],
    "monitor.potential_violation": ["vehicle", "action"],
    "collision": ["entities"],
}

JSON_TYPES = {"null", "boolean", "object", "array", "number", "string", "integer"}


def test_kinds_are_the_schema_files():
    folder = files("store").joinpath("schemas")
    assert KINDS == {entry.name.removesuffix(".json") for entry in folder.iterdir() if entry.name.endswith(".json")}
    assert KINDS == set(REQUIRED)


@pytest.mark.parametrize("kind", sorted(REQUIRED))
def test_schema_header(kind):
    schema = SCHEMAS[kind]
    assert schema["$schema"] == "https://json-schema.org/draft/2020-12/schema"
    assert schema["title"] == kind
    assert schema["type"] == "object"
    assert schema["additionalProperties"] is True
    assert schema["required"] == REQUIRED[kind]
    assert set(schema["required"]) <= set(schema["properties"])


@pytest.mark.parametrize(
    "kind, field, values",
    [
        ("entity.spawn", "type", ["car", "ambulance", "fire_engine", "police_car", "bus", "cyclist", "pedestrian"]),
        ("entity.spawn", "driver", ["human", "autonomous", "none"]),
        ("signal.state", "colour", ["red", "red_amber", "amber", "green", "off"]),
        (
            "ads.event",
            "event",
            [
                "activated",
                "deactivated",
                "transition_demand",
                "driver_override",
                "minimal_risk_manoeuvre",
                "emergency_manoeuvre_start",
                "emergency_manoeuvre_end",
                "failure",
            ],
        ),
    ],
)
def test_enums_from_design(kind, field, values):
    assert SCHEMAS[kind]["properties"][field]["enum"] == values


def test_map_junction_control_enum():
    junction = SCHEMAS["run.start"]["$defs"]["map"]["properties"]["junctions"]["items"]
    assert junction["properties"]["control"]["enum"] == ["lights", "stop", "give_way", "none"]


def test_proof_tree_status_enum():
    proof = SCHEMAS["vehicle.trace"]["$defs"]["proof"]
    assert proof["properties"]["status"]["enum"] == ["proved", "failed", "builtin", "fact"]


def _walk(node, path="#"):
    """Every (path, sub-schema dict) in a schema."""
    if isinstance(node, dict):
        yield path, node
        for key, value in node.items():
            yield from _walk(value, f"{path}/{key}")
    elif isinstance(node, list):
        for index, value in enumerate(node):
            yield from _walk(value, f"{path}/{index}")


@pytest.mark.parametrize("kind", sorted(REQUIRED))
def test_schema_is_well_formed(kind):
    """Types are JSON types and every $ref points at a definition in the same file."""
    schema = SCHEMAS[kind]
    for path, node in _walk(schema):
        if path.endswith(("/properties", "/$defs")):
            continue  # a map of names to schemas: a property named "type" is not the keyword
        kinds = node.get("type")
        if kinds is not None:
            assert set(kinds if isinstance(kinds, list) else [kinds]) <= JSON_TYPES, path
        ref = node.get("$ref")
        if isinstance(ref, str):
            assert ref.startswith("#/$defs/"), path
            assert ref.removeprefix("#/$defs/") in schema["$defs"], path


def test_schema_files_are_plain_utf8_json():
    folder = files("store").joinpath("schemas")
    for entry in folder.iterdir():
        if entry.name.endswith(".json"):
            json.loads(entry.read_bytes().decode("utf-8"))
