"""Canonical JSON: the single byte form of an event that is hashed, stored and compared.

Two producers that mean the same event must produce the same bytes, or the hash chain and
duplicate detection would depend on key order and whitespace. The form is: keys sorted, no
insignificant whitespace, non-ASCII written as UTF-8 (not \\u escapes), NaN and infinities
refused. Numbers are written the way Python's json module writes them (integers as digits,
floats as the shortest repr that round-trips); a verifier in another language must do the same.

The definition is `reference_canonical_json` (json.dumps with the options above). Every stored
chain was hashed over those bytes, so they may never change. `canonical_json` gives the same
bytes five times faster for the values events are made of: it writes with orjson, and takes
orjson's bytes only when the value is one whose bytes orjson is known to write identically
(`_same_in_orjson`), else it writes with the reference. Where the two differ, and why the
check is enough:

- floats: both write the shortest repr that round-trips, but orjson uses other exponent rules
  (1e-05 is "0.00001", 2.5e-07 is "2.5e-7"); in 1e-4 <= |x| < 1e16, and for zeros, both write
  the plain decimal repr gives. Other floats, NaN and infinities (which orjson writes as null
  without complaint) go to the reference, which writes or refuses them as always.
- types: orjson writes enums, UUIDs, dataclasses, dates and subclasses of dict, list, str and
  int, which json refuses or writes its own way; only the exact types json.loads produces (and
  tuples, arrays to both) take the fast path.
- what orjson refuses and json writes (integers beyond 64 bits, keys that are not str,
  nesting deeper than 255) raises in orjson and goes to the reference; so do lone surrogates,
  which the reference then refuses.
- strings and key order: the same for every code point and key (tests/store/test_store_canonical.py
  compares them over all of Unicode and over arbitrary JSON values).
"""

from __future__ import annotations

import json
import json.encoder
from typing import Any, Callable, Iterable

import orjson

# Built once: json.dumps with non-default options would build a new encoder on every call.
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


def reference_canonical_json(obj: Any) -> bytes:
    """The canonical bytes as defined: json.dumps(obj, sort_keys=True, separators=(",", ":"),
    ensure_ascii=False, allow_nan=False) in UTF-8. Raises like canonical_json."""
    if _C_ENCODE is None:
        return _ENCODER.encode(obj).encode("utf-8")
    return "".join(_C_ENCODE(obj, 0)).encode("utf-8")


PLAIN_FLOAT = "1e-4 <= {x} < 1e16 or -1e16 < {x} <= -1e-4 or {x} == 0.0"
"""The floats orjson writes as the reference does, as a Python condition on {x} (_same_in_orjson's
test, which generated checks (store/body_check.py) use as source)."""

_ORJSON_DUMPS = orjson.dumps
_SORT_KEYS = orjson.OPT_SORT_KEYS
_SCALARS = frozenset((str, int, bool, type(None)))


def _same_in_orjson(values: Iterable[Any]) -> bool:
    """Are these values, and everything inside them, of a kind orjson writes exactly as the
    reference does? (Called on a value orjson has written, so it holds no cycles and nests at
    most 255 deep.) Floats outside [1e-4, 1e16) in magnitude, other than zero, answer no: that
    also catches NaN, which fails every comparison, and the infinities."""
    for value in values:
        kind = type(value)
        if kind in _SCALARS:
            continue
        if kind is float:
            if not (1e-4 <= value < 1e16 or -1e16 < value <= -1e-4 or value == 0.0):
                return False
        elif kind is dict:
            if not _same_in_orjson(value.values()):
                return False
        elif kind is list or kind is tuple:
            if not _same_in_orjson(value):
                return False
        else:
            return False
    return True


def canonical_json(obj: Any) -> bytes:
    """Return the canonical UTF-8 bytes of a JSON value (byte for byte reference_canonical_json).

    Raises ValueError (NaN, infinity, text that is not valid Unicode), TypeError (values JSON
    cannot express) or RecursionError (absurdly deep nesting, circular data).
    """
    try:
        data = _ORJSON_DUMPS(obj, option=_SORT_KEYS)
        if _same_in_orjson((obj,)):
            return data
    except (TypeError, RecursionError):  # orjson.JSONEncodeError is a TypeError
        pass
    return reference_canonical_json(obj)


def canonical_plain_event(ev: dict) -> bytes | None:
    """canonical_json(ev) for the append path, or None where the caller must use canonical_json.

    Only for an event whose envelope has been found plain (envelope._plainly_valid): exactly
    the seven fields (and a `sig` of two exact strs, if signed), v, seq and t ints of exact type
    within 64 bits, run, src and kind exact strs, body an exact dict. orjson writes all of those
    as the reference does, so only the body needs _same_in_orjson's walk; that saves a third of
    the cost per event.
    """
    try:
        data = _ORJSON_DUMPS(ev, option=_SORT_KEYS)
        if _same_in_orjson(ev["body"].values()):
            return data
    except (TypeError, RecursionError):
        pass
    return None
