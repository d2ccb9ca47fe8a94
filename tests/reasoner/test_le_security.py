"""Facts, scenarios, questions and documents can never execute Prolog, crash or hang the engine."""
import time

import pytest

from reasoner.bundled import bundled
from reasoner.engine import QuestionError, get_engine
from reasoner.le.document import parse_document, parse_facts, parse_question
from reasoner.le.errors import LEError
from reasoner.le.sentences import parse_fact

DOC = """the templates are:
*a vehicle* has *a colour* light.
*a vehicle* can go.
*a vehicle* is named *a name*.
the knowledge base k includes:
a vehicle can go if the vehicle has green light.
"""


def hostile(marker):
    return [
        f"'), shell('touch {marker}'), ('",
        f":- shell('touch {marker}')",
        f"\" ), halt, ( \"",
        "halt",
        f"X), call(shell('touch {marker}')",
        "A =.. [shell, 'x'], call(A)",
        "[a|b]",
        "'\\x00\\n'",
        "1 + 2 * (3",
        "% not a comment",
        "\u202e\u0000\u2028",
        "a" * 200_000,
    ]


def alive():
    engine = get_engine()
    rb = engine.load(DOC, "alive.le")
    assert engine.holds(rb, parse_fact("1 can go", rb.document.templates),
                        [parse_fact("1 has green light", rb.document.templates)])


def test_hostile_constants_in_facts_are_data(tmp_path):
    engine = get_engine()
    rb = engine.load(DOC, "doc.le")
    marker = tmp_path / "pwned"
    for text in hostile(marker):
        fact = parse_fact(f"7 is named {text}", rb.document.templates)
        assert fact is not None and fact.functor == "is_named"
        answer = engine.ask(rb, parse_fact("7 can go", rb.document.templates), [fact])
        assert not answer.holds
        got = engine.answers(rb, parse_question(rb.document, "7 is named which name"), [fact]).answers
        assert len(got) == 1
    assert not marker.exists()
    alive()


def test_hostile_text_in_documents_questions_and_scenarios(tmp_path):
    engine = get_engine()
    marker = tmp_path / "pwned"
    for i, text in enumerate(hostile(marker)):
        if "\u0000" in text or len(text) > 1000:
            continue
        doc = DOC + f"\nscenario s is:\n    7 is named {text.replace('%', 'pct')}.\nquery q is:\n    which vehicle is named which name.\n"
        try:
            rb = engine.load(doc, f"h{i}.le")
        except LEError:
            continue
        engine.query(rb, "q", "s")
        for attempt in (text, f"7 is named {text}", f"which vehicle has {text} light"):
            try:
                engine.answers(rb, parse_question(rb.document, attempt), parse_facts(rb.document, "7 has red light"))
            except LEError:
                pass
    assert not marker.exists()
    alive()


@pytest.mark.parametrize("template", ["halt.", "call *a goal*.", "*a file* delete_file.", "shell *a command*."])
def test_templates_that_would_name_prolog_built_ins_are_refused_or_local(template, tmp_path):
    engine = get_engine()
    marker = tmp_path / "pwned"
    doc = f"the templates are:\n{template}\n*a x* is fine.\nthe knowledge base k includes:\n{marker} is fine.\n"
    try:
        rb = engine.load(doc, "builtin.le")
    except LEError as exc:
        assert "Prolog built-in" in str(exc)
        return
    engine.answers(rb, parse_question(rb.document, "which x is fine"), [])
    assert not marker.exists()


def test_rules_that_recurse_without_end_give_an_error_not_a_hang():
    engine = get_engine()
    doc = """the templates are:
*a x* is red.
*a number* is big.
the knowledge base k includes:
a x is red if the x is red.
a number N is big if
    a number M = N + 1
    and M is big.
"""
    rb = engine.load(doc, "loop.le")
    for question in ("which x is red", "3 is big"):
        start = time.monotonic()
        with pytest.raises(QuestionError) as err:
            engine.answers(rb, parse_question(rb.document, question), [])
        assert time.monotonic() - start < 30
        assert "limit" in str(err.value) or "stack" in str(err.value)
        with pytest.raises(QuestionError):
            engine.answers(rb, parse_question(rb.document, question), [], explain=True)
    alive()


def test_huge_and_deep_inputs_are_refused_or_read_quickly():
    rb = get_engine().load(bundled("paper.le"), "paper.le")
    templates = rb.document.templates
    start = time.monotonic()
    assert parse_fact("173 has " + "9" * 5000 + " light", templates).args[1] == "9" * 5000
    assert parse_fact("173 has 1e999 light", templates).args[1] == "1e999"
    assert parse_fact("173 has red light" * 50_000, templates) is None
    assert parse_fact("x " * 500_000, templates) is None
    assert parse_fact(None, templates) is None
    assert parse_fact("173 has " + "red " * 90_000 + "light", templates).functor == "has_light"
    deep = "the templates are:\n*a person* says that *a sentence*.\nthe knowledge base k includes:\n" + \
        "a says that " * 5000 + "a says that b says that c.\n"
    try:
        parse_document(deep, "deep.le")
    except LEError as exc:
        assert "deep.le" in str(exc)
    assert time.monotonic() - start < 20
    alive()


def test_a_recorded_fact_in_a_builtins_words_is_not_taken_as_a_fact():
    """`x > y` fits the comparison built-in: as a recorded observation it is an unknown fact."""
    from reasoner.le.document import parse_document
    from reasoner.le.sentences import parse_fact
    doc = parse_document("the templates are:\n*a vehicle* is stopped.\n")
    assert parse_fact("<script > alert(1)</script>", doc.templates) is None
    assert parse_fact("7 > 3", doc.templates) is None
    assert parse_fact("173 is stopped", doc.templates).functor == "is_stopped"
