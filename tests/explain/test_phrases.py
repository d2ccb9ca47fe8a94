"""What might have been is the rulebook's sentence put in the past perfect by grammar: the verb is
read off the template, so a foreign producer's core-vocabulary sentences and a made-up rulebook's
sentences read without a table entry; the tables keep only what a template lacks."""
import pytest

from explain import phrases as ph
from reasoner import vocabulary as vocab
from reasoner.le.render import sentence_text
from reasoner.le.templates import parse_template
from reasoner.le.terms import Atom
from reasoner.wording import shape


class Rulebook:
    """A made-up rulebook's templates, as the renderer reads them (document.template_for)."""

    def __init__(self, *templates: str) -> None:
        self.templates = [parse_template(t) for t in templates]

    def template_for(self, functor, arity):
        return next((t for t in self.templates if t.functor == functor and t.arity == arity), None)


def said(template: str, *args) -> tuple[list, str]:
    """A sentence as the engine hands it over: its data, and its text rendered with its template."""
    atom = Atom(parse_template(template).functor, args)
    return [atom.functor, *args], sentence_text(atom, Rulebook(template))


def core(sentence: vocab.Sentence, *args) -> tuple[list, str]:
    """A core-vocabulary sentence as a foreign producer writes it."""
    return [sentence.functor, *sentence.atom(*args).args], sentence.text(*args)


@pytest.mark.parametrize("sentence, args, held, not_held", [
    (vocab.IS_STOPPED, (173,), "173 been stopped", "173 not been stopped"),
    (vocab.HAS_CROSSED_THE_STOP_LINE, (173,), "173 crossed the stop line", "173 not crossed the stop line"),
    (vocab.IS_ON_AN_EMERGENCY_CALL, (253,), "253 been on an emergency call", "253 not been on an emergency call"),
    (vocab.IS_IN_THE_JUNCTION, (173,), "173 been in the junction", "173 not been in the junction"),
    (vocab.IS_APPROACHING, (9, 173), "9 been approaching 173", "9 not been approaching 173"),
    (vocab.IS_DRIVING_ITSELF, (41,), "41 been driving itself", "41 not been driving itself"),
    (vocab.HAS_SIGN, (8, "give_way"), "8 had a give way sign", "8 had no give way sign"),
    (vocab.HAS_STOPPED_AT_THE_STOP_LINE, (8,), "8 stopped at the stop line", "8 not stopped at the stop line"),
    (vocab.IS_TOO_CLOSE_TO_STOP, (5,), "5 been too close to the stop line to stop safely",
     "5 not been too close to the stop line to stop safely"),
    (vocab.IS_ON_THE_MAIN_ROAD, (11,), "11 been on the main road", "11 not been on the main road"),
    (vocab.HAS_A_LIGHT_PERCEPTION_FAULT, (41,), "41 had a perception fault about the light",
     "41 had no perception fault about the light"),
])
def test_core_sentences_read_by_grammar_alone(sentence, args, held, not_held):
    assert sentence.functor not in ph._PROSE
    data, text = core(sentence, *args)
    assert ph.had(data, text) == held
    assert ph.had(data, text, holds=False) == not_held


@pytest.mark.parametrize("sentence, args, held, not_held", [
    (vocab.HAS_LIGHT, (173, "amber"), "173 had an amber light", "173 had no amber light"),
    (vocab.IS_OF_TYPE, (173, "fire_engine"), "173 been a fire engine", "173 not been a fire engine"),
    (vocab.HAS_SPEED_OF, (28, 30), "28 been doing 30 mph", "28 not been doing 30 mph"),
    (vocab.SPEED_LIMIT_IS, (38,), "the speed limit been 38 mph", "the speed limit not been 38 mph"),
])
def test_core_sentences_that_need_an_article_or_a_unit(sentence, args, held, not_held):
    data, text = core(sentence, *args)
    assert ph.had(data, text) == held
    assert ph.had(data, text, holds=False) == not_held


def test_what_the_grammar_makes_of_those_without_their_entry():
    """Each PROSE entry is there because the rulebook's own template reads worse, or cannot be put
    after "had" at all (a verb already in the past: "crossed the stop line on")."""
    for sentence, prose in ph.PROSE.items():
        args = [("x" if s.type != "number" else 30) for s in sentence.parsed.slots]
        own = ph.perfect(shape(sentence.template), [str(a) for a in args])
        mine = ph.perfect(shape(prose), [str(a) for a in args])
        assert mine is not None and own != mine
    data, text = core(vocab.HAS_LIGHT, 173, "red")
    assert ph.perfect(ph.layout(data, text), ["173", "red"]) == "173 had red light"
    assert ph.perfect(ph.layout(data, text), ["173", "red"], holds=False) == "173 not had red light"


def test_every_table_is_keyed_by_the_vocabulary_and_prose_keeps_the_slots():
    for table in (ph.PROSE, ph.INSTEAD, ph.MANNER, ph.MANNER_NOT):
        assert set(table) <= set(vocab.SENTENCES)
    for sentence, prose in ph.PROSE.items():
        assert parse_template(prose).slots == sentence.parsed.slots


@pytest.mark.parametrize("template, args, held, not_held", [
    ("*a train* is waiting at *a platform*", ("t1", "platform_4"), "t1 been waiting at platform 4",
     "t1 not been waiting at platform 4"),
    ("*a tram* has overtaken *a cyclist*", (7, 9), "7 overtaken 9", "7 not overtaken 9"),
    ("*a vessel* has a *a flag* flag", ("v2", "orange"), "v2 had an orange flag", "v2 had no orange flag"),
    ("*a drone* would enter *a zone*", ("d1", "z3"), "d1 entered z3", "d1 not entered z3"),
    ("*a driver* would give way to *a road user*", (3, 4), "3 given way to 4", "3 not given way to 4"),
    ("*a driver* would have slowed down", (3,), "3 slowed down", "3 not slowed down"),
    ("there are *a number* pedestrians on *a crossing*", (3, "c1"), "there been 3 pedestrians on c1",
     "there not been 3 pedestrians on c1"),
    ("there is a cyclist in *a lane*", ("l2",), "there been a cyclist in l2", "there been no cyclist in l2"),
    ("the visibility is *a distance* metres", (50,), "the visibility been 50 metres",
     "the visibility not been 50 metres"),
    ("*a vehicle* is not indicating", (6,), "6 not been indicating", "6 been indicating"),
    # the template, not the value, decides: "painted" fills a slot, so "has" is possession
    ("*a vehicle* has *a finish* bodywork", (6, "painted"), "6 had painted bodywork", "6 not had painted bodywork"),
    ("*a crew* has need of *a tool*", ("c1", "a_jack"), "c1 had need of a jack", "c1 not had need of a jack"),
    # a value that is also a word of the template
    ("*a vehicle* is stopped", ("is",), "is been stopped", "is not been stopped"),
])
def test_a_made_up_rulebook_needs_no_table(template, args, held, not_held):
    data, text = said(template, *args)
    assert ph.had(data, text) == held
    assert ph.had(data, text, holds=False) == not_held


@pytest.mark.parametrize("template, args", [
    ("*a vehicle* potentially violates *an action*", (173, "enter the junction")),
    ("*a vehicle* must not *an action*", (173, "enter the junction")),
    ("a transition demand for *a vehicle* has expired unanswered", (41,)),
    ("*a vehicle* enters *a junction*", (5, "j1")),
])
def test_a_sentence_the_grammar_cannot_place_keeps_the_rules_words(template, args):
    data, text = said(template, *args)
    assert ph.had(data, text) == f"it been recorded that {text}"
    assert ph.had(data, text, holds=False) == f"it not been recorded that {text}"


def test_the_layout_is_read_off_the_text_with_the_functor():
    assert ph.layout(*said("*a road user* is approaching *a vehicle*", 9, 173)) == [0, "is", "approaching", 1]
    assert ph.layout(*said("the speed limit is *a number*", 30)) == ["the", "speed", "limit", "is", 0]
    assert ph.layout(["is_stopped", 173], "173 was stopped") is None        # not this template's text
    assert ph.layout(["$not", []], "it is not the case that") is None
    assert list(ph.layouts(["is_stopped", "is"], "is is stopped")) == [["is", 0, "stopped"], [0, "is", "stopped"]]


def test_a_replacement_says_what_it_replaced():
    old, new = core(vocab.IS_OF_TYPE, 173, "car"), core(vocab.IS_OF_TYPE, 173, "ambulance")
    assert ph.change_clause("replace", old[0], old[1], new[0], new[1]) == "had 173 been an ambulance instead of a car"
    old, new = core(vocab.HAS_LIGHT, 173, "red"), core(vocab.HAS_LIGHT, 173, "green")
    assert ph.change_clause("replace", old[0], old[1], new[0], new[1]) == "had 173 had a green light instead of red"
    old, new = said("*a train* is waiting at *a platform*", "t1", 4), said("*a train* is waiting at *a platform*", "t1", 5)
    assert ph.change_clause("replace", old[0], old[1], new[0], new[1]) == "had t1 been waiting at 5 instead of 4"
