"""The LE parser and engine fuzzed: documents built from LE's words with hostile sizes (many slots,
long sentences, deep brackets) and arithmetic of any numbers, parsed and asked, end in an answer,
an LEError or a QuestionError, within the budgets (a parse error is located; no question runs away)."""
from __future__ import annotations

import time

from hypothesis import given
from hypothesis import strategies as st

from reasoner.engine import QuestionError, get_engine
from reasoner.le.document import parse_document, parse_question
from reasoner.le.errors import LEError
from tests.fuzz.budget import fuzz

TEMPLATE = "the templates are:\n*a number* becomes *a result*.\nthe knowledge base k includes:\n"
OPS = ["+", "-", "*", "/"]
number = st.one_of(st.integers(-10**30, 10**30), st.sampled_from([0, 1, -1, 2, 10**300, 2**4095, 2**4096]),
                   st.floats(allow_nan=False, allow_infinity=False, width=32).map(lambda f: round(f, 3)))


@st.composite
def expression(draw, depth=0):
    if depth > 3 or draw(st.booleans()):
        return draw(st.one_of(number.map(str), st.just("the number")))
    return f"({draw(expression(depth + 1))} {draw(st.sampled_from(OPS))} {draw(expression(depth + 1))})"


@fuzz(30)
@given(expression(), st.integers(0, 12), number)
def test_arithmetic_answers_or_stops_cleanly(expr, repeats, start):
    body = "a number becomes a result\n    if the result = " + expr + ".\n"
    chained = "".join(f"    and a step{i} = the number * the number\n" for i in range(repeats))
    text = TEMPLATE + body.replace(".\n", "\n" + chained + "    and the result = the result.\n") if repeats else TEMPLATE + body
    engine = get_engine()
    started = time.monotonic()
    try:
        rb = engine.load(text, "fuzz.le")
        engine.answers(rb, parse_question(rb.document, f"{start} becomes which result"), [])
    except (LEError, QuestionError):
        pass
    assert time.monotonic() - started < 10


words = st.sampled_from(["*a x*", "*an y*", "and", "or", "if", "the", "a", "is", "red", "(", ")", "=", "*", "1",
                         "2021-01-01", ",", "\n", "\n    ", "not", "it", "case", "that"])


@fuzz(15)
@given(st.lists(words, max_size=200), st.integers(1, 80), st.integers(0, 2000))
def test_documents_with_hostile_shapes_parse_or_fail_located(tail, slots, brackets):
    template = " and ".join(f"*a x{i}*" for i in range(slots)) + " are fine"
    text = ("the templates are:\n" + template + ".\n*a x* is red.\nthe knowledge base k includes:\n"
            "a x is red if the x = " + "(" * brackets + "1" + ")" * brackets + " ".join(tail) + ".\n")
    started = time.monotonic()
    try:
        parse_document(text, "fuzz.le")
    except LEError as exc:
        assert exc.file == "fuzz.le" and exc.line >= 0
    assert time.monotonic() - started < 10
