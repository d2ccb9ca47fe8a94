"""Canonical JSON: the single byte form of an event that is hashed, stored and compared.

Two producers that mean the same event must produce the same bytes, or the hash chain and
duplicate detection would depend on key order and whitespace. The form is: keys sorted, no
insignificant whitespace, non-ASCII written as UTF-8 (not \\u escapes), NaN and infinities
refused. Numbers are written the way Python's json module writes them (integers as digits,
floats as the shortest repr that round-trips); a verifier in another language must do the same.
"""

from __future__ import annotations

import json
from typing import Any

# Built once: json.dumps with non-default options would build a new encoder on every call,
# and this function runs once per event on the hot append path.
_ENCODER = json.JSONEncoder(
    sort_keys=True,
    separators=(",", ":"),
    ensure_ascii=False,
    allow_nan=False,
)


def canonical_json(obj: Any) -> bytes:
    """Return the canonical UTF-8 bytes of a JSON value.

    Raises ValueError (NaN, infinity, circular data, text that is not valid Unicode),
    TypeError (values JSON cannot express) or RecursionError (absurdly deep nesting).
    """
    return _ENCODER.encode(obj).encode("utf-8")
