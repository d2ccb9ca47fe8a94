"""Counterfactuals: the smallest changes to recorded facts that flip an answer, each classified as
the vehicle's own conduct (controlled) or a circumstance; and why-not questions read with the
rulebook's templates."""
import pytest

from reasoner.bundled import bundled
from reasoner.counterfactuals import QuestionUnreadable, apply, search, why_not
from reasoner.engine import get_engine
from reasoner.le.sentences import parse_fact
from reasoner.le.terms import Atom

ENTER = "enter the junction"
COLOURS = {"colour": ["red", "amber", "green"]}


@pytest.fixture(scope="module")
def books():
    e = get_engine()
    return e, e.load(bundled("validators.le"), "validators.le"), e.load(bundled("monitors.le"), "monitors.le")


def facts(rb, *sentences):
    return [a for s in sentences if (a := parse_fact(s, rb.document.templates)) is not None]


def found(cfs, rb):
    """Each counterfactual as a set of (kind, fact, new) in words, with its classification."""
    return {frozenset((c.kind, rb.render(c.fact), rb.render(c.new) if c.new else None) for c in cf.changes): cf.kind
            for cf in cfs}


def lawful(books, v, *sentences, action=ENTER, **kw):
    e, val, _ = books
    pv = Atom("potentially_violates", (v, action))
    return found(search(e, val, facts(val, *sentences) + [pv], Atom("can", (v, action)), True, v, fixed=[pv],
                        values=COLOURS, **kw), val)


def test_car_173_is_lawful_only_by_circumstance(books):
    got = lawful(books, 173, "173 is of type car", "173 has red light")
    green = frozenset({("replace", "173 has red light", "173 has green light")})
    # TSRGD para 5(6): the exemption follows the purpose (an emergency call), not the vehicle's type
    on_call = frozenset({("add", "173 is on an emergency call", None)})
    assert got[green] == "circumstance" and got[on_call] == "circumstance"
    assert not any(("replace", "173 is of type car", "173 is of type ambulance") in cf for cf in got)
    # being stopped does not make entering lawful: it is no answer to this question
    assert not any(("add", "173 is stopped", None) in cf for cf in got)
    # minimal: no answer contains another
    assert all(not (a < b) for a in got for b in got)
    # "no red light" is said as the concrete "green instead of red"
    assert frozenset({("remove", "173 has red light", None)}) not in got
    assert not any(k == "controlled" for k in got.values())


def test_car_173_could_have_avoided_the_potential_violation_by_not_crossing_on_red(books):
    """The act is proceeding beyond the stop line on red (TSRGD para 5(3)): not crossing the line
    (or crossing it on green) is the vehicle's own way out; being stopped after crossing is not."""
    e, _, mon = books
    pv = Atom("potentially_violates", (173, ENTER))
    got = found(search(e, mon, facts(mon, "173 has red light", "173 has crossed the stop line"), pv, False, 173,
                       values=COLOURS), mon)
    assert got[frozenset({("remove", "173 has crossed the stop line", None)})] == "controlled"
    assert not any(("add", "173 is stopped", None) in cf for cf in got)
    got = found(search(e, mon, facts(mon, "173 has red light", "173 crossed the stop line on red light"), pv, False,
                       173, values=COLOURS), mon)
    assert got[frozenset({("replace", "173 crossed the stop line on red light",
                                      "173 crossed the stop line on green light")})] == "controlled"


def test_ambulance_forcing_a_pedestrian_could_have_not_forced_them(books):
    got = lawful(books, 255, "255 is of type ambulance", "255 has red light", "255 is on an emergency call",
                 "p1 is of type pedestrian", "255 would force p1 to change speed or course")
    assert got[frozenset({("remove", "255 would force p1 to change speed or course", None)})] == "controlled"
    # the pedestrian being someone else would not do: forcing any road user to brake is barred too
    assert frozenset({("replace", "p1 is of type pedestrian", "p1 is of type car")}) not in got


def test_amber_car_had_it_crossed_the_line(books):
    """HC 175: the amber appearing after the vehicle crossed the line (it crossed on green), or its
    being too close to stop safely, are its own ways out; being over the line now is not."""
    got = lawful(books, 5, "5 is of type car", "5 has amber light")
    assert got[frozenset({("add", "5 crossed the stop line on green light", None)})] == "controlled"
    assert got[frozenset({("add", "5 is too close to the stop line to stop safely", None)})] == "controlled"
    assert frozenset({("add", "5 has crossed the stop line", None)}) not in got


def test_speeding_is_lawful_only_on_an_emergency_call_but_avoidable(books):
    e, val, mon = books
    # RTRA 1984 s.87: the limit does not apply to a vehicle on an emergency call (a circumstance)
    assert lawful(books, 28, "28 is of type car", "28 has speed of 38", "the speed limit is 30",
                  action="exceed the speed limit") == {frozenset({("add", "28 is on an emergency call", None)}):
                                                       "circumstance"}
    pv = Atom("potentially_violates", (28, "exceed the speed limit"))
    got = found(search(e, mon, facts(mon, "28 has speed of 38", "the speed limit is 30"), pv, False, 28), mon)
    assert got[frozenset({("replace", "28 has speed of 38", "28 has speed of 30")})] == "controlled"
    assert got[frozenset({("replace", "the speed limit is 30", "the speed limit is 38")})] == "circumstance"


def test_mitigated_ambulance_made_punishable_in_one_change(books):
    e, val, _ = books
    pv = Atom("potentially_violates", (253, ENTER))
    base = facts(val, "253 is of type ambulance", "253 has red light", "253 is on an emergency call") + [pv]
    cfs = search(e, val, base, Atom("can", (253, ENTER)), False, 253, fixed=[pv], max_size=1,
                 exclude={"type": {"pedestrian"}})
    got = found(cfs, val)
    assert got[frozenset({("remove", "253 is on an emergency call", None)})] == "circumstance"
    assert not any(("replace", "253 is of type ambulance", "253 is of type pedestrian") in k for k in got)
    for cf in cfs:      # every answer really flips the question
        assert not e.holds(val, Atom("can", (253, ENTER)), apply(base, cf.changes))


def test_no_search_when_the_answer_is_already_wanted(books):
    e, val, _ = books
    assert search(e, val, facts(val, "1 is of type car", "1 has green light"), Atom("can", (1, ENTER)), True, 1) == []


def test_why_not_reads_the_sentence_with_the_templates(books):
    e, val, _ = books
    scenario = facts(val, "173 is of type car", "173 has red light")
    got = why_not(e, val, "173 can enter the junction", scenario)
    assert got["holds"] is False and got["trees"][0]["status"] == "failed"
    assert why_not(e, val, "173 must not enter the junction.", scenario)["holds"] is True
    with pytest.raises(QuestionUnreadable):
        why_not(e, val, "173 :- halt", scenario)
