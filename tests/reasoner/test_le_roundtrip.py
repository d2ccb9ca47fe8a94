"""Translated into and out of Prolog (paper, section 5): every compiled rule renders back as LE
that compiles to the same rule, and every answer and goal renders with the rulebook's templates."""
from pathlib import Path

import pytest

from reasoner.bundled import bundled
from reasoner.engine import get_engine
from reasoner.le.document import parse_document, parse_rule
from reasoner.le.errors import LEError
from reasoner.le.render import rule_text

SUITE = Path(__file__).parents[2].parent / "shared/le/conformance"
DOCS = [("paper.le", bundled("paper.le"))] + \
    [(p.name, p.read_text(encoding="utf-8")) for p in sorted(SUITE.glob("*.le")) if p.name != "error.le"]


@pytest.mark.parametrize("name, text", DOCS, ids=[n for n, _ in DOCS])
def test_every_rule_renders_back_to_le_that_compiles_to_the_same_rule(name, text):
    doc = parse_document(text, name)
    for rule in doc.rules:
        again = parse_rule(doc, rule_text(rule, doc))
        assert (again.head, again.body) == (rule.head, rule.body), rule_text(rule, doc)


def test_rule_text_reads_like_the_source():
    doc = parse_document(bundled("paper.le"), "paper.le")
    assert rule_text(doc.rules[0], doc) == (
        "a vehicle can enter the junction if\n"
        "    the vehicle is of type ambulance\n"
        "    and it is not the case that\n"
        "        the vehicle must give way to an other vehicle.")


def test_goals_and_answers_render_with_the_templates():
    engine = get_engine()
    rb = engine.load(bundled("paper.le"), "paper.le")
    assert rb.render(["has_light", 173, "red"]) == "173 has red light"
    assert rb.render(["$not", [["is_stopped", {"var": "vehicle"}]]]) == "it is not the case that a vehicle is stopped"
    assert rb.render(["is_a", 173, "ambulance"]) == "173 is an ambulance"
    assert rb.render([">=", {"var": "turnover"}, 75000]) == "a turnover >= 75000"
    with pytest.raises(LEError):
        parse_rule(rb.document, "a vehicle flies.")
