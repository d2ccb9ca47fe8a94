"""decode_event takes a fast road for bytes that are already canonical; it must end exactly where
the careful road (the standard parser refusing duplicate keys and NaN, then encode_event) ends,
for any bytes at all: the same event and canonical bytes, or the same refusal."""
from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from store import EventError, canonical_json
from store.envelope import _already_canonical, decode_event
from tests.helpers.store_testkit import careful, event


def fast(raw: bytes):
    try:
        ev, data = decode_event(raw)
        return ("ok", ev, data)
    except EventError as exc:
        return ("refused", str(exc))


values = st.recursive(
    st.none() | st.booleans() | st.integers(min_value=-(2 ** 70), max_value=2 ** 70)
    | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=8),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner, max_size=3),
    max_leaves=12)


@settings(max_examples=300, deadline=None)
@given(body=st.dictionaries(st.text(max_size=6), values, max_size=4))
def test_canonical_bytes_of_any_body_end_where_the_careful_road_ends(body) -> None:
    ev = event(kind="entity.state", body={"x": 1.0, "y": 2.0, "speed_mps": 3.0, **body})
    try:
        raw = canonical_json(ev)
    except (ValueError, TypeError):
        return
    assert fast(raw) == careful(raw)


@pytest.mark.parametrize("twist", [
    lambda raw: raw.replace(b'"seq":', b'"seq":1,"seq":', 1),                 # a duplicate key
    lambda raw: raw.replace(b'"x":1.0', b'"x":NaN', 1),
    lambda raw: raw.replace(b'"x":1.0', b'"x":18446744073709551616', 1),     # beyond 64 bits
    lambda raw: raw.replace(b'"x":1.0', b'"x":1e400', 1),
    lambda raw: raw.replace(b'"x":1.0', b'"x":"\\ud800"', 1),                 # a lone surrogate
    lambda raw: raw.replace(b'"x":1.0', b'"x":1.00', 1),                      # not the canonical number
    lambda raw: raw.replace(b',', b', ', 1),                                  # whitespace
    lambda raw: raw.replace(b'"v":1', b'"v":2', 1),                           # invalid envelope
    lambda raw: raw + b" ",
    lambda raw: b"\xef\xbb\xbf" + raw,                                         # a byte-order mark
])
def test_bytes_not_canonical_take_the_careful_road(twist) -> None:
    raw = twist(canonical_json(event(kind="entity.state", body={"x": 1.0, "y": 2.0, "speed_mps": 3.0})))
    assert _already_canonical(raw) is None
    assert fast(raw) == careful(raw)


@settings(max_examples=300, deadline=None)
@given(text=st.text(max_size=60))
def test_any_text_ends_where_the_careful_road_ends(text) -> None:
    raw = text.encode("utf-8", "surrogatepass")
    assert fast(raw) == careful(raw)


def test_the_fast_road_is_taken_for_canonical_bytes() -> None:
    raw = canonical_json(event(kind="entity.state", body={"x": 1.0, "y": 2.0, "speed_mps": 3.0}))
    assert _already_canonical(raw) == json.loads(raw)
