"""plain_event is the append path's fast lane: one function for the common event (canonical bytes,
unsigned, a known source, a flat body). It may pass an event over (None: the other roads decide),
but whatever it accepts must be exactly what the careful road (the standard parser, then
encode_event) makes of the same bytes; and the plain body check behind it may say yes only where
the schema and canonical's float walk both do."""
from __future__ import annotations

import json

import orjson
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from store import canonical_json, decode_event, plain_event
from store.body_check import body_ok, plain_body, quick_source
from store.canonical import PLAIN_FLOAT, _same_in_orjson, reference_canonical_json
from store import envelope
from store.kinds import KINDS, SCHEMAS
from tests.helpers.store_testkit import BODIES, careful, event

FLAT_KINDS = sorted(kind for kind in KINDS if quick_source(SCHEMAS[kind], plain=True) is not None)

_floats = st.floats() | st.sampled_from([0.0, -0.0, 1e-4, -1e-4, 9.99e-5, 1e16, -1e16, 9.999999999999998e15,
                                         1e-5, 2.5e-7, 1e300, 5e-324, 0.5, 8.25])
_values = st.recursive(
    st.none() | st.booleans() | st.integers(min_value=-(2 ** 64), max_value=2 ** 64) | _floats
    | st.text(max_size=4) | st.sampled_from(["car", "red", "activated", "human", "a" * 64, "0" * 64]),
    lambda inner: st.lists(inner, max_size=3) | st.dictionaries(st.sampled_from(["id", "x", "to"]), inner, max_size=2),
    max_leaves=8)


@st.composite
def bodies(draw, kinds=sorted(KINDS)):
    kind = draw(st.sampled_from(kinds))
    names = sorted(SCHEMAS[kind].get("properties", {})) + ["extra"]
    body = dict(BODIES[kind]) if draw(st.booleans()) else {}
    for name in draw(st.lists(st.sampled_from(names), max_size=4)):
        body[name] = draw(_floats | _values)  # half of them floats: numbers are where the writers differ
    for name in draw(st.lists(st.sampled_from(names), max_size=2)):
        body.pop(name, None)
    return kind, body


@settings(deadline=None, max_examples=400)
@given(bodies())
def test_the_plain_body_check_says_yes_only_where_the_schema_and_the_float_walk_do(case) -> None:
    kind, body = case
    if plain_body(kind)(body):
        assert body_ok(kind, body), (kind, body)
        assert _same_in_orjson(body.values()), (kind, body)
        assert orjson.dumps(body, option=orjson.OPT_SORT_KEYS) == reference_canonical_json(body)


@pytest.mark.parametrize("kind", FLAT_KINDS)
def test_the_plain_body_check_says_yes_to_the_plain_bodies(kind) -> None:
    """Else the lane would only cost time: every flat kind's ordinary body takes it, and so does one
    with more to say than its schema names, in scalars both writers spell alike (a simulation's
    states carry a lane, an acceleration, an emergency flag); a value there that orjson writes
    otherwise, or one with values inside, is left to the walk."""
    assert plain_body(kind)(dict(BODIES[kind]))
    assert plain_body(kind)({**BODIES[kind], "extra": 1.0, "lane": "w3_j11_1", "flag": False, "n": 7, "none": None})
    for other in (1e-05, 1e16, -2.5e-07, {"x": 1}, [1], 2 ** 64, -(2 ** 63) - 1):
        assert not plain_body(kind)({**BODIES[kind], "extra": other}), other


@settings(deadline=None, max_examples=500)
@given(st.floats())
def test_the_plain_float_is_the_float_walks_float(x) -> None:
    assert eval(PLAIN_FLOAT.format(x="x")) == _same_in_orjson([x])  # noqa: S307 (our own constant)


_twists = [
    lambda raw: raw,
    lambda raw: raw.replace(b'"seq":', b'"seq":1,"seq":', 1),
    lambda raw: raw.replace(b',', b', ', 1),
    lambda raw: raw.replace(b'"v":1', b'"v":true', 1),
    lambda raw: raw.replace(b'"v":1', b'"v":1.0', 1),
    lambda raw: raw.replace(b'"run":"r1"', b'"run":"r 1"', 1),
    lambda raw: raw.replace(b'"t":', b'"t":-', 1),
    lambda raw: raw.replace(b'"t":', b'"t":9', 1),
    lambda raw: raw.replace(b'"seq":', b'"seq":-', 1),
    lambda raw: raw.replace(b'}', b',"sig":{}}', 1),
    lambda raw: raw.replace(b'.0', b'.00', 1),
    lambda raw: raw.replace(b'"body":{', b'"body":{"zz":1e-05,', 1),
    lambda raw: raw[:-1],
]


@settings(deadline=None, max_examples=400)
@given(bodies(), st.sampled_from(range(len(_twists))), st.integers(0, 3))
def test_plain_event_accepts_only_what_the_careful_road_accepts_alike(case, twist, seq) -> None:
    kind, body = case
    decode_event(canonical_json(event(kind=kind)))  # the run and the (kind, src) are met before
    try:
        raw = _twists[twist](canonical_json(event(seq, kind=kind, body=body)))
    except (ValueError, TypeError):
        return
    plain = plain_event(raw)
    expected = careful(raw)
    if plain is not None:
        ev, run, src, seq_, kind_ = plain
        assert expected == ("ok", ev, raw)
        assert (run, src, seq_, kind_) == (ev["run"], ev["src"], ev["seq"], ev["kind"])
    got = decode_event(raw) if expected[0] == "ok" else None
    assert got is None or ("ok", *got) == expected


@pytest.mark.parametrize("kind", FLAT_KINDS)
def test_the_ordinary_events_take_the_first_road(kind, monkeypatch) -> None:
    """The one expression, not the itemised second road, judges what producers send all day."""
    raw = canonical_json(event(3, kind=kind))
    decode_event(canonical_json(event(kind=kind)))
    monkeypatch.setattr(envelope, "_plainly_valid", lambda ev: pytest.fail("the second road was taken"))
    plain = plain_event(raw)
    assert plain is not None and plain[0] == json.loads(raw)


def test_a_simulated_state_with_more_than_its_schema_names_takes_the_first_road(monkeypatch) -> None:
    body = {"accel_mps2": 0.34, "emergency": False, "heading_deg": 0.0, "junction": None, "lane": "w3_j11_1",
            "road": "r3", "speed_mps": 12.2, "x": -258.27, "y": 1001.75}
    decode_event(canonical_json(event(kind="entity.state")))
    raw = canonical_json(event(3, kind="entity.state", body=body))
    expected = careful(raw)
    monkeypatch.setattr(envelope, "_plainly_valid", lambda ev: pytest.fail("the second road was taken"))
    plain = plain_event(raw)
    assert plain is not None and ("ok", plain[0], raw) == expected


@pytest.mark.parametrize("ev", [
    event(kind="vehicle.perception", src="vehicle/never-met-before-plain"),    # the regular expressions' turn
    event(kind="vehicle.trace"),                                                # no plain check: nested schema
    {**event(), "sig": {"key": "0" * 16, "ed25519": "A" * 85 + "A=="}},         # signed
])
def test_the_other_canonical_events_take_the_second_road(ev) -> None:
    raw = canonical_json(ev)
    plain = plain_event(raw)
    assert plain is not None and ("ok", plain[0], raw) == careful(raw)
    assert plain[1:] == (ev["run"], ev["src"], ev["seq"], ev["kind"])
