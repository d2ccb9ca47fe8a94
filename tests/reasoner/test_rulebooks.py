"""The Highway Code rulebooks (`reasoner/rules/*.le`): each loads and passes its `.le.tests` on its
own, the paper's two scenarios come out punishable and mitigated with explanations that cite
HC 176 and TSRGD 2016 Sch 14 Pt 1 para 5, and validators.le's restatement of highway_code.le's
rules has not drifted from the original."""
import re

import pytest

from reasoner.bundled import RULES_DIR
from reasoner.engine import get_engine
from reasoner.rules_verify import verify_file

RULEBOOKS = ["highway_code.le", "monitors.le", "validators.le", "penalties.le", "liability.le"]


@pytest.mark.parametrize("name", RULEBOOKS)
def test_rulebook_passes_its_scenario_suite(name):
    path = RULES_DIR / name
    assert (RULES_DIR / (name + ".tests")).is_file()
    report = verify_file(path)
    assert report.error is None, report.error
    failed = [(o.expectation.query, o.expectation.scenario, o.got, o.error)
              for o in report.outcomes if not o.passed]
    assert not failed
    assert report.passed >= 10


def load(name):
    engine = get_engine()
    return engine, engine.load((RULES_DIR / name).read_text(encoding="utf-8"), name)


def cited(rb, trees, status=("proved",)):
    """(label, law) of every rule used by a node of the trees with one of the statuses."""
    out = set()

    def walk(node):
        if isinstance(node, list):
            for n in node:
                walk(n)
            return
        rule = rb.rule(node.get("rule"))
        if rule is not None and node["status"] in status:
            out.add((rule.label, rule.law))
        for child in node.get("children", []):
            walk(child)
    walk(trees)
    return out


def cites_para_5(citations):
    return any(label == "HC 176" and law and "TSRGD 2016 Sch 14 Pt 1 para 5" in law for label, law in citations)


def test_paper_car_173_punishable_citing_hc_176_and_tsrgd():
    engine, rb = load("validators.le")
    result = engine.query(rb, "punishable", "car_173", explain=True)
    assert result.answers == ["173 punishably violates enter the junction"]
    assert engine.query(rb, "mitigated", "car_173").answers == []
    assert cites_para_5(cited(rb, result.proofs))


def test_paper_ambulance_253_mitigated_citing_hc_176_and_tsrgd():
    engine, rb = load("validators.le")
    result = engine.query(rb, "mitigated", "ambulance_253", explain=True)
    assert result.answers == ["253 mitigately violates enter the junction"]
    assert engine.query(rb, "punishable", "ambulance_253").answers == []
    # the exception that applies (para 5(4) and (6)) is proved, and the prohibitions it replaces are cited
    assert cites_para_5(cited(rb, result.proofs))
    assert cites_para_5(cited(rb, result.proofs, status=("failed",)))


@pytest.mark.parametrize("scenario", ["ambulance_off_call", "ambulance_forces_pedestrian",
                                      "ambulance_forces_driver"])
def test_ambulance_without_the_exception_is_punishable(scenario):
    engine, rb = load("validators.le")
    assert engine.query(rb, "mitigated", scenario).answers == []
    assert len(engine.query(rb, "punishable", scenario).answers) == 1


def rule_blocks(text):
    kb = text.split("includes:", 1)[1]
    return {b.strip() for b in re.split(r"\n\s*\n", kb) if b.strip() and not b.lstrip().startswith("scenario")}


def test_validators_restate_highway_code_verbatim():
    hc = (RULES_DIR / "highway_code.le").read_text(encoding="utf-8")
    val = (RULES_DIR / "validators.le").read_text(encoding="utf-8")
    restated = val.split("% restated from highway_code.le", 1)[1].split("% end of restatement", 1)[0]
    blocks = rule_blocks("includes:" + restated)
    assert len(blocks) >= 15
    assert blocks <= rule_blocks(hc), blocks - rule_blocks(hc)
    # every prohibition of the actions a monitor records is restated
    for head in ("a vehicle must not enter the junction", "a vehicle must not enter the box junction",
                 "a vehicle must not exceed the speed limit"):
        assert sum(head in b for b in rule_blocks(hc)) == sum(head in b for b in blocks)
    # and every rule those prohibitions rest on (the light at the line, the emergency purposes and
    # their hindrance, s.87, the worn Stop line, danger to a person)
    for head in ("a vehicle faces a colour light at the stop line", "a vehicle may go on at the amber light",
                 "a vehicle is used for an emergency purpose", "the emergency exception applies",
                 "observing the red signal would be likely", "is one of the purposes set out in paragraph 5(6)",
                 "the speed limit does not apply", "a vehicle is used for a purpose of section 87",
                 "is one of the purposes of section 87", "observing the speed limit would be likely",
                 "a vehicle would endanger a person", "a vehicle has stopped before entering the major road",
                 "a vehicle must give way to a road user"):
        assert sum(head in rule_head(b) for b in rule_blocks(hc)) == sum(head in rule_head(b) for b in blocks) > 0, head


def rule_head(block):
    """The first line of a rule or fact that is not a comment: its head."""
    return next(line for line in block.splitlines() if not line.lstrip().startswith("%"))


def test_penalties_restate_the_light_at_the_stop_line_verbatim():
    """penalties.le's traffic light offence is on the light the vehicle crossed on: it restates
    highway_code.le's rules for that light, and the copy must not drift."""
    hc = (RULES_DIR / "highway_code.le").read_text(encoding="utf-8")
    pen = (RULES_DIR / "penalties.le").read_text(encoding="utf-8")
    restated = pen.split("% restated from highway_code.le", 1)[1].split("% end of restatement", 1)[0]
    blocks = rule_blocks("includes:" + restated)
    assert len(blocks) == 2 and blocks <= rule_blocks(hc)
    assert sum("a vehicle faces a colour light at the stop line" in rule_head(b) for b in rule_blocks(hc)) == 2


def test_highway_code_labels_every_rule_170_to_183():
    _, rb = load("highway_code.le")
    rules = [r for r in rb.document.rules if r.section == "kb"]
    unlabelled = [r.text for r in rules if r.label is None]
    assert len(unlabelled) == 1 and unlabelled[0].startswith("a vehicle can an action")
    numbers = {int(r.label.split()[1]) for r in rules if r.label}
    assert set(range(170, 184)) <= numbers
    assert all(r.law for r in rules if r.label)
