"""The skeleton LE step: templates, sentences, rules and located errors."""
import pytest

from reasoner.bundled import bundled
from reasoner.le.document import parse_document
from reasoner.le.errors import LEError
from reasoner.le.sentences import parse_fact
from reasoner.le.templates import parse_template, render
from reasoner.le.terms import Atom, Var

DOC = """the templates are:
*a vehicle* has *a colour* light.
*a vehicle* is stopped.
*a vehicle* can *an action*.

the knowledge base k includes:
a vehicle can enter the junction if
    the vehicle has green light
    and it is not the case that
        the vehicle is stopped.
"""


def test_template_functor_follows_reference_naming():
    t = parse_template("*a vehicle* has *a colour* light at *a time*.")
    assert t.functor == "has_light_at" and t.arity == 3
    assert render(t, ["173", "red", "noon"]) == "173 has red light at noon"


def test_rule_compiles_with_variables_constants_and_negation():
    doc = parse_document(DOC, "k.le")
    (rule,) = doc.rules
    assert rule.head == Atom("can", (Var("vehicle"), "enter the junction"))
    assert rule.line == 7
    assert rule.body[0].atom == Atom("has_light", (Var("vehicle"), "green"))
    assert rule.body[1].negated[0].atom == Atom("is_stopped", (Var("vehicle"),))


def test_facts_are_ground_and_numbers_are_numbers():
    doc = parse_document(DOC)
    assert parse_fact("173 has red light.", doc.templates) == Atom("has_light", (173, "red"))
    assert parse_fact("173 drives on the moon", doc.templates) is None


def test_paper_rulebook_parses_with_rule_labels():
    doc = parse_document(bundled("paper.le"), "paper.le")
    assert len(doc.rules) == 5
    assert [r.label for r in doc.rules[:3]] == ["HC 176"] * 3
    assert doc.rules[0].law.startswith("RTA 1988 s.36")


@pytest.mark.parametrize("text, line, message", [
    (DOC.replace("has green light", "flies over the junction"), 8, "no template fits"),
    (DOC.replace("        the vehicle is stopped.", "    the vehicle is stopped."), 9, "indented block"),
    (DOC.rstrip().rstrip("."), 7, "no full stop"),
])
def test_errors_are_located(text, line, message):
    with pytest.raises(LEError) as err:
        parse_document(text, "k.le")
    assert err.value.line == line and message in str(err.value)
    assert str(err.value).startswith(f"k.le:{line}:")
