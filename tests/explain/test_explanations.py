"""Explanations read as English built from the proofs, with the rule and the evidence cited: the
demo's run (paper.le), a hostile fact in HTML and Markdown, why-not on request, and a run whose
hash chain was tampered with."""
import sqlite3

import pytest

from tests.helpers.explained_cases import explained
from explain import explain_incident
from explain.explanation_doc import document
from explain.explanation_formats import html_fragment, html_page, render, to_markdown
from reasoner.investigation import Investigation
from sim_replay.paper import RUN, paper_run
from store import Store


@pytest.fixture(scope="module")
def paper(tmp_path_factory):
    with Store(tmp_path_factory.mktemp("x") / "s.db") as store:
        store.append(paper_run())
        inv = Investigation(store)
        return {inc.vehicle: explain_incident(inv, inc) for inc in inv.incidents(RUN)}


def test_paper_car_explanation(paper):
    text = paper["173"]
    assert text.startswith("Vehicle 173 committed a punishable violation of Highway Code rule 176 at "
                           "08:00:10.000 UTC: it\nentered the junction against a red light.")
    assert "because 173 has red light [E6]" in text
    assert "every rule for it needs one of 173 is of type ambulance [HC 176, paper.le:26]; 173 has green light" in text
    assert "Liable: the driver." in text
    assert "E6 08:00:10.000 UTC monitor/m1 0 monitor.observation" in " ".join(text.split())


def test_paper_ambulance_explanation(paper):
    text = paper["253"]
    assert text.startswith("Vehicle 253 committed a mitigated violation of Highway Code rule 176")
    assert "which the rules allow because 253 is of type ambulance" in " ".join(text.split())
    assert "and 253 can enter the junction [HC 176, paper.le:26]" in text


HOSTILE = "<script>alert(1)</script> & *bold* [x](javascript:1) | \x1b[31m"


def hostile_doc(tmp_path):
    """Car 173's run with a hostile sentence in its perception and in the monitor's observation."""
    from tests.helpers.verdict_runs import RUN as VP_RUN, RunBuilder
    run = RunBuilder()
    run.spawn("173", "car")
    run.lights(10, "red")
    run.crossing("173", 10, ["173 is of type car", "173 has red light", HOSTILE],
                 ["173 has red light", "173 crossed the stop line on red light", HOSTILE])
    with Store(tmp_path / "h.db") as store:
        store.append(run.finish())
        inv = Investigation(store)
        (inc,) = inv.incidents(VP_RUN)
        return document(inc, inv.explanation(inc), store)


def test_hostile_fact_is_escaped_in_html_markdown_and_text(tmp_path):
    doc = hostile_doc(tmp_path)
    assert "alert(1)" in repr(doc), "the hostile sentence reaches the explanation (as a fact or finding)"
    for page in (html_fragment(doc, "full"), html_page(doc)):
        assert "<script" not in page and "&lt;script" in page and "alert(1)&lt;/script&gt;" in page
        assert "\x1b" not in page
    md = to_markdown(doc, "full")
    assert "<script" not in md and "&lt;script" in md and "\\*bold\\*" in md and "\\|" in md
    text = render(doc, "text", "full")
    assert "\x1b" not in text and "\\x1b[31m" in text
    assert doc["incident"]["verdict"] == "punishable"


def test_why_not_on_request(tmp_path):
    _, doc = explained(tmp_path / "s.db", "paper_car_173_punishable",
                       why_not=["173 can enter the junction", "173 has green light", "173 flies"])
    can, green, nonsense = doc["why_not"]
    assert can["holds"] is False and can["question"] == "173 can enter the junction"
    text = render(doc, "text", "standard")
    assert "“173 can enter the junction” does not hold on the validator scenario (validators.le):" in text
    assert "but 173 must not enter the junction [HC 176, validators.le:183]" in text
    assert green["holds"] is False and "173 has green light: not recorded" in text
    assert "error" in nonsense and "cannot read" in nonsense["error"]


def test_why_not_of_a_sentence_that_holds(tmp_path):
    _, doc = explained(tmp_path / "s.db", "paper_car_173_punishable", why_not=["173 must not enter the junction"])
    (w,) = doc["why_not"]
    assert w["holds"] is True and w["trees"][0]["label"] == "HC 176"


def test_a_tampered_run_says_its_chain_did_not_verify(tmp_path):
    path = tmp_path / "s.db"
    _, clean = explained(path, "paper_car_173_punishable")
    assert clean["evidence"]["chain"]["verified"] is True
    assert all(r["chain_pos"] is not None for r in clean["evidence"]["events"])
    spawn = next(r for r in clean["evidence"]["events"] if r["kind"] == "entity.spawn")
    conn = sqlite3.connect(path)        # as an attacker with the file would (tests/store does the same)
    conn.execute("DROP TRIGGER IF EXISTS events_no_update")
    changed = conn.execute("UPDATE events SET event = replace(event, 'GAPS 173', 'GAPS 999') "
                           "WHERE run = 'verdict-paths' AND chain_pos = ?", (spawn["chain_pos"],)).rowcount
    conn.commit()
    conn.close()
    assert changed == 1
    _, doc = explained(path, "paper_car_173_punishable")
    chain = doc["evidence"]["chain"]
    assert chain["verified"] is False and chain["problem"]["chain_pos"] == spawn["chain_pos"]
    text = render(doc, "text", "summary")
    assert "WARNING: the run's hash chain did NOT verify" in " ".join(text.split())    # wherever the line wraps
    assert f"events from chain position {spawn['chain_pos']} on are not vouched for" in " ".join(text.split())
    rows = doc["evidence"]["events"]
    assert all(r["vouched"] is (r["chain_pos"] < spawn["chain_pos"]) for r in rows)
    assert "(not vouched for)" in render(doc, "text", "standard")


def test_levels_grow(tmp_path):
    _, doc = explained(tmp_path / "s.db", "paper_ambulance_253_mitigated")
    summary, standard, full = (render(doc, "text", lvl) for lvl in ("summary", "standard", "full"))
    assert len(summary) < len(standard) < len(full)
    assert "other rules do not apply" in standard and "other rules do not apply" not in full
    assert "9. Rulebooks" in full and "9. Rulebooks" not in standard
