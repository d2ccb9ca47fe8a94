"""Engine.ask_first and first_holding ask several sentences on one scenario; they must answer
exactly as asking `holds` and then `ask` of each in turn does (the verdict is read from them),
whatever the facts: random scenarios of the validator rulebook's own sentences, the proofs and
why-nots compared whole."""
from __future__ import annotations

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from reasoner.bundled import bundled
from reasoner.engine import Answer, get_engine
from reasoner.le.sentences import parse_fact
from reasoner.vocabulary import MITIGATELY_VIOLATES, PUNISHABLY_VIOLATES

ENTER = "enter the junction"
POOL = [
    "7 is of type car", "7 is of type ambulance", "7 is on an emergency call", "7 has red light",
    "7 has amber light", "7 has green light", "7 has a stop sign", "7 is stopped", "7 has crossed the stop line",
    "7 is in the junction", "8 is approaching 7", "7 potentially violates enter the junction",
    "7 crossed the stop line on red light", "7 is too close to the stop line to stop safely",
    "7 has stopped at the stop line", "the stop line is not clearly visible for 7",
    "7 would force 8 to change speed or course", "7 is being used for fire brigade purposes",
    "observing the red signal would be likely to hinder the use of 7 for its purpose",
]


def _rulebook():
    return get_engine().load(bundled("validators.le"), "validators.le")


def _one_by_one(rb, goals, facts) -> tuple[int, Answer]:
    engine = get_engine()
    for i, goal in enumerate(goals):
        if engine.holds(rb, goal, facts):
            answer = engine.ask(rb, goal, facts)
            if answer.holds:
                return i, answer
    return -1, engine.ask(rb, goals[0], facts)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sets(st.sampled_from(POOL)))
def test_ask_first_answers_as_each_question_in_turn(chosen: set[str]) -> None:
    rb = _rulebook()
    facts = [parse_fact(s, rb.document.templates) for s in sorted(chosen)]
    assert all(facts)
    goals = (PUNISHABLY_VIOLATES.atom(7, ENTER), MITIGATELY_VIOLATES.atom(7, ENTER))
    index, answer = get_engine().ask_first(rb, goals, facts)
    want_index, want = _one_by_one(rb, goals, facts)
    assert index == want_index
    assert (answer.proofs, answer.why_not) == (want.proofs, want.why_not)
    plain = next((i for i, g in enumerate(goals) if get_engine().holds(rb, g, facts)), -1)
    assert get_engine().first_holding(rb, goals, facts) == plain


def test_each_verdict_is_reached() -> None:
    """The scenarios above reach all three answers (else the comparison proves little)."""
    rb = _rulebook()
    goals = (PUNISHABLY_VIOLATES.atom(7, ENTER), MITIGATELY_VIOLATES.atom(7, ENTER))
    red_runner = ["7 is of type car", "7 has red light", "7 potentially violates enter the junction",
                  "7 crossed the stop line on red light"]
    on_call = ["7 is of type ambulance", "7 is on an emergency call", "7 has red light",
               "7 potentially violates enter the junction", "7 crossed the stop line on red light",
               "observing the red signal would be likely to hinder the use of 7 for its purpose"]
    found = {get_engine().ask_first(rb, goals, [parse_fact(s, rb.document.templates) for s in facts])[0]
             for facts in (red_runner, on_call, [])}
    assert found == {0, 1, -1}


LIABILITY_POOL = [
    "7 is driving itself", "7 punishably violates enter the junction", "alice is the driver of 7",
    "bob is the user-in-charge of 7", "a transition demand for 7 has expired unanswered",
    "bob has taken control of 7", "acme is the authorised self-driving entity for 7",
    "fleetco is the no-user-in-charge operator of 7", "7 is travelling autonomously",
]


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.sets(st.sampled_from(LIABILITY_POOL)))
def test_answers_all_answers_as_each_question_alone(chosen: set[str]) -> None:
    """The liability stage's four questions, asked together, as `answers` gives each."""
    from reasoner.le.terms import Cond, Var
    from reasoner.vocabulary import (FACES_REGULATORY_SANCTIONS, GETS_LICENCE_POINTS, IS_LIABLE,
                                     IS_OFFERED_A_FIXED_PENALTY)
    engine = get_engine()
    rb = engine.load(bundled("liability.le"), "liability.le")
    facts = [parse_fact(s, rb.document.templates) for s in sorted(chosen)]
    questions = [([Cond(atom=s.atom(Var("party"), ENTER, 7))], explain) for s, explain in
                 ((IS_LIABLE, True), (GETS_LICENCE_POINTS, False), (FACES_REGULATORY_SANCTIONS, False),
                  (IS_OFFERED_A_FIXED_PENALTY, False), (IS_LIABLE, False))]
    together = engine.answers_all(rb, questions, facts)
    for (body, explain), got in zip(questions, together):
        alone = engine.answers(rb, body, facts, explain=explain, texts=False)
        assert (got.bindings, got.proofs, got.why_not) == (alone.bindings, alone.proofs, alone.why_not)


def test_the_liability_scenarios_name_parties() -> None:
    """The pool above reaches answers (else comparing empty lists proves little)."""
    from reasoner.le.terms import Cond, Var
    from reasoner.vocabulary import IS_LIABLE
    engine = get_engine()
    rb = engine.load(bundled("liability.le"), "liability.le")
    facts = [parse_fact(s, rb.document.templates) for s in
             ("7 punishably violates enter the junction", "alice is the driver of 7")]
    [liable] = engine.answers_all(rb, [([Cond(atom=IS_LIABLE.atom(Var("party"), ENTER, 7))], True)], facts)
    assert liable.bindings and liable.proofs
