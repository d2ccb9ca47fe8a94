"""The monitor rulebook asked once per shape of observation (reasoner/shapes.py): the same actions
as asking about the vehicle's own sentences, each skeleton of a sentence parsed once whichever
numbers it holds, and a vehicle whose id is also a number of its sentences judged on its own
numbers."""

import pytest
from hypothesis import given, settings, strategies as st

from reasoner.bundled import bundled
from reasoner.engine import get_engine
from reasoner.episodes import Rederiver
from reasoner.facts import FactReader
from reasoner.le.render import arg_text
from reasoner.le.sentences import constant, parse_fact
from reasoner.le.terms import Cond, Var
from reasoner.vocabulary import POTENTIALLY_VIOLATES


@pytest.fixture(scope="module")
def monitors():
    engine = get_engine()
    return engine, engine.load(bundled("monitors.le"), "monitors.le")


def own_answer(engine, rb, vehicle, facts):
    """What the rulebook says of the vehicle's own sentences, each parsed as it is and asked
    directly (no shapes, no skeletons)."""
    atoms = [a for a in (parse_fact(s, rb.document.templates) for s in facts) if a is not None]
    me = constant(vehicle.split(" "))
    question = [Cond(atom=POTENTIALLY_VIOLATES.atom(Var("vehicle"), Var("action")))]
    return frozenset(arg_text(b[0][2]) for b in engine.answers(rb, question, atoms).bindings if b[0][1] == me)


RED_RUN = ["{v} is of type car", "{v} has red light", "{v} has crossed the stop line", "{v} has speed of 34",
           "the speed limit is 30"]
STOPPED = ["{v} is of type car", "{v} has red light", "{v} is stopped", "{v} has speed of 0", "the speed limit is 30"]
GIVE_WAY = ["{v} is of type car", "{v} has a give way sign", "{v} is in the junction", "12 is approaching {v}",
            "12 is on the main road", "{v} has speed of 9", "the speed limit is 30"]


@pytest.mark.parametrize("template", [RED_RUN, STOPPED, GIVE_WAY])
@pytest.mark.parametrize("vehicle", ["173", "p7", "AB12 CDE", "12", "30", "34"])
def test_a_shape_answers_as_the_vehicles_own_sentences_do(monitors, template, vehicle):
    engine, rb = monitors
    facts = [s.format(v=vehicle) for s in template]
    assert Rederiver(engine, rb, FactReader()).actions(vehicle, facts) == own_answer(engine, rb, vehicle, facts)


def test_a_vehicle_whose_id_is_its_speed_or_the_limit_is_judged_on_its_speed(monitors):
    # HC 124 / RTRA 1984 s.89: over the limit is an offence, at or under it is not. The ids here are
    # also speeds and limits; one answer shared between "25 at 25 mph" and "35 at 35 mph" under a
    # 30 mph limit (both once blanked alike) would clear one of them or accuse the other.
    engine, rb = monitors
    rederiver = Rederiver(engine, rb, FactReader())
    cases = {("35", 35, 40): False, ("30", 31, 30): True, ("25", 25, 30): False, ("35", 35, 30): True,
             ("30", 30, 30): False}
    for (vehicle, speed, limit), over in cases.items():
        facts = [f"{vehicle} is of type car", f"{vehicle} has speed of {speed}", f"the speed limit is {limit}"]
        found = rederiver.actions(vehicle, facts)
        assert ("exceed the speed limit" in found) is over, (vehicle, speed, limit, found)
        assert found == own_answer(engine, rb, vehicle, facts)


def test_the_sentences_of_one_shape_are_parsed_and_asked_once_for_every_vehicle(monitors, monkeypatch):
    engine, rb = monitors
    import reasoner.facts as facts_module
    parsed = []
    monkeypatch.setattr(facts_module, "parse_fact", lambda s, t: parsed.append(s) or parse_fact(s, t))
    rederiver = Rederiver(engine, rb, FactReader())
    found = {v: rederiver.actions(v, [s.format(v=v) for s in RED_RUN]) for v in ("173", "174", "175")}
    assert set(found.values()) == {frozenset({"enter the junction", "exceed the speed limit"})}
    assert rederiver.asked == 1 and len(parsed) == len(RED_RUN)


def test_other_road_users_are_renamed_too(monitors):
    engine, rb = monitors
    rederiver = Rederiver(engine, rb, FactReader())
    for vehicle, other in (("173", "12"), ("174", "13"), ("175", "p9")):
        facts = [s.format(v=vehicle).replace("12 ", f"{other} ") for s in GIVE_WAY]
        assert rederiver.actions(vehicle, facts) == own_answer(engine, rb, vehicle, facts)
    assert rederiver.asked == 1


@settings(max_examples=60, deadline=None)
@given(st.lists(st.one_of(st.integers(0, 10**17), st.sampled_from(["007", "-4", "2.5", "p7", "AB12 CDE", "0"])),
                min_size=2, max_size=2),
       st.sampled_from(["{a} is approaching {b}", "{a} has speed of {b}", "the speed limit is {a}",
                        "{a} is of type car", "{a} crossed the stop line on {b} light", "{a} has {b} light"]))
def test_a_skeleton_parses_as_the_sentence_does(monitors, values, pattern):
    _, rb = monitors
    sentence = pattern.format(a=values[0], b=values[1])
    assert FactReader().atom(rb, sentence) == parse_fact(sentence, rb.document.templates)


NUMBERED = """the templates are:
*a vehicle* is used for a purpose of section 87.
*a vehicle* is used for a purpose of section *a number*.
*a vehicle* is in lane 2.
*a vehicle* has speed of *a speed*.
*a vehicle* is checked.

the knowledge base numbered includes:
a vehicle is checked if the vehicle is in lane 2.
"""


@pytest.fixture(scope="module")
def numbered():
    return get_engine().load(NUMBERED, "numbered.le")


@settings(max_examples=80, deadline=None)
@given(st.lists(st.one_of(st.integers(0, 10**17), st.sampled_from(["87", "2", "02", "087", "5", "0"])),
                min_size=2, max_size=2),
       st.sampled_from(["{a} is used for a purpose of section {b}", "{a} is in lane {b}", "{a} has speed of {b}",
                        "{a} is used for a purpose of section 87", "{a} is in lane 2"]))
def test_a_skeleton_keeps_the_templates_own_numbers(numbered, values, pattern):
    # "section 87" and "lane 2" are a template's own words: 87 and 2 there are no arguments,
    # and the sentence's other numbers still are (the skeleton parses as the sentence does)
    sentence = pattern.format(a=values[0], b=values[1])
    assert FactReader().atom(numbered, sentence) == parse_fact(sentence, numbered.document.templates)


def test_a_rulebook_with_number_words_still_parses_each_skeleton_once(numbered, monkeypatch):
    import reasoner.facts as facts_module
    parsed = []
    monkeypatch.setattr(facts_module, "parse_fact", lambda s, t: parsed.append(s) or parse_fact(s, t))
    reader = FactReader()
    atoms = [reader.atom(numbered, f"{v} has speed of {v + 3}") for v in (173, 174, 175)]
    assert [a.args for a in atoms] == [(173, 176), (174, 177), (175, 178)]
    assert reader.atom(numbered, "173 is used for a purpose of section 87").functor != \
        reader.atom(numbered, "173 is used for a purpose of section 88").functor
    assert len(parsed) == 3
