"""The monitor rulebook asked once per shape of observation: the same actions as asking about the
vehicle's own sentences, and each sentence of a shape parsed once whichever vehicle it was about."""

import pytest

from reasoner.bundled import bundled
from reasoner.engine import get_engine
from reasoner.episodes import Rederiver
from reasoner.facts import FactReader


@pytest.fixture(scope="module")
def monitors():
    engine = get_engine()
    return engine, engine.load(bundled("monitors.le"), "monitors.le")


def own_answer(engine, rb, vehicle, facts):
    """What the rulebook says of the vehicle's own sentences, asked directly (no shapes)."""
    return Rederiver(engine, rb, FactReader())._ask(vehicle, facts)


RED_RUN = ["{v} is of type car", "{v} has red light", "{v} has crossed the stop line", "{v} has speed of 34",
           "the speed limit is 30"]
STOPPED = ["{v} is of type car", "{v} has red light", "{v} is stopped", "{v} has speed of 0", "the speed limit is 30"]
GIVE_WAY = ["{v} is of type car", "{v} has a give way sign", "{v} is in the junction", "12 is approaching {v}",
            "12 is on the main road", "{v} has speed of 9", "the speed limit is 30"]


@pytest.mark.parametrize("template", [RED_RUN, STOPPED, GIVE_WAY])
@pytest.mark.parametrize("vehicle", ["173", "p7", "AB12 CDE"])
def test_a_shape_answers_as_the_vehicles_own_sentences_do(monitors, template, vehicle):
    engine, rb = monitors
    facts = [s.format(v=vehicle) for s in template]
    assert Rederiver(engine, rb, FactReader()).actions(vehicle, facts) == own_answer(engine, rb, vehicle, facts)


def test_the_sentences_of_one_shape_are_parsed_once_for_every_vehicle(monitors):
    engine, rb = monitors
    reader = FactReader()
    rederiver = Rederiver(engine, rb, reader)
    found = {v: rederiver.actions(v, [s.format(v=v) for s in RED_RUN]) for v in ("173", "174", "175")}
    assert set(found.values()) == {frozenset({"enter the junction", "exceed the speed limit"})}
    assert rederiver.asked == 1 and len(reader._cache) == len(RED_RUN)


def test_a_vehicle_whose_sentences_hold_the_stand_in_word_is_asked_about_as_itself(monitors):
    engine, rb = monitors
    facts = [s.format(v="173") for s in RED_RUN] + ["990000000001 is approaching 173"]
    assert Rederiver(engine, rb, FactReader()).actions("173", facts) == own_answer(engine, rb, "173", facts)
