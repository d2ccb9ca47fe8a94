"""Viewer-safe copies of JSON Schemas, for the schema records of MCAP channels.

Foxglove and Lichtblick turn a channel's JSON Schema into the field types their panels offer, and
their parser reads only `type`, `properties`, `items` and `contentEncoding`: every property must
have exactly one of the types object, array, string, number, integer or boolean; an object must
list its properties; an array's items must have one of those types other than array. A schema
that breaks any of these (a `$ref`, an `enum` without `type`, a type array such as
["string", "null"], a `oneOf`) is refused whole, and every message on the channel with it.

`viewer_safe` derives, from a schema of store/schemas, a copy that passes that parser and still
accepts every message the original accepts, so the schema written beside a message never refuses
it. The rules, applied mechanically:

- `$ref`s to `#/$defs/...` are inlined (their sibling keywords win); a definition that refers to
  itself is inlined once, and inside itself becomes an open object (any object validates).
- an `enum` or `const` without `type`, and a `oneOf`/`anyOf` of `const`s only (how enumerations
  are written), get the type of their values.
- a type array becomes one type when one type covers it (["integer", "number"] is "number").
- what has no single type (a type array with "null", an enum whose values differ in type, a
  `oneOf`/`anyOf` of shapes, an array of arrays or of such values) is left out of its object's
  `properties`, and named in that object's description. It is still in every message, and the
  viewers show it as it is; only its type is not declared. Dropping the null instead would type
  the field but make the schema refuse the messages where it is null.
- a `oneOf`/`anyOf` of shapes beside a declared `type` is dropped: the type alone accepts more.
- an object gets `"properties": {}` when it has none (any object), and a `contentEncoding` other
  than base64 is dropped (it is an annotation: a validator ignores it, Lichtblick refuses it).

The derivation raises ValueError on a keyword it does not know how to carry (allOf, if/then,
patternProperties, an external $ref, ...), so that a new schema using one fails the tests that
derive every schema, rather than reaching a viewer half-translated.
"""

from __future__ import annotations

import copy
from typing import Any

VIEWER_TYPES = ("object", "array", "string", "number", "integer", "boolean")
_ANNOTATIONS = {"$schema", "$id", "$comment", "title", "description", "examples", "default", "deprecated",
                "readOnly", "writeOnly", "format"}
_ASSERTIONS = {"type", "enum", "const", "properties", "required", "additionalProperties", "items", "minItems",
               "maxItems", "uniqueItems", "minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum", "multipleOf",
               "minLength", "maxLength", "pattern", "contentEncoding", "contentMediaType", "minProperties",
               "maxProperties", "oneOf", "anyOf"}
_DEFS_PREFIX = "#/$defs/"


def viewer_safe(schema: dict[str, Any]) -> dict[str, Any]:
    """A copy of `schema` that Foxglove's and Lichtblick's JSON Schema parser accepts."""
    schema = copy.deepcopy(schema)  # the copy shares nothing with the store's schemas
    defs = schema.get("$defs", {})
    inlined = _inline({k: v for k, v in schema.items() if k != "$defs"}, defs, ())
    safe = _typed(inlined)
    if safe is None or safe["type"] != "object":
        raise ValueError("a message schema must describe a JSON object")
    return safe


# --- inlining $ref ---------------------------------------------------------------------------


def _inline(node: Any, defs: dict[str, Any], stack: tuple[str, ...]) -> Any:
    if isinstance(node, list):
        return [_inline(item, defs, stack) for item in node]
    if not isinstance(node, dict):
        return node
    if "$ref" in node:
        return _resolve(node, defs, stack)
    return {key: value if key in ("enum", "const", "examples", "default") else _inline(value, defs, stack)
            for key, value in node.items()}


def _resolve(node: dict[str, Any], defs: dict[str, Any], stack: tuple[str, ...]) -> dict[str, Any]:
    ref = node["$ref"]
    if not isinstance(ref, str) or not ref.startswith(_DEFS_PREFIX) or ref[len(_DEFS_PREFIX):] not in defs:
        raise ValueError(f"cannot inline $ref {ref!r}: only #/$defs/<name> of the same schema")
    name = ref[len(_DEFS_PREFIX):]
    siblings = {k: _inline(v, defs, stack) for k, v in node.items() if k != "$ref"}
    if name in stack:  # recursion: one level is described, deeper ones are any value of the same type
        target = defs[name]
        open_node: dict[str, Any] = {"description": f"A {name} (nested levels are not described here)."}
        if target.get("type") == "object":
            open_node["type"] = "object"
        return {**open_node, **siblings}
    return {**_inline(defs[name], defs, (*stack, name)), **siblings}


# --- one type per value ----------------------------------------------------------------------


def _json_type(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "boolean"
    if isinstance(value, int):
        return "integer"
    if isinstance(value, float):
        return "number"
    if isinstance(value, str):
        return "string"
    return "array" if isinstance(value, list) else "object"


def _one(types: set[str]) -> str | None:
    """The one viewer type that covers all of `types`, if there is one."""
    if types == {"integer", "number"}:
        return "number"
    if len(types) == 1:
        (only,) = types
        return only if only in VIEWER_TYPES else None
    return None


def _consts(branches: Any) -> list[Any] | None:
    """The values of a oneOf/anyOf whose branches are all `const` (an enumeration), else None."""
    if not isinstance(branches, list) or not branches:
        return None
    if all(isinstance(b, dict) and "const" in b and set(b) <= _ANNOTATIONS | {"const"} for b in branches):
        return [b["const"] for b in branches]
    return None


def _type_of(node: dict[str, Any]) -> str | None:
    declared = node.get("type")
    if isinstance(declared, str):
        return declared if declared in VIEWER_TYPES else None
    if isinstance(declared, list):
        return _one(set(declared))
    values = node["enum"] if "enum" in node else [node["const"]] if "const" in node else None
    for combinator in ("oneOf", "anyOf"):
        if combinator in node:
            values = _consts(node[combinator])
            if values is None:
                return None  # alternatives of different shapes: no one type describes them
    if values is None or not values:
        return None
    return _one({_json_type(v) for v in values})


def _typed(node: Any) -> dict[str, Any] | None:
    """The viewer-safe copy of one (inlined) schema node, or None when it has no single type."""
    if not isinstance(node, dict):
        return None
    unknown = set(node) - _ANNOTATIONS - _ASSERTIONS
    unknown = {k for k in unknown if not k.startswith("x-")}
    if unknown:
        raise ValueError(f"no viewer-safe form for the keyword(s) {', '.join(sorted(unknown))}")
    kind = _type_of(node)
    if kind is None:
        return None
    out = dict(node, type=kind)
    for combinator in ("oneOf", "anyOf"):  # alternatives under a declared type: the type says enough
        if combinator in out and _consts(out[combinator]) is None:
            del out[combinator]
    if kind == "object":
        return _object(out)
    if kind == "array":
        items = _typed(node.get("items"))
        if items is None or items["type"] == "array":
            return None
        out["items"] = items
    if out.get("contentEncoding") not in (None, "base64"):
        del out["contentEncoding"]
    return out


def _object(node: dict[str, Any]) -> dict[str, Any]:
    properties, untyped = {}, []
    for name, sub in (node.get("properties") or {}).items():
        safe = _typed(sub)
        if safe is None:
            untyped.append(name)
        else:
            properties[name] = safe
    node["properties"] = properties
    if untyped:
        if node.get("additionalProperties", True) is not True:
            node.pop("additionalProperties")  # the untyped fields must still be accepted
        note = f"Not typed for viewers (no single JSON type): {', '.join(untyped)}."
        node["description"] = f"{node['description']} {note}" if node.get("description") else note
    return node
