"""The vocabulary the code relies on is the bundled rulebooks' own: every sentence named in
reasoner/vocabulary.py is declared, with that very template, by the rulebook it cites (so renaming a
template in LE fails here, not in a verdict), the stages' questions are concluded by a rule there,
the English the code writes reads back to the term it asks with, and DESIGN's core vocabulary is
read by the rulebooks of both stages that read a vehicle's scenario."""
import pytest

from reasoner import vocabulary as vocab
from reasoner.bundled import CURRENT_SET, RULES_DIR, bundled
from reasoner.engine import get_engine
from reasoner.le.sentences import parse_fact
from reasoner.stages import defines

SAMPLE = {"vehicle": 173, "road_user": 253, "action": "enter the junction", "colour": "red",
          "sign": "stop", "type": "ambulance", "number": 30, "amount": 100, "offence": "red_light_offence",
          "law": "rta_1988", "party": "driver", "person": "driver", "entity": "asde"}


def rulebook(name):
    return get_engine().load(bundled(name), name)


def sample(sentence):
    return tuple(SAMPLE[slot.type] for slot in sentence.parsed.slots)


@pytest.mark.parametrize("sentence", vocab.SENTENCES, ids=lambda s: s.functor)
def test_the_rulebook_it_cites_declares_its_template(sentence):
    assert sentence.rulebook in {p.name for p in RULES_DIR.glob("*.le")}
    declared = rulebook(sentence.rulebook).document.template_for(sentence.functor, sentence.arity)
    assert declared is not None, f"{sentence.rulebook} has no template {sentence.template!r}"
    assert declared.parts == sentence.parsed.parts and not declared.builtin


@pytest.mark.parametrize("sentence", vocab.SENTENCES, ids=lambda s: s.functor)
def test_what_the_code_writes_reads_back_as_what_it_asks(sentence):
    args = sample(sentence)
    rb = rulebook(sentence.rulebook)
    assert parse_fact(sentence.text(*args), rb.document.templates) == sentence.atom(*args)


@pytest.mark.parametrize("stage", sorted(vocab.STAGES))
def test_each_stage_question_is_concluded_by_a_current_rulebook(stage):
    sentence = vocab.STAGES[stage]
    assert sentence.rulebook in CURRENT_SET
    assert defines(rulebook(sentence.rulebook), sentence.functor)


@pytest.mark.parametrize("reader", ["highway_code.le", "monitors.le", "validators.le", "penalties.le"])
@pytest.mark.parametrize("sentence", (*vocab.CORE, vocab.CROSSED_THE_STOP_LINE_ON), ids=lambda s: s.functor)
def test_the_core_vocabulary_is_read_by_the_scenario_stages(sentence, reader):
    """DESIGN: a producer that knows only the core vocabulary gets a correct verdict, and every
    stage gives each core sentence its meaning: the monitor stage (monitors.le), the vehicle
    stage (highway_code.le), the validator stage (validators.le) and the penalties stage, which
    reads the Validator Scenario (penalties.le), read all of it, and the light a vehicle crossed
    its stop line on beside it."""
    args = sample(sentence)
    text = sentence.text(*args) + "."
    assert parse_fact(text, rulebook(reader).document.templates) == sentence.atom(*args)


def test_the_core_vocabulary_is_designs_table():
    assert [s.pattern for s in vocab.CORE] == [
        "{} is of type {}", "{} is on an emergency call", "{} has {} light", "{} has a {} sign",
        "{} is stopped", "{} has crossed the stop line", "{} is in the junction", "{} is approaching {}",
        "{} has speed of {}", "the speed limit is {}", "{} is driving itself"]


def test_a_sentence_is_built_with_one_argument_per_slot():
    assert vocab.HAS_LIGHT.text("173", "red") == "173 has red light"
    assert vocab.IS_LIABLE.atom("driver", "enter the junction", "173").functor == "is_liable_for_the_violation_of_by"
    with pytest.raises(TypeError):
        vocab.HAS_LIGHT.atom("173")
    with pytest.raises(TypeError):
        vocab.IS_STOPPED.text("173", "now")
