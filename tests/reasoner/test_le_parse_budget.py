"""The parsing budget of an LE document (issue 15, finding 6): a template of thousands of slots,
a rule of a hundred thousand conditions, a sentence of a hundred thousand words, deep brackets or
tens of thousands of rules each end in a located error (file:line), quickly; a 3,000-slot
template used to end `gaps rules check` in a Prolog traceback (`max_procedure_arity`)."""

from __future__ import annotations

import time

import pytest

from reasoner.bundled import RULES_DIR
from reasoner.engine import get_engine
from reasoner.le.document import MAX_STATEMENT_TOKENS, MAX_TOKENS, parse_document
from reasoner.le.errors import LEError
from reasoner.le.templates import MAX_SLOTS
from tests.helpers.cli import gaps

HEAD = "the templates are:\n*a x* is red.\n*a x* is blue.\nthe knowledge base k includes:\n"


def slots_template(n: int, joiner: str = " and ") -> str:
    return joiner.join(f"*a x{i}*" for i in range(n)) + " are big"


def test_a_template_of_3000_slots_is_a_located_error_not_a_traceback(tmp_path):
    doc = tmp_path / "slots.le"
    doc.write_text("the templates are:\n" + slots_template(3000) + ".\nthe knowledge base k includes:\n",
                   encoding="utf-8")
    result = gaps("rules", "check", str(doc))
    assert result.exit_code == 1
    assert result.stderr.startswith("slots.le:2:1: ")


def test_a_template_of_more_slots_than_allowed_is_refused_where_it_is_written():
    text = "the templates are:\n*a y* is red.\n" + slots_template(MAX_SLOTS + 1) + ".\n"
    with pytest.raises(LEError, match=f"a template of {MAX_SLOTS + 1} slots; a template has at most {MAX_SLOTS}") as err:
        parse_document(text, "wide.le")
    assert (err.value.file, err.value.line) == ("wide.le", 3)


def test_a_template_of_the_most_slots_allowed_loads_and_answers():
    n = MAX_SLOTS
    template = slots_template(n)
    rule = " and ".join(f"a x{i}" for i in range(n)) + " are big if 1 > 0"
    rb = get_engine().load("the templates are:\n" + template + ".\nthe knowledge base k includes:\n"
                           + rule + ".\n", "wide.le")
    assert rb.document.templates and len(rb.document.rules) == 1


@pytest.mark.parametrize("name, text, message, line", [
    ("one rule of 100,000 conditions",
     HEAD + "a x is red if\n" + "\nand ".join("the x is blue" for _ in range(100_000)) + ".\n",
     f"more than {MAX_TOKENS} words and signs", 20_000),
    ("one sentence of 300,000 words", HEAD + "a x is red if the x is " + "very " * 300_000 + "blue.\n",
     f"more than {MAX_TOKENS} words and signs", 5),
    ("20,000 rules", HEAD + "a x is red if the x is blue.\n" * 20_000,
     f"more than {MAX_TOKENS} words and signs", 10_002),
    ("a statement over the statement cap", HEAD + "a x is red if the x is " + "very " * MAX_STATEMENT_TOKENS + "blue.\n",
     f"a statement has at most {MAX_STATEMENT_TOKENS}", 5),
    ("6,000 short rules", HEAD + "a x is red.\n" * 6_000, "a document has at most 5000", 5_001),
    ("brackets 1,500 deep", HEAD + "a x is red if the x = " + "(" * 1500 + "1" + ")" * 1500 + ".\n",
     "nests too deeply", 5),
])
def test_documents_over_the_budget_end_in_a_located_error_quickly(name, text, message, line):
    started = time.monotonic()
    with pytest.raises(LEError, match=message) as err:
        parse_document(text, "big.le")
    assert (err.value.file, err.value.line) == ("big.le", line), name
    assert time.monotonic() - started < 8, name  # 25 to 55 s before, on this machine


def test_the_deadline_stops_a_slow_document_at_the_statement_it_reached(monkeypatch):
    from reasoner.le import document
    monkeypatch.setattr(document, "PARSE_SECONDS", 0.0)
    with pytest.raises(LEError, match="took longer than 0 s to read") as err:
        parse_document(HEAD + "a x is red if the x is blue.\n", "slow.le")
    assert err.value.line == 1


def test_the_bundled_rulebooks_are_well_within_the_budget():
    for path in sorted(RULES_DIR.glob("*.le")):
        started = time.monotonic()
        parse_document(path.read_text(encoding="utf-8"), path.name)
        assert time.monotonic() - started < 2, path.name
