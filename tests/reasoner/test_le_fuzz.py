"""Parser fuzzing: any text gives a Document or a clean LEError, and within a second."""
import random
import time
from pathlib import Path

from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from reasoner.bundled import bundled
from reasoner.le.document import parse_document, parse_facts, parse_question
from reasoner.le.errors import LEError
from reasoner.le.sentences import parse_fact

PAPER = bundled("paper.le")
SUITE = Path(__file__).parents[2].parent / "shared/le/conformance"
SEEDS = [PAPER] + [p.read_text(encoding="utf-8") for p in sorted(SUITE.glob("*.le"))[:6]] if SUITE.is_dir() \
    else [PAPER]
PAPER_DOC = parse_document(PAPER, "paper.le")

WORDS = ["the", "a", "an", "if", "and", "or", "it", "is", "not", "case", "that", "which", "each", "for",
         "all", "cases", "in", "where", "such", "sum", "of", "set", "collection", "templates", "are",
         "knowledge", "base", "includes", "ontology", "scenario", "query", "target", "language",
         "prolog", "vehicle", "other", "first", "number", "X", "light", "red", "2021-10-09",
         "2021-02-30", "3.5", "-", "+", "*", "/", "=", "<", ">=", "=<", "(", ")", "[", "]", ",", ".",
         ":", "%", "'", '"', "\\", "\t", "\n", "\n    ", "\n        ", "*a vehicle*", "*", "that",
         "it is not the case that\n", "for all cases in which\n", "it is the case that\n"]

tokens = st.lists(st.sampled_from(WORDS), max_size=120).map(lambda ws: " ".join(ws))
unicode_text = st.text(max_size=400)


@st.composite
def mutated(draw):
    """A real document with a few random cuts, duplications and insertions."""
    text = draw(st.sampled_from(SEEDS))
    rnd = random.Random(draw(st.integers(0, 2 ** 32)))
    for _ in range(draw(st.integers(1, 6))):
        if not text:
            break
        i, j = sorted(rnd.randrange(len(text) + 1) for _ in range(2))
        op = rnd.randrange(4)
        if op == 0:
            text = text[:i] + text[j:]
        elif op == 1:
            text = text[:i] + text[i:j] * 2 + text[j:]
        elif op == 2:
            text = text[:i] + rnd.choice(WORDS) + " " + text[i:]
        else:
            text = text[:i] + rnd.choice(["\t", "    ", "\n", ".", ":", "*"]) + text[i:]
    return text


def parses_cleanly(text: str) -> None:
    start = time.monotonic()
    try:
        parse_document(text, "fuzz.le")
    except LEError as exc:
        assert str(exc).startswith("fuzz.le:")
    assert time.monotonic() - start < 1.0


FUZZ = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@FUZZ
@given(st.one_of(tokens, unicode_text))
def test_random_text_parses_or_gives_a_clean_error(text):
    parses_cleanly(text)


@FUZZ
@given(tokens.map(lambda body: "the templates are:\n*a vehicle* has *a colour* light.\n*a vehicle* can go.\n"
                  "the knowledge base k includes:\na vehicle can go if\n    " + body + "\n"))
def test_random_rule_bodies_parse_or_give_a_clean_error(text):
    parses_cleanly(text)


@FUZZ
@given(mutated())
def test_mutated_documents_parse_or_give_a_clean_error(text):
    parses_cleanly(text)


@FUZZ
@given(st.one_of(tokens, unicode_text))
def test_facts_and_questions_never_raise_anything_but_le_errors(text):
    start = time.monotonic()
    fact = parse_fact(text, PAPER_DOC.templates)
    assert fact is None or fact.functor
    for fn in (parse_question, parse_facts):
        try:
            fn(PAPER_DOC, text)
        except LEError:
            pass
    assert time.monotonic() - start < 1.0
