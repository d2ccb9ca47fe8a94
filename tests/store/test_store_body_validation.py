"""Every body is checked against its kind's full JSON Schema, and every source against the roles
DESIGN allows for the kind; refusals name the event, the kind, the failing path and the rule."""

import json

import pytest
from tests.helpers.store_testkit import BODIES, event

from store import EventError, validate_event
from store.body_check import validator
from store.kinds import KINDS, SCHEMAS, SRC_ROLES

ANY = ("vehicle", "monitor", "signal", "pedestrian", "sim")

# DESIGN.md, "Kinds (v1)", the src column.
ROLES = {
    "run.start": ("sim",),
    "run.end": ("sim",),
    "entity.spawn": ANY,
    "entity.state": ("vehicle", "pedestrian"),
    "entity.despawn": ANY,
    "signal.state": ("signal",),
    "vehicle.perception": ("vehicle",),
    "vehicle.decision": ("vehicle",),
    "vehicle.trace": ("vehicle",),
    "ads.event": ("vehicle",),
    "monitor.observation": ("monitor",),
    "monitor.potential_violation": ("monitor",),
    "collision": ("sim",),
}


def refusal(ev) -> EventError:
    with pytest.raises(EventError) as caught:
        validate_event(ev)
    return caught.value


def test_roles_are_designs_src_column():
    assert dict(SRC_ROLES) == ROLES


@pytest.mark.parametrize("kind", sorted(KINDS))
@pytest.mark.parametrize("role", ANY)
def test_each_kind_only_from_its_roles(kind, role):
    ev = event(kind=kind, src=f"{role}/x1")
    if role in ROLES[kind]:
        validate_event(ev)
    else:
        error = refusal(ev)
        assert error.field == "src"
        assert str(error) == (f"event run=r1 src={role}/x1 seq=0: kind {kind} comes only from src role(s) "
                              f"{', '.join(ROLES[kind])}, not from {role}/x1")


# (kind, body change, failing path, rule, words of the message)
BAD_BODIES = [
    ("entity.state", {"speed_mps": "fast"}, "body.speed_mps", "type", "body.speed_mps must be number"),
    ("entity.state", {"speed_mps": -1}, "body.speed_mps", "minimum", "bigger than or equal to 0"),
    ("entity.state", {"x": True}, "body.x", "type", "body.x must be number"),
    ("entity.state", {"junction": 4}, "body.junction", "type", "must be string or null"),
    ("entity.spawn", {"type": "tank"}, "body.type", "enum", "must be one of"),
    ("entity.spawn", {"automation_level": 6}, "body.automation_level", "maximum", "smaller than or equal to 5"),
    ("entity.spawn", {"automation_level": -1}, "body.automation_level", "minimum", "bigger than or equal to 0"),
    ("entity.spawn", {"automation_level": 2.5}, "body.automation_level", "type", "must be integer"),
    ("entity.spawn", {"driver": "ghost"}, "body.driver", "enum", "must be one of"),
    ("entity.spawn", {"emergency": "yes"}, "body.emergency", "type", "must be boolean"),
    ("signal.state", {"colour": "blue"}, "body.colour", "enum", "must be one of ['red', 'red_amber', 'amber'"),
    ("signal.state", {"junction": ""}, "body.junction", "minLength", "longer than or equal to 1"),
    ("vehicle.perception", {"facts": ["173 is stopped", ""]}, "body.facts[1]", "minLength", "longer than"),
    ("vehicle.perception", {"facts": [1]}, "body.facts[0]", "type", "must be string"),
    ("vehicle.perception", {"facts": "173 is stopped"}, "body.facts", "type", "must be array"),
    ("monitor.observation", {"facts": [""]}, "body.facts[0]", "minLength", "longer than"),
    ("monitor.observation", {"speed_mps": -3}, "body.speed_mps", "minimum", "bigger than"),
    ("vehicle.decision", {"proceeds": "yes"}, "body.proceeds", "type", "must be boolean"),
    ("vehicle.decision", {"rulebook": "abc"}, "body.rulebook", "pattern", "must match pattern"),
    ("vehicle.decision", {"trace": -1}, "body.trace", "minimum", "bigger than"),
    ("vehicle.trace", {"answer": 3}, "body.answer", "oneOf", "exactly by one definition"),
    ("vehicle.trace", {"proof": {"sentence": "s", "status": "proved", "children": [{"sentence": "t", "status": "?"}]}},
     "body.proof.children[0].status", "enum", "must be one of"),
    ("ads.event", {"event": "nap"}, "body.event", "enum", "must be one of"),
    ("collision", {"entities": []}, "body.entities", "minItems", "must contain at least 1 items"),
    ("run.start", {"seed": "seven"}, "body.seed", "type", "must be integer"),
    ("run.start", {"map": {"junctions": [{"id": "j1", "x": 0, "y": 0, "control": "roundabout"}]}},
     "body.map.junctions[0].control", "enum", "must be one of"),
    ("run.start", {"rulebooks": [{"name": "hc", "sha256": "xyz", "text": ""}]}, "body.rulebooks[0].sha256",
     "pattern", "must match pattern"),
    ("run.end", {"reason": 5}, "body.reason", "type", "must be string"),
]


@pytest.mark.parametrize("kind, change, path, rule, words", BAD_BODIES, ids=[f"{b[0]}:{b[2]}" for b in BAD_BODIES])
def test_schema_violations_are_named(kind, change, path, rule, words):
    ev = event(4, kind=kind, body=dict(BODIES[kind], **change))
    error = refusal(ev)
    assert error.field == path
    message = str(error)
    assert message.startswith(f"event run=r1 src={ev['src']} seq=4: {kind} {path} ")
    assert words in message
    assert f"(schema rule {rule})" in message


def test_the_briefs_example_message():
    error = refusal(event(4, kind="entity.state", body={"x": 0, "y": 0, "speed_mps": "fast"}))
    assert str(error) == ("event run=r1 src=vehicle/173 seq=4: entity.state body.speed_mps must be number "
                          "(schema rule type), got string 'fast'")


def test_extra_fields_are_allowed_at_every_level():
    body = {"facts": ["173 is stopped"], "camera": {"id": "c9"},
            "proof": {"anything": [1, 2]}}
    validate_event(event(kind="vehicle.perception", body=body))
    start = {"map": {"roads": [{"id": "r", "from": [0, 0], "to": [1, 1], "lanes": 2}], "extra": True}}
    validate_event(event(kind="run.start", body=start))


def test_an_empty_facts_list_is_valid():
    validate_event(event(body={"facts": []}))


def test_deeply_nested_proof_is_refused_not_crashing():
    node: dict = {"sentence": "s", "status": "proved"}
    for _ in range(5_000):
        node = {"sentence": "s", "status": "proved", "children": [node]}
    error = refusal(event(kind="vehicle.trace", body={"query": "q", "answer": True, "proof": node}))
    assert error.field == "body"
    assert "nested too deeply" in str(error)


def test_every_schema_compiles_once():
    for kind in KINDS:
        assert validator(kind) is validator(kind)


def test_refused_bodies_are_quarantined_on_append(store):
    bad = event(0, kind="signal.state", body={"junction": "J1", "colour": "blue"})
    misrouted = event(1, kind="vehicle.perception", src="signal/J1")
    report = store.append([bad, misrouted, event(0)])
    assert report.stored == 1
    reasons = [r.reason for r in report.rejected]
    assert "signal.state body.colour must be one of" in reasons[0]
    assert "kind vehicle.perception comes only from src role(s) vehicle" in reasons[1]
    assert [q["reason"] for q in store.quarantined()] == reasons


def test_raw_input_is_validated_too(store):
    raw = json.dumps(event(0, kind="entity.state", body={"x": 0, "y": 0, "speed_mps": -2})).encode()
    report = store.append_raw([(raw, "file.jsonl:3")])
    assert report.rejected[0].origin == "file.jsonl:3"
    assert "body.speed_mps must be bigger than or equal to 0" in report.rejected[0].reason
    assert store.quarantined()[0]["raw"] == raw


def test_the_schemas_use_only_keywords_with_the_same_meaning_in_draft_2019_and_2020():
    """fastjsonschema applies 2019-09 rules; these keywords mean the same in 2020-12 (items as
    one schema, not the tuple form whose meaning changed)."""
    keywords = {"$schema", "$id", "$ref", "$defs", "title", "description", "x-src-roles", "type", "required",
                "additionalProperties", "properties", "items", "enum", "minimum", "maximum", "minItems",
                "maxItems", "minLength", "pattern", "oneOf",
                "exclusiveMinimum"}     # a number in both drafts (the boolean form was draft 4's)

    def walk(schema):
        for key, value in schema.items():
            assert key in keywords, key
            if key in ("properties", "$defs"):
                for sub in value.values():
                    walk(sub)
            elif key == "items":
                assert isinstance(value, dict)
                walk(value)
            elif key == "oneOf":
                for sub in value:
                    walk(sub)

    for schema in SCHEMAS.values():
        walk(schema)


def test_one_valid_event_of_every_kind_is_stored(store):
    report = store.append([event(0, kind=kind, run=kind.replace(".", "-")) for kind in KINDS])
    assert report.stored == len(KINDS)


# --- the quick check in front of fastjsonschema: may say "not sure", never a wrong yes ----------

import decimal  # noqa: E402

import fastjsonschema  # noqa: E402
from hypothesis import given, settings, strategies as st  # noqa: E402

from store.body_check import body_ok, quick, quick_source  # noqa: E402


class _Text(str):
    pass


def _schema_accepts(kind, body) -> bool:
    try:
        validator(kind)(body)
    except fastjsonschema.JsonSchemaValueException:
        return False
    return True


def _field_names(kind):
    return sorted(SCHEMAS[kind].get("properties", {})) + ["extra"]


_values = st.recursive(
    st.none() | st.booleans() | st.integers(min_value=-3, max_value=8) | st.integers()
    | st.floats() | st.sampled_from([0.0, -0.0, -1.5, 5.0, 5.5, 6.0])
    | st.text(max_size=3) | st.sampled_from(["car", "red", "green", "activated", "human", "a" * 64, "0" * 64])
    | st.builds(_Text, st.sampled_from(["car", "red", "x"])) | st.builds(decimal.Decimal, st.integers(0, 9)),
    lambda children: st.lists(children, max_size=3) | st.lists(children, max_size=2).map(tuple)
    | st.dictionaries(st.sampled_from(["id", "from", "to", "x"]), children, max_size=3),
    max_leaves=8,
)


@st.composite
def bodies(draw):
    kind = draw(st.sampled_from(sorted(KINDS)))
    names = _field_names(kind)
    body = dict(BODIES[kind]) if draw(st.booleans()) else {}
    for name in draw(st.lists(st.sampled_from(names), max_size=4)):
        body[name] = draw(_values)
    for name in draw(st.lists(st.sampled_from(names), max_size=2)):
        body.pop(name, None)
    return kind, body


@settings(deadline=None, max_examples=1000)
@given(bodies())
def test_the_quick_check_never_accepts_what_the_schema_refuses(case):
    kind, body = case
    check = quick(kind)
    if check is not None and check(body):
        assert _schema_accepts(kind, body), (kind, body)
    assert body_ok(kind, body) == _schema_accepts(kind, body)


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_the_quick_check_says_yes_to_the_plain_valid_bodies(kind):
    """Else it would only cost time: every kind's plain body is answered without fastjsonschema
    (a run.start's map, with its patternProperties, is still left to it)."""
    check = quick(kind)
    assert check is not None and check(dict(BODIES[kind]))


@pytest.mark.parametrize("kind, body", [
    ("entity.state", {"x": 1.0, "y": 2.0, "speed_mps": -0.5}),
    ("entity.state", {"x": 1.0, "y": 2.0, "speed_mps": float("nan")}),
    ("entity.state", {"x": True, "y": 2.0, "speed_mps": 1.0}),
    ("entity.state", {"x": decimal.Decimal(1), "y": 2.0, "speed_mps": 1.0}),
    ("entity.state", {"x": 1.0, "y": 2.0}),
    ("entity.spawn", {"type": _Text("car")}),
    ("entity.spawn", {"type": "car", "automation_level": 6}),
    ("entity.spawn", {"type": "car", "automation_level": 4.0}),
    ("signal.state", {"junction": "", "colour": "red"}),
    ("vehicle.perception", {"facts": ("a",)}),
    ("vehicle.perception", {"facts": ["a", ""]}),
    ("vehicle.decision", {"goal": "g", "action": "a", "proceeds": True, "rulebook": "0" * 64 + "\n"}),
    ("vehicle.decision", {"goal": "g", "action": "a", "proceeds": True, "rulebook": "0" * 63}),
    ("vehicle.trace", {"query": "q", "answer": True, "proof": {"sentence": "s", "status": "guessed"}}),
    ("vehicle.trace", {"query": "q", "answer": (True,)}),
    ("vehicle.trace", {"query": "q", "answer": 1}),
    ("vehicle.trace", {"query": "q", "answer": False, "proof": {"sentence": "s", "status": "fact",
                                                                 "source": {"file": "f", "line": 0}}}),
    ("vehicle.trace", {"query": "q", "answer": False, "proof": {"sentence": "s", "status": "fact",
                                                                 "children": [{"sentence": "s"}]}}),
    ("collision", {"entities": []}),
])
def test_the_quick_check_leaves_the_edge_cases_to_fastjsonschema(kind, body):
    assert quick(kind)(body) is False
    assert body_ok(kind, body) == _schema_accepts(kind, body)


# --- the quick check of nested schemas: a vehicle's proof tree ($ref, oneOf), a rulebook's hash ---

_odd = _values | st.sampled_from(["proved", "failed", "builtin", "fact", "guessed", "0" * 64 + "\n", "f" * 64])


def _proofs(node_value=_odd):
    """Proof trees as a vehicle sends them, their fields now and then given an odd value, dropped or
    joined by one the schema does not name, at any depth."""
    def node(children):
        return st.fixed_dictionaries(
            {"sentence": st.sampled_from(["173 can enter the junction", ""]),
             "status": st.sampled_from(["proved", "failed", "builtin", "fact"])},
            optional={"rule": st.sampled_from([None, "HC 171"]),
                      "source": st.none() | st.fixed_dictionaries(
                          {"file": st.just("highway_code.le"), "line": st.integers(-1, 200)},
                          optional={"extra": node_value}),
                      "evidence": st.lists(node_value, max_size=2),
                      "children": st.just([]) if children is None else st.lists(children, max_size=3)})

    def twisted(tree):
        return st.one_of(st.just(tree), st.tuples(st.sampled_from(
            ["sentence", "status", "rule", "source", "evidence", "children", "line", "extra"]), node_value).map(
            lambda pair: {**tree, pair[0]: pair[1]}), st.just({k: v for k, v in tree.items() if k != "status"}))
    return st.recursive(node(None), lambda inner: node(inner).flatmap(twisted), max_leaves=12)


@settings(deadline=None, max_examples=600)
@given(st.fixed_dictionaries({"query": st.sampled_from(["173 can enter the junction", ""])},
                             optional={"answer": st.booleans() | st.lists(_odd, max_size=2) | _odd,
                                       "proof": _proofs() | _odd, "extra": _odd}))
def test_the_quick_check_of_a_proof_says_yes_only_where_the_schema_does(body):
    """vehicle.trace's proofs are checked by the generated recursive helper (its $defs' proof, the
    answer's and source's oneOf); whatever it cannot vouch for fastjsonschema decides as before."""
    accepted = _schema_accepts("vehicle.trace", body)
    if quick("vehicle.trace")(body):
        assert accepted, body
    assert body_ok("vehicle.trace", body) == accepted


@settings(deadline=None, max_examples=300)
@given(st.sampled_from(["0" * 64, "f" * 64, "F" * 64, "0" * 64 + "\n", "0" * 63, "0" * 65, "g" * 64, ""])
       | st.text(alphabet="0123456789abcdef\n", max_size=66) | _odd)
def test_the_quick_check_reads_a_pattern_as_fastjsonschema_does(rulebook):
    """fastjsonschema searches with its $ read as end of text (\\Z), so a hash followed by a newline
    is refused; the quick check must not take it either."""
    body = {"goal": "g", "action": "a", "proceeds": True, "rulebook": rulebook}
    accepted = _schema_accepts("vehicle.decision", body)
    if quick("vehicle.decision")(body):
        assert accepted, body
    assert body_ok("vehicle.decision", body) == accepted


def test_the_quick_check_takes_a_vehicles_proof_and_hash():
    """Else the generated helpers would only cost time."""
    leaf = {"children": [], "evidence": [], "rule": None, "sentence": "173 has red light", "source": None,
            "status": "fact"}
    proof = {**leaf, "children": [leaf, {**leaf, "source": {"file": "highway_code.le", "line": 93}}],
             "rule": "HC 171", "status": "failed"}
    assert quick("vehicle.trace")({"query": "173 can enter the junction", "answer": True, "proof": proof})
    assert quick("vehicle.trace")({"query": "q", "answer": ["173 must stop"]})
    assert quick("vehicle.decision")({**BODIES["vehicle.decision"], "rulebook": "0" * 64})


def test_a_proof_nested_past_the_quick_checks_recursion_is_decided_by_the_schema():
    proof: dict = {"sentence": "s", "status": "fact"}
    for _ in range(5000):
        proof = {"sentence": "s", "status": "proved", "children": [proof]}
    assert body_ok("vehicle.trace", {"query": "q", "answer": True, "proof": proof}) is False


def test_a_hostile_proof_or_hash_is_quarantined_with_fastjsonschemas_words(store):
    """The quick check only ever says yes sooner: a proof wrong three levels down, a hash with a
    newline after it, reach quarantine, raw bytes and all, with the reason the schema gives."""
    leaf = {"sentence": "173 has red light", "status": "fact"}
    bad_leaf = {**leaf, "source": {"file": "highway_code.le", "line": 0}}
    trace = event(1, kind="vehicle.trace", body={"query": "173 can enter the junction", "answer": True, "proof": {
        **leaf, "status": "proved", "children": [leaf, {**leaf, "status": "proved", "children": [bad_leaf]}]}})
    decision = event(2, kind="vehicle.decision", body={**BODIES["vehicle.decision"], "rulebook": "0" * 64 + "\n"})
    raws = [(json.dumps(ev, sort_keys=True, separators=(",", ":")).encode(), f"wire:{i}")
            for i, ev in enumerate([trace, decision])]
    report = store.append_raw(raws)
    assert report.stored == 0
    reasons = [r.reason for r in report.rejected]
    assert ("vehicle.trace body.proof.children[1].children[0].source must be valid exactly by one definition"
            in reasons[0])
    assert "vehicle.decision body.rulebook must match pattern ^[0-9a-f]{64}$" in reasons[1]
    assert [(q["raw"], q["reason"]) for q in store.quarantined()] == [(raw, reason) for (raw, _), reason in
                                                                         zip(raws, reasons)]
