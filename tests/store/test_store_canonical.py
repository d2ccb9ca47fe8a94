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
