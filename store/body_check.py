"""Checking an event's body against its kind's JSON Schema (store/schemas/<kind>.json).

The schemas are compiled by fastjsonschema into plain Python functions, once per kind and only
when a kind is first seen, so that commands which never append start fast. fastjsonschema reads
our 2020-12 schemas with its draft 2019-09 rules; the keywords the schemas use (type, enum,
required, properties, items as one schema, min/max, minLength, pattern, oneOf, $ref to $defs)
mean the same in both drafts.
"""

from __future__ import annotations

from typing import Any, Callable

import fastjsonschema

from .describe import json_type, show
from .kinds import SCHEMAS

Validator = Callable[..., Any]
_compiled: dict[str, Validator] = {}


def validator(kind: str) -> Validator:
    """The compiled schema of a known kind (KeyError for an unknown one)."""
    found = _compiled.get(kind)
    if found is None:
        found = _compiled[kind] = fastjsonschema.compile(SCHEMAS[kind])
    return found


def body_ok(kind: str, body: Any) -> bool:
    """Does the body satisfy its schema? The fast yes/no of the append path."""
    try:
        (_compiled.get(kind) or validator(kind))(body)
    except (fastjsonschema.JsonSchemaValueException, RecursionError):
        return False
    return True


def body_problem(kind: str, body: Any) -> tuple[str, str] | None:
    """(field, sentence) for the first schema rule the body breaks, or None.

    The field is the failing path ("body.speed_mps", "body.facts[1]"), the sentence names the
    kind, the path, the rule and (briefly) the value, for the person reading the quarantine.
    """
    try:
        validator(kind)(body, name_prefix="body")
    except fastjsonschema.JsonSchemaValueException as exc:
        shown = f"{json_type(exc.value)} {show(exc.value)}"
        return exc.name, f"{kind} {exc.message} (schema rule {exc.rule}), got {shown}"
    except RecursionError:
        return "body", f"{kind} body is nested too deeply to check"
    return None
