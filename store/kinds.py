"""The event kinds: one JSON Schema per kind in store/schemas/, loaded once at import.

The schema files are the single source of the kind list and of which sources may send each
kind (the "x-src-roles" keyword, DESIGN's src column), so adding a kind is adding a file.
"""

from __future__ import annotations

import json
from importlib.resources import files
from types import MappingProxyType
from typing import Any, Mapping

_SUFFIX = ".json"


def _load_schemas() -> dict[str, dict[str, Any]]:
    """Read every schema file; the kind is the file name without .json."""
    folder = files(__package__).joinpath("schemas")
    schemas = {}
    for entry in folder.iterdir():
        if entry.name.endswith(_SUFFIX):
            kind = entry.name[: -len(_SUFFIX)]
            schemas[kind] = json.loads(entry.read_text(encoding="utf-8"))
    return dict(sorted(schemas.items()))


SCHEMAS: Mapping[str, dict[str, Any]] = MappingProxyType(_load_schemas())
KINDS: frozenset[str] = frozenset(SCHEMAS)

# Looked up once per event on the append path, so computed here rather than per call.
REQUIRED: Mapping[str, tuple[str, ...]] = MappingProxyType(
    {kind: tuple(schema.get("required", ())) for kind, schema in SCHEMAS.items()}
)

# DESIGN's "src" column: a signal cannot report what a vehicle perceived.
SRC_ROLES: Mapping[str, tuple[str, ...]] = MappingProxyType(
    {kind: tuple(schema["x-src-roles"]) for kind, schema in SCHEMAS.items()}
)
