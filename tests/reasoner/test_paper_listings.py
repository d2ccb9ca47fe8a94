"""The paper's own LE listings (section 7), taken verbatim from the LaTeX source, compile and
answer as the paper says: the car may not enter on red and its violation is punishable; the
ambulance may, and its violation is mitigated."""
import re
from pathlib import Path

import pytest

from reasoner.engine import get_engine
from reasoner.le.document import parse_facts, parse_question

PAPER = Path(__file__).parents[2].parent / "shared/paper/mind-the-gaps.tex"
TEMPLATES = """the templates are:
*a vehicle* is of type *a type*.
*a vehicle* has *a colour* light.
*a vehicle* is stopped.
*a vehicle* must give way to *a road user*.
*a vehicle* can *an action*.
*a vehicle* potentially violates *an action*.
*a vehicle* punishably violates *an action*.
*a vehicle* mitigately violates *an action*.

the knowledge base paper includes:
"""

pytestmark = pytest.mark.skipif(not PAPER.is_file(), reason="no paper source")


def listings() -> dict[str, str]:
    tex = PAPER.read_text(encoding="utf-8")
    out = {}
    for m in re.finditer(r"\\begin\{lstlisting\}\[([^\]]*)\]\n(.*?)\\end\{lstlisting\}", tex, re.S):
        label = re.search(r"label=\{([^}]*)\}", m.group(1)).group(1)
        out[label] = m.group(2)
    return out


def scenario_and_goal(listing: str) -> tuple[str, str]:
    scenario, goal = listing.split("goal:")
    return scenario.replace("scenario:", "").strip(), goal.strip()


def test_the_listings_compile_and_answer_as_the_paper_says():
    lst = listings()
    engine = get_engine()
    rb = engine.load(TEMPLATES + lst["lst:junction"] + "\n" + lst["lst:violations"] + "\n" +
                     lst["lst:add-validator-rules"], "paper-listings.le")
    doc = rb.document
    assert len(doc.rules) == 5

    car, car_goal = scenario_and_goal(lst["lst:vehicle-scenario"])
    ambulance, ambulance_goal = scenario_and_goal(lst["lst:ambulance-scenario"])
    assert car_goal == "173 can enter the junction." and ambulance_goal == "253 can enter the junction."

    def ask(question, facts):
        return engine.answers(rb, parse_question(doc, question), parse_facts(doc, facts)).answers

    # Vehicle Action: the rules of the road (Listing "Example rule in Logical English")
    assert ask(car_goal, car) == []
    assert ask(ambulance_goal, ambulance) == ["253 can enter the junction"]
    # Monitor: both entered on red without stopping (Listing "Example of the modeled violations")
    assert ask("which vehicle potentially violates entering the junction", car + "\n" + ambulance) == \
        ["173 potentially violates entering the junction", "253 potentially violates entering the junction"]
    # Validator (Listing "Comparing Ideal (Legal) Actions to Real (Violable) Actions"), with the
    # potential violation recorded as the action the vehicle took ("enter the junction", as in
    # reasoner/rules/paper.le: the monitor listing's "entering the junction" never matches "can")
    pv = "\n{v} potentially violates enter the junction."
    assert ask("173 punishably violates enter the junction", car + pv.format(v=173)) == \
        ["173 punishably violates enter the junction"]
    assert ask("173 mitigately violates enter the junction", car + pv.format(v=173)) == []
    assert ask("253 mitigately violates enter the junction", ambulance + pv.format(v=253)) == \
        ["253 mitigately violates enter the junction"]
    assert ask("253 punishably violates enter the junction", ambulance + pv.format(v=253)) == []
