"""Engine.holds_each asks many sentences, each on its own scenario, in one Prolog call (a
regression's thousands of decision shapes); it must answer each exactly as `holds` does, and a
question that raises must give the very QuestionError `holds` raises for it, the others answered
all the same; KeptForms raises it where the question is asked, as asking one by one did."""
from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from reasoner.bundled import bundled
from reasoner.engine import QuestionError, get_engine
from reasoner.le.sentences import parse_fact
from reasoner.le.terms import Atom, Var
from reasoner.regress.decisions import GOALLESS, KeptForms
from reasoner.vocabulary import MITIGATELY_VIOLATES, PUNISHABLY_VIOLATES

ENTER = "enter the junction"
POOL = [
    "7 is of type car", "7 is of type ambulance", "7 is on an emergency call", "7 has red light",
    "7 has amber light", "7 has green light", "7 is stopped", "7 has crossed the stop line",
    "7 is in the junction", "8 is approaching 7", "7 potentially violates enter the junction",
    "7 crossed the stop line on red light", "7 is too close to the stop line to stop safely",
    "7 would force 8 to change speed or course", "7 is being used for fire brigade purposes",
]

RUNAWAY = """the templates are:
*a x* is red.
*a number* is big.
*a number* squared *a count* times is *a result*.
*a x* is near *a y*.
the knowledge base k includes:
a x is red if the x is red.
a number N is big if
    a number M = N + 1
    and M is big.
a number squared a count times is a result
    if the count = 0
    and the result = the number.
a number squared a count times is a result
    if the count > 0
    and a next = the number * the number
    and a fewer = the count - 1
    and the next squared the fewer times is the result.
a x is near a y if the y is near the x.
"""
RUNAWAY_ATOMS = [Atom("is_red", ("a",)), Atom("is_big", (3,)), Atom("squared_times_is", (2, 40, 5)),
                 Atom("squared_times_is", (2, 3, 256)), Atom("is_near", ("a", "b")), Atom("is_near", ("b", "a")),
                 Atom("is_near", (Var("x"), "c")), Atom("squared_times_is", (2, 3, 255))]


def _one_by_one(rb, atoms, question) -> bool | str:
    """What `holds` answers for a question (its places among the atoms), or the error's text."""
    try:
        return get_engine().holds(rb, atoms[question[0]], [atoms[i] for i in question[1:]])
    except QuestionError as exc:
        return f"error: {exc}"


def _each(rb, atoms, questions) -> list[bool | str]:
    return [a if type(a) is bool else f"error: {a}" for a in get_engine().holds_each(rb, atoms, questions)]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.lists(st.integers(0, len(POOL) + 1), min_size=1, max_size=8), min_size=1, max_size=12))
def test_holds_each_answers_as_holds_does(questions: list[list[int]]) -> None:
    rb = get_engine().load(bundled("validators.le"), "validators.le")
    atoms = [PUNISHABLY_VIOLATES.atom(7, ENTER), MITIGATELY_VIOLATES.atom(7, ENTER),
             *(parse_fact(s, rb.document.templates) for s in POOL)]
    assert _each(rb, atoms, questions) == [_one_by_one(rb, atoms, q) for q in questions]


def test_the_validator_answers_both_ways() -> None:
    """The sentences above reach both answers (else the comparison proves little)."""
    rb = get_engine().load(bundled("validators.le"), "validators.le")
    atoms = [PUNISHABLY_VIOLATES.atom(7, ENTER), *(parse_fact(s, rb.document.templates) for s in POOL)]
    red = [POOL.index(s) + 1 for s in ("7 is of type car", "7 has red light",
                                       "7 potentially violates enter the junction", "7 crossed the stop line on red light")]
    assert get_engine().holds_each(rb, atoms, [[0, *red], [0]]) == [True, False]


def test_a_question_that_raises_gives_the_error_holds_raises_and_the_others_are_answered() -> None:
    rb = get_engine().load(RUNAWAY, "runaway.le")
    questions = [[0], [3], [1, 4], [2], [4, 5], [7], [6, 6], [5, 6], [5, 4]]
    got = _each(rb, RUNAWAY_ATOMS, questions)
    assert got == [_one_by_one(rb, RUNAWAY_ATOMS, q) for q in questions]
    assert [type(a) for a in got] == [str, bool, str, str, bool, bool, bool, str, bool]
    assert "inference limit" in got[0] and "4096 bits" in got[3]
    assert got[1] is True and got[4] is True and got[5] is False and got[8] is True


def test_kept_forms_raise_a_shapes_error_where_it_is_asked() -> None:
    """Asked all at once, a shape's error waits for `permitted` to ask that shape: a regression
    stops where asking one by one stopped, with the same error."""
    rb = get_engine().load(RUNAWAY, "runaway.le")
    forms = {"v:1": (("is_near", ("a", "b")), ("is_near", ("b", "a"))), "v:2": (("is_red", ("a",)),),
             "v:3": (("squared_times_is", (2, 3, 256)),), "v:4": GOALLESS}
    kept = KeptForms.read(KeptForms.data(forms))
    places = [kept.form_of(ident) for ident in forms]
    kept.ask_all(get_engine(), rb, places)
    assert kept.permitted(get_engine(), rb, places[0]) is True
    with pytest.raises(QuestionError, match="inference limit"):
        kept.permitted(get_engine(), rb, places[1])
    assert kept.permitted(get_engine(), rb, places[2]) is True
    assert kept.permitted(get_engine(), rb, places[3]) is None
