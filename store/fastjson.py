"""Parsing stored JSON fast, with exactly the values the standard parser would give.

Reading the state at a time parses a few hundred kilobytes of snapshot and event JSON; orjson
does that three to four times faster than `json`.  But orjson reads an integer outside 64 bits
(above 2**64-1, or below -2**63) as a float, silently; an evidence locker cannot round a value.
So any text that could hold such an integer (a run of 20 digits, or a negative run of 19) is
parsed by `json` instead, as is anything orjson refuses.  Only reading uses this: the canonical
form that is hashed is written by `store.canonical` alone.
"""

from __future__ import annotations

import json
from typing import Any

import orjson

# Every digit becomes "0", "-" stays, everything else a space: then two substring searches
# find the risky runs, an order of magnitude faster than a regular expression over digit runs.
_DIGITS = bytes(48 if 48 <= b <= 57 else 45 if b == 45 else 32 for b in range(256))
_TWENTY_DIGITS = b"0" * 20
_NEGATIVE_NINETEEN = b"-" + b"0" * 19


def _may_hold_big_int(raw: bytes) -> bool:
    shape = raw.translate(_DIGITS)
    return _TWENTY_DIGITS in shape or _NEGATIVE_NINETEEN in shape


def loads(data: bytes | str) -> Any:
    raw = data.encode("utf-8") if isinstance(data, str) else data
    if not _may_hold_big_int(raw):
        try:
            return orjson.loads(raw)
        except orjson.JSONDecodeError:
            pass
    return json.loads(raw)


def loads_all(texts: list[str]) -> list[Any]:
    """Each text parsed, as `loads` would parse it alone. The texts are joined into one JSON
    array and parsed at once: a reader of hundreds of thousands of small events pays the call
    and the digit-run search once a chunk, not once an event. A text that is not JSON on its
    own (it would break the array) is no concern here: every stored event is canonical JSON,
    and if the array does not parse as exactly len(texts) values, each text is parsed alone."""
    if not texts:
        return []
    joined = "[" + ",".join(texts) + "]"
    try:
        values = loads(joined)
    except ValueError:
        values = None
    if type(values) is list and len(values) == len(texts):
        return values
    return [loads(text) for text in texts]
