"""The JSON Schema of an MCAP event channel: the whole envelope, with the kind's body schema.

An MCAP message on `gaps/<run>/<src>/<kind>` is the full event envelope, so its schema describes
the envelope and takes `body` from store/schemas/<kind>.json. The body schema's $defs move to the
top so that its "#/$defs/..." references still resolve, and the envelope's rules are written out
so that a tool that knows nothing of this project can check a message with the schema alone.

What an export writes into the file is the viewer-safe copy of that schema (viewer_schema.py):
Foxglove and Lichtblick refuse a channel whose schema uses $ref, an untyped enum or a type array,
and with it every message on the channel. The copy accepts every message the exact schema accepts;
its description names the exact schema it was derived from.
"""

from __future__ import annotations

import json
from functools import lru_cache
from typing import Any

from ..envelope import ENVELOPE_FIELDS, ROLES
from ..kinds import SCHEMAS
from .viewer_schema import viewer_safe

_ID = "[A-Za-z0-9._-]{1,64}"
_INT64 = {"type": "integer", "minimum": -(1 << 63), "maximum": (1 << 63) - 1}


def envelope_schema(kind: str) -> dict[str, Any]:
    """The schema of an event message of this kind."""
    body = dict(SCHEMAS[kind])
    defs = body.pop("$defs", None)
    dialect = body.pop("$schema", "https://json-schema.org/draft/2020-12/schema")
    body.pop("$id", None)
    schema: dict[str, Any] = {
        "$schema": dialect,
        "$id": f"urn:mind-the-gaps:message:v1:{kind}",
        "title": kind,
        "description": f"A mind-the-gaps event of kind {kind}: the envelope, with the body of the kind.",
        "type": "object",
        "required": list(ENVELOPE_FIELDS),
        "additionalProperties": False,
        "properties": {
            "v": {"type": "integer", "const": 1, "description": "Envelope version."},
            "run": {"type": "string", "pattern": f"^{_ID}$"},
            "src": {"type": "string", "pattern": f"^({'|'.join(ROLES)})/{_ID}$"},
            "seq": {"type": "integer", "minimum": 0, "maximum": (1 << 63) - 1,
                    "description": "Per (run, src), from 0, rising by 1."},
            "t": {**_INT64, "description": "World time, integer nanoseconds since the Unix epoch."},
            "kind": {"type": "string", "const": kind},
            "body": body,
            "sig": {
                "type": "object",
                "description": "The source's Ed25519 signature over the event's canonical JSON without sig "
                               "(optional; docs/store.md, Signatures).",
                "required": ["key", "ed25519"],
                "additionalProperties": False,
                "properties": {
                    "key": {"type": "string", "pattern": "^[0-9a-f]{16}$",
                            "description": "Key id: the first 16 hex digits of sha256(public key)."},
                    "ed25519": {"type": "string", "pattern": "^[A-Za-z0-9+/]{85}[AQgw]==$",
                                "description": "The 64-byte signature, standard base64."},
                },
            },
        },
    }
    if defs:
        schema["$defs"] = defs
    return schema


def viewer_envelope_schema(kind: str) -> dict[str, Any]:
    """The viewer-safe copy of envelope_schema(kind), as written into MCAP files."""
    exact = envelope_schema(kind)
    schema = viewer_safe(exact)
    schema["$id"] = f"{exact['$id']}:viewer"
    schema["description"] = (f"{exact['description']} Viewer-safe copy of {exact['$id']} (body: "
                             f"{SCHEMAS[kind].get('$id', kind)}, store/schemas/{kind}.json), derived by "
                             f"store/transfer/viewer_schema.py: it accepts every message the exact schema accepts.")
    return schema


@lru_cache(maxsize=None)
def schema_bytes(kind: str) -> bytes:
    """The schema as written into an MCAP Schema record: the viewer-safe copy."""
    return json.dumps(viewer_envelope_schema(kind), separators=(",", ":"), sort_keys=True).encode("utf-8")
