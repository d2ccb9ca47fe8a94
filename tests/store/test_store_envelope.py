"""The envelope: every malformed event is refused with an EventError that says what was wrong."""

import json

import pytest
from tests.helpers.store_testkit import BODIES, event
from hypothesis import given, settings, strategies as st

from store import KINDS, MAX_EVENT_BYTES, EventError, parse_event, validate_event
from store.wire import key_for
from store.envelope import _CHECKS, _plainly_valid, decode_event, encode_event
from store.kinds import REQUIRED


def refusal(ev) -> EventError:
    with pytest.raises(EventError) as caught:
        validate_event(ev)
    return caught.value


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_a_valid_event_of_every_kind_passes(kind):
    validate_event(event(kind=kind))


def test_unknown_body_fields_are_kept_not_refused():
    ev = event(body={"facts": ["173 is stopped"], "camera": {"id": "c9", "confidence": 0.8}})
    validate_event(ev)
    assert parse_event(json.dumps(ev).encode())["body"]["camera"] == {"id": "c9", "confidence": 0.8}


@pytest.mark.parametrize(
    "field, value, says",
    [
        ("v", 2, "v must be 1"),
        ("v", True, "v must be 1"),
        ("v", "1", "v must be 1"),
        ("run", "", "run must be"),
        ("run", "demo/001", "run must be"),
        ("run", "a" * 65, "run must be"),
        ("run", 7, "run must be"),
        ("run", "demo\n", "run must be"),
        ("src", "vehicle", "src must be '<role>/<id>'"),
        ("src", "truck/1", "src role 'truck'"),
        ("src", "vehicle/", "src id"),
        ("src", "vehicle/1/2", "src id"),
        ("src", "vehicle/a b", "src id"),
        ("src", ["vehicle", "1"], "src must be"),
        ("seq", -1, "seq must be between 0"),
        ("seq", 2**63, "seq must be between 0"),
        ("seq", 1.0, "seq must be an integer"),
        ("seq", True, "seq must be an integer"),
        ("seq", "3", "seq must be an integer"),
        ("t", "12.5s", "t must be integer nanoseconds"),
        ("t", 1.5, "t must be integer nanoseconds"),
        ("t", False, "t must be integer nanoseconds"),
        ("t", 2**64, "t must fit in 64 bits"),
        ("kind", "vehicle.dream", "kind 'vehicle.dream' is unknown"),
        ("kind", None, "kind None is unknown"),
        ("body", [], "body must be a JSON object"),
        ("body", None, "body must be a JSON object"),
    ],
)
def test_each_bad_field_is_named(field, value, says):
    error = refusal(dict(event(), **{field: value}))
    assert error.field == field
    assert says in str(error)


@pytest.mark.parametrize("field", ["v", "run", "src", "seq", "t", "kind", "body"])
def test_missing_envelope_field_is_named(field):
    ev = event()
    del ev[field]
    error = refusal(ev)
    assert error.field == field
    assert f"missing envelope field(s) {field}" in str(error)


def test_unknown_envelope_field_is_refused():
    error = refusal(dict(event(), meta={"x": 1}))
    assert error.field == "envelope"
    assert "'meta'" in str(error)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_each_required_body_field_is_named(kind):
    for name in BODIES[kind]:
        body = dict(BODIES[kind])
        del body[name]
        ev = event(kind=kind, body=body)
        if name in REQUIRED[kind]:
            error = refusal(ev)
            assert error.field == f"body.{name}"
            assert f"lacks required field(s) {name}" in str(error)
        else:
            validate_event(ev)


@pytest.mark.parametrize("facts", ["173 has red light", [1, 2], ["ok", None], {"a": "b"}])
@pytest.mark.parametrize("kind", ["vehicle.perception", "monitor.observation", "monitor.potential_violation"])
def test_facts_must_be_a_list_of_strings(kind, facts):
    body = dict(BODIES[kind], facts=facts)
    error = refusal(event(kind=kind, body=body))
    assert error.field.startswith("body.facts")
    assert str(error).startswith(f"event run=r1 src={event(kind=kind)['src']} seq=0: {kind} body.facts")


def test_message_names_run_src_and_seq_when_known():
    error = refusal(event(seq=42, run="demo-001", src="monitor/m1", t="later"))
    assert str(error).startswith("event run=demo-001 src=monitor/m1 seq=42: t must be")
    assert (error.run, error.src, error.seq) == ("demo-001", "monitor/m1", 42)


def test_message_leaves_out_what_is_itself_invalid():
    error = refusal(dict(event(seq=3), src="alien/1"))
    assert str(error).startswith("event run=r1 seq=3: src role 'alien'")
    assert error.src is None


def test_not_an_object():
    for value in ([], "event", 3, None):
        assert refusal(value).field == "event"


def test_long_hostile_values_are_quoted_briefly():
    error = refusal(dict(event(), run="x" * 100_000))
    assert len(str(error)) < 300


# --- parse_event: bytes as received ---------------------------------------------------------


def test_parse_roundtrip_with_any_spacing():
    ev = event(seq=5)
    assert parse_event(json.dumps(ev, indent=2).encode()) == ev


def test_size_limit_is_exactly_one_mebibyte():
    base = event(kind="run.end", body={"reason": ""})
    padding = MAX_EVENT_BYTES - len(json.dumps(base, separators=(",", ":")).encode())
    at_limit = json.dumps(dict(base, body={"reason": "x" * padding}), separators=(",", ":")).encode()
    assert len(at_limit) == MAX_EVENT_BYTES
    assert parse_event(at_limit)["body"]["reason"] == "x" * padding
    with pytest.raises(EventError) as caught:
        parse_event(at_limit + b" ")
    assert caught.value.field == "size"
    assert f"{MAX_EVENT_BYTES + 1} bytes, over the {MAX_EVENT_BYTES}-byte limit" in str(caught.value)


def test_oversized_dict_is_refused_when_encoded():
    ev = event(kind="run.end", body={"reason": "x" * MAX_EVENT_BYTES})
    with pytest.raises(EventError) as caught:
        encode_event(ev)
    assert caught.value.field == "size"


def test_invalid_utf8():
    raw = json.dumps(event()).encode().replace(b"red", b"r\xffd")
    with pytest.raises(EventError) as caught:
        parse_event(raw)
    assert caught.value.field == "utf-8"
    assert f"at byte {raw.index(bytes([0xFF]))}" in str(caught.value)


def test_malformed_json_gives_line_and_column():
    with pytest.raises(EventError) as caught:
        parse_event(b'{"v": 1,\n  "run": }')
    assert caught.value.field == "json"
    assert "line 2, column 10" in str(caught.value)


@pytest.mark.parametrize("raw", [b"[1, 2]", b'"event"', b"42", b"null"])
def test_top_level_must_be_an_object(raw):
    with pytest.raises(EventError, match="must be a JSON object"):
        parse_event(raw)


@pytest.mark.parametrize("constant", [b"NaN", b"Infinity", b"-Infinity"])
def test_nan_literals_refused(constant):
    raw = json.dumps(event(kind="entity.state")).encode().replace(b"8.25", constant)
    with pytest.raises(EventError, match="not valid JSON"):
        parse_event(raw)


def test_number_overflowing_to_infinity_refused():
    raw = json.dumps(event(kind="entity.state")).encode().replace(b"8.25", b"1e999")
    with pytest.raises(EventError, match="canonical JSON"):
        parse_event(raw)


def test_duplicate_keys_refused():
    raw = json.dumps(event(seq=1)).encode().replace(b'"seq": 1', b'"seq": 1, "seq": 2')
    with pytest.raises(EventError, match="duplicate key 'seq'"):
        parse_event(raw)


def test_deep_nesting_refused_not_crashing():
    with pytest.raises(EventError) as caught:
        parse_event(b"[" * (MAX_EVENT_BYTES - 1))
    assert caught.value.field == "json"


def test_deeply_nested_body_refused_not_crashing():
    deep: list = []
    for _ in range(100_000):
        deep = [deep]
    with pytest.raises(EventError, match="canonical JSON"):
        encode_event(event(kind="run.end", body={"reason": "x", "deep": deep}))


def test_lone_surrogate_refused():
    raw = json.dumps(event()).encode().replace(b"red light", b"red \\ud800 light")
    with pytest.raises(EventError, match="canonical JSON"):
        parse_event(raw)


def test_huge_integer_refused():
    raw = json.dumps(event()).encode().replace(b'"seq": 0', b'"seq": ' + b"9" * 5000)
    with pytest.raises(EventError) as caught:
        parse_event(raw)
    assert caught.value.field == "json"


def test_prolog_looking_strings_are_just_text():
    facts = ["X :- halt.", "'; shell('rm -rf /')."]
    assert parse_event(json.dumps(event(body={"facts": facts})).encode())["body"]["facts"] == facts


def test_decode_returns_canonical_bytes():
    ev, canonical = decode_event(b' { "body": {"facts": []}, "v": 1, "run": "r", "src": "vehicle/s", '
                                 b'"seq": 0, "t": 0, "kind": "vehicle.perception" } ')
    assert canonical == b'{"body":{"facts":[]},"kind":"vehicle.perception","run":"r","seq":0,"src":"vehicle/s","t":0,"v":1}'


def test_raw_must_be_bytes():
    with pytest.raises(TypeError):
        parse_event(json.dumps(event()))


def test_key_for():
    ev = event(run="demo-001", src="vehicle/173", kind="vehicle.perception")
    assert key_for(ev) == "gaps/demo-001/vehicle/173/vehicle.perception"


# --- the fast path never accepts what the itemised checks refuse ------------------------------

_values = st.one_of(
    st.none(), st.booleans(), st.integers(min_value=-(2**70), max_value=2**70), st.floats(allow_nan=False),
    st.text(max_size=70), st.sampled_from(["r1", "vehicle/1", "sim/x", "signal/", "collision", "vehicle.perception"]),
    st.lists(st.text(max_size=3), max_size=2), st.dictionaries(st.sampled_from(["facts", "type", "x"]), st.text(max_size=3)),
)


@settings(deadline=None)
@given(st.dictionaries(st.sampled_from(["v", "run", "src", "seq", "t", "kind", "body", "extra"]), _values),
       st.sampled_from(sorted(KINDS)))
def test_fast_path_agrees_with_the_checks(overrides, kind):
    ev = dict(event(kind=kind), **overrides)
    if _plainly_valid(ev):
        assert all(check(ev) is None for check in _CHECKS)
