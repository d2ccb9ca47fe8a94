"""canonical_json: one byte form per JSON value, whatever the key order or spacing."""

import json

import pytest
from hypothesis import given, settings, strategies as st

from store import canonical_json

json_values = st.recursive(
    st.none()
    | st.booleans()
    | st.integers()
    | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(alphabet=st.characters(exclude_categories=("Cs",))),
    lambda children: st.lists(children, max_size=5)
    | st.dictionaries(st.text(alphabet=st.characters(exclude_categories=("Cs",)), max_size=8), children, max_size=5),
    max_leaves=30,
)


def test_sorted_keys_no_whitespace_utf8():
    assert canonical_json({"b": 1, "a": [1, 2, {"d": None, "c": True}], "é": "ü"}) == (
        '{"a":[1,2,{"c":true,"d":null}],"b":1,"é":"ü"}'.encode("utf-8")
    )


def test_non_ascii_is_raw_utf8_not_escaped():
    assert canonical_json("173 hat rotes Licht – ß") == '"173 hat rotes Licht – ß"'.encode("utf-8")
    assert b"\\u" not in canonical_json("é")


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), float("-inf"), {"x": [float("nan")]}])
def test_nan_and_infinity_refused(bad):
    with pytest.raises(ValueError):
        canonical_json(bad)


def test_lone_surrogate_refused():
    with pytest.raises(ValueError):
        canonical_json("\ud800")


@settings(deadline=None)
@given(json_values)
def test_canonical_form_is_a_fixed_point(value):
    once = canonical_json(value)
    assert canonical_json(json.loads(once)) == once


@settings(deadline=None)
@given(st.dictionaries(st.text(max_size=6, alphabet="abcxyz"), st.integers(), min_size=1, max_size=8), st.randoms())
def test_key_order_does_not_matter(mapping, rnd):
    items = list(mapping.items())
    rnd.shuffle(items)
    assert canonical_json(dict(items)) == canonical_json(mapping)


@settings(deadline=None)
@given(json_values)
def test_spacing_of_the_input_does_not_matter(value):
    spaced = json.dumps(value, indent=3, ensure_ascii=True)
    assert canonical_json(json.loads(spaced)) == canonical_json(value)


@settings(deadline=None)
@given(json_values)
def test_same_bytes_as_json_dumps_with_the_canonical_options(value):
    """canonical_json reuses the C encoder for speed; json.dumps is the reference it must match."""
    reference = json.dumps(value, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False)
    assert canonical_json(value) == reference.encode("utf-8")


def test_circular_data_refused():
    loop: list = []
    loop.append(loop)
    with pytest.raises((ValueError, RecursionError)):
        canonical_json({"body": loop})


@pytest.mark.parametrize("bad", [{"x": {1, 2}}, {"x": b"bytes"}, {("a",): 1}])
def test_values_json_cannot_express_refused(bad):
    with pytest.raises(TypeError):
        canonical_json(bad)


# --- the orjson fast path must give the reference's bytes, or the reference's refusal -------------

import dataclasses  # noqa: E402
import datetime  # noqa: E402
import enum  # noqa: E402
import math  # noqa: E402
import sys  # noqa: E402
import uuid  # noqa: E402

import orjson  # noqa: E402

from store.canonical import reference_canonical_json  # noqa: E402


def outcome(encode, value):
    """The bytes, or the kind of refusal: what callers can observe of an encoder."""
    try:
        return encode(value)
    except (ValueError, TypeError, RecursionError) as exc:
        return type(exc)


def assert_same_as_reference(value):
    expected = outcome(reference_canonical_json, value)
    got = outcome(canonical_json, value)
    assert got == expected, (value, got, expected)


any_float = st.floats()  # NaN, infinities, -0.0, subnormals, huge, tiny
wide_integers = st.integers() | st.integers(min_value=-(2**70), max_value=2**70) | st.sampled_from(
    [2**63 - 1, 2**63, 2**64 - 1, 2**64, -(2**63), -(2**63) - 1, -(2**64)]
)
any_text = st.text()  # surrogates included: both must refuse them
any_json = st.recursive(
    st.none() | st.booleans() | wide_integers | any_float | any_text,
    lambda children: st.lists(children, max_size=5)
    | st.lists(children, max_size=3).map(tuple)
    | st.dictionaries(any_text, children, max_size=5),
    max_leaves=30,
)


@settings(deadline=None, max_examples=2000)
@given(any_json)
def test_fast_path_matches_the_reference_on_arbitrary_values(value):
    assert_same_as_reference(value)


@settings(deadline=None, max_examples=500)
@given(st.dictionaries(any_text, st.integers(), max_size=8))
def test_fast_path_sorts_keys_like_the_reference(mapping):
    assert_same_as_reference(mapping)


@settings(deadline=None, max_examples=3000)
@given(any_float)
def test_every_float_is_written_as_the_reference_writes_it(x):
    assert_same_as_reference(x)
    assert_same_as_reference({"body": {"x": x, "y": [x, -x]}})


@pytest.mark.parametrize("x", [
    1e-05, 2.5e-07, 9.999999999999999e-05, 1e-4, 0.00012345, 1e15, 9999999999999998.0, 1e16, 1e17,
    1.2345678901234568e16, 1e21, 1e22, 1e100, 1.7976931348623157e308, 5e-324, 2.2250738585072014e-308,
    -0.0, 0.0, -1e-05, -1e16, 0.1, 100.0, -5.25, 1732184100.35,
    math.nextafter(1e-4, 0.0), math.nextafter(1e-4, 1.0), math.nextafter(1e16, 0.0), math.nextafter(1e16, math.inf),
])
def test_floats_near_where_the_formats_differ(x):
    assert canonical_json([x]) == reference_canonical_json([x])
    assert canonical_json([x]) == f"[{x!r}]".encode()


def test_orjson_would_differ_on_these_floats_so_the_guard_is_needed():
    """The reason for _same_in_orjson: if orjson ever wrote these like repr, the guard could be
    loosened; until then, a fast path without it would change stored bytes."""
    assert orjson.dumps(1e-05) != repr(1e-05).encode()
    assert orjson.dumps(2.5e-07) != repr(2.5e-07).encode()
    assert orjson.dumps(float("nan")) == b"null"


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_non_finite_floats_deep_inside_are_refused(bad):
    with pytest.raises(ValueError):
        canonical_json({"body": {"a": [1, {"b": (2, bad)}], "junction": None}})


def test_every_code_point_is_written_as_the_reference_writes_it():
    chunk = 4096
    for start in range(0, sys.maxunicode + 1, chunk):
        text = "".join(chr(c) for c in range(start, min(start + chunk, sys.maxunicode + 1))
                       if not 0xD800 <= c <= 0xDFFF)
        assert canonical_json({text: text}) == reference_canonical_json({text: text}), hex(start)


def test_keys_sort_by_code_point_across_planes():
    keys = ["\U00010000", "\uffff", "\ufb01", "é", "z", "Z", "", "a\x00", "a", "\x7f", "\u2028"]
    value = {key: i for i, key in enumerate(keys)}
    assert canonical_json(value) == reference_canonical_json(value)


class _Colour(enum.Enum):
    RED = "red"


class _Level(enum.IntEnum):
    FOUR = 4


class _Text(str):
    pass


class _Mapping(dict):
    pass


@dataclasses.dataclass
class _Point:
    x: float = 1.0


@pytest.mark.parametrize("value", [
    _Colour.RED, uuid.UUID(int=7), _Point(), datetime.date(2024, 11, 21), orjson.Fragment(b"1"),
    {"body": {"colour": _Colour.RED}}, {"body": {"id": uuid.UUID(int=7)}}, [datetime.datetime(2024, 1, 1)],
])
def test_values_orjson_writes_but_json_refuses_are_still_refused(value):
    with pytest.raises(TypeError):
        reference_canonical_json(value)
    with pytest.raises(TypeError):
        canonical_json(value)


@pytest.mark.parametrize("value", [
    _Level.FOUR, {"automation_level": _Level.FOUR}, _Text("car"), {"type": _Text("car")}, _Mapping(a=1),
    {1: "int key"}, {True: 1, False: 2}, {2.5: 1}, {"big": 2**64}, {"small": -(2**63) - 1}, 10**400,
])
def test_values_only_the_reference_writes_get_the_reference_bytes(value):
    assert canonical_json(value) == reference_canonical_json(value)


def test_nesting_deeper_than_orjson_allows_gets_the_reference_bytes():
    value: list = []
    for _ in range(400):
        value = [value]
    assert canonical_json(value) == reference_canonical_json(value)


def test_a_typical_event_takes_the_fast_path(monkeypatch):
    """The speed is the point: an ordinary event must not fall back to the reference."""
    import store.canonical as canonical

    def no_reference(obj):
        raise AssertionError("fell back to the reference encoder")

    monkeypatch.setattr(canonical, "reference_canonical_json", no_reference)
    event = {"v": 1, "run": "r1", "src": "vehicle/173", "seq": 4, "t": 1732184100350000000, "kind": "entity.state",
             "body": {"x": -400.0, "y": -5.25, "speed_mps": 12.0, "heading_deg": 0.0, "road": "r1", "junction": None,
                      "facts": ["173 has red light", "é"], "pair": (1, 2)}}
    assert canonical.canonical_json(event) == json.dumps(
        event, sort_keys=True, separators=(",", ":"), ensure_ascii=False, allow_nan=False).encode()


@settings(deadline=None, max_examples=1000)
@given(st.dictionaries(any_text.filter(lambda k: k != "reason"), any_json, max_size=5),
       st.integers(min_value=0, max_value=2**63 - 1), st.integers(min_value=-(2**63), max_value=2**63 - 1))
def test_an_appended_event_is_stored_in_the_reference_form_whatever_its_body(body, seq, t):
    """encode_event writes plain envelopes through canonical_plain_event, which walks only the
    body: the envelope's own fields must never need the reference."""
    from store.envelope import EventError, encode_event

    ev = {"v": 1, "run": "r1", "src": "vehicle/173", "seq": seq, "t": t, "kind": "entity.despawn", "body": body}
    expected = outcome(reference_canonical_json, ev)
    try:
        got = encode_event(ev)
    except EventError:
        got = "refused"
    if isinstance(expected, bytes):
        assert got == expected
    else:
        assert got == "refused"
