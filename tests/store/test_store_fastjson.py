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


@given(st.lists(values, max_size=12))
def test_parsing_a_chunk_at_once_gives_each_value_as_alone(chunk):
    texts = [json.dumps(value, ensure_ascii=False) for value in chunk]
    together = fastjson.loads_all(texts)
    assert json.dumps(together) == json.dumps([json.loads(text) for text in texts])


def test_a_big_integer_in_one_text_of_a_chunk_stays_exact():
    texts = ['{"a": 1.5}', '{"b": 123456789012345678901234567890}', '{"c": -9223372036854775809}']
    assert fastjson.loads_all(texts)[1]["b"] == 123456789012345678901234567890
    assert isinstance(fastjson.loads_all(texts)[2]["c"], int)


def test_texts_that_do_not_join_into_one_array_are_parsed_alone():
    # "1, 2" is no JSON text on its own; joined it would look like two values
    texts = ['{"a": 1}', "[1, 2]", '"x"']
    assert fastjson.loads_all(texts) == [{"a": 1}, [1, 2], "x"]
    try:
        fastjson.loads_all(['{"a": 1}', "1, 2"])
    except ValueError:
        pass
    else:
        raise AssertionError("a text that is not JSON alone was accepted")
