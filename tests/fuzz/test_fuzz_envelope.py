"""Envelope decoding fuzzed: any bytes, and valid envelopes mutated a few bytes or fields at a time,
give an event or a refusal with its reason, never an exception; an event accepted is one the
store's own validation accepts again from its canonical bytes."""
from __future__ import annotations

import json

from hypothesis import given
from hypothesis import strategies as st

from store.envelope import decode_event
from store.intake import from_raw
from tests.fuzz.budget import fuzz
from tests.helpers.store_testkit import BODIES, event

KINDS = sorted(BODIES)
VALID = [json.dumps(event(i, kind=kind)).encode() for i, kind in enumerate(KINDS)]
JSON_VALUES = st.recursive(st.none() | st.booleans() | st.integers() | st.floats(allow_nan=True) | st.text(max_size=20),
                           lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=8), inner, max_size=4),
                           max_leaves=12)


def assert_decodes_cleanly(raw: bytes) -> None:
    candidate = from_raw(raw, "fuzz")
    assert (candidate.event is None) != (candidate.reason is None)
    assert candidate.raw == raw
    if candidate.event is not None:
        again, canonical = decode_event(candidate.canonical)
        assert canonical == candidate.canonical and again == candidate.event


@fuzz(150)
@given(st.binary(max_size=600))
def test_any_bytes(raw):
    assert_decodes_cleanly(raw)


@fuzz(80)
@given(st.sampled_from(VALID), st.lists(st.tuples(st.integers(0, 10_000), st.integers(0, 255)), min_size=1, max_size=4))
def test_mutated_bytes_of_valid_envelopes(raw, edits):
    data = bytearray(raw)
    for position, byte in edits:
        data[position % len(data)] = byte
    assert_decodes_cleanly(bytes(data))


@fuzz(60)
@given(st.sampled_from(KINDS), st.sampled_from(["v", "run", "src", "seq", "t", "kind", "body", "sig", "extra"]),
       JSON_VALUES)
def test_a_field_replaced_by_any_json_value(kind, field, value):
    ev = event(3, kind=kind)
    ev[field] = value
    assert_decodes_cleanly(json.dumps(ev, allow_nan=True).encode())
