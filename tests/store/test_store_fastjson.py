"""Fast parsing of stored JSON gives exactly what `json` gives, big integers included."""
import json

from hypothesis import given, strategies as st

from store import fastjson

values = st.recursive(
    st.none() | st.booleans() | st.integers() | st.floats(allow_nan=False, allow_infinity=False) | st.text(),
    lambda inner: st.lists(inner, max_size=4) | st.dictionaries(st.text(max_size=5), inner, max_size=4),
    max_leaves=20)


@given(values)
def test_same_values_and_types_as_json(value):
    text = json.dumps(value, ensure_ascii=False)
    fast, reference = fastjson.loads(text), json.loads(text)
    assert fast == reference
    assert json.dumps(fast) == json.dumps(reference)      # no int silently turned into a float


def test_integers_beyond_64_bits_stay_exact():
    for literal in ("123456789012345678901234567890", "-9223372036854775809", "18446744073709551616"):
        assert fastjson.loads(literal) == int(literal) and isinstance(fastjson.loads(literal), int)
