"""Canonical JSON: the single byte form of an event that is hashed, stored and compared.

Two producers that mean the same event must produce the same bytes, or the hash chain and
duplicate detection would depend on key order and whitespace. The form is: keys sorted, no
insignificant whitespace, non-ASCII written as UTF-8 (not \\u escapes), NaN and infinities
refused. Numbers are written the way Python's json module writes them (integers as digits,
floats as the shortest repr that round-trips); a verifier in another language must do the same.
"""

from __future__ import annotations

import json
import json.encoder
from typing import Any, Callable

# Built once: json.dumps with non-default options would build a new encoder on every call,
# and this function runs once per event on the hot append path.
_ENCODER = json.JSONEncoder(
    sort_keys=True,
    separators=(",", ":"),
    ensure_ascii=False,
    allow_nan=False,
)


def _c_encoder() -> Callable[[Any, int], Any] | None:
    """The C encoder behind _ENCODER, made once instead of on every encode() call (which is
    what JSONEncoder.encode does); a third of the cost of encoding a small event. Same options,
    same bytes. No circular-reference bookkeeping: circular data recurses until RecursionError,
    which callers already treat as unencodable. None where CPython's C accelerator is missing."""
    make = getattr(json.encoder, "c_make_encoder", None)
    if make is None:
        return None
    return make(None, _ENCODER.default, json.encoder.encode_basestring, None, ":", ",", True, False, False)


_C_ENCODE = _c_encoder()


def canonical_json(obj: Any) -> bytes:
    """Return the canonical UTF-8 bytes of a JSON value.

    Raises ValueError (NaN, infinity, text that is not valid Unicode), TypeError (values JSON
    cannot express) or RecursionError (absurdly deep nesting, circular data).
    """
    if _C_ENCODE is None:
        return _ENCODER.encode(obj).encode("utf-8")
    return "".join(_C_ENCODE(obj, 0)).encode("utf-8")
