"""`gaps rules check|query|prolog|verify`, as a rule author runs them."""
import json
import subprocess
import sys
from pathlib import Path

import pytest

GAPS = str(Path(sys.executable).with_name("gaps"))
SUITE = Path(__file__).parents[2].parent / "shared/le/conformance"
PAPER = Path(__file__).parents[2] / "reasoner/rules/paper.le"


def gaps(*args):
    return subprocess.run([GAPS, "rules", *map(str, args)], capture_output=True, text=True, timeout=120)


def test_check_ok_and_error_exit_codes(tmp_path):
    ok = gaps("check", PAPER)
    assert ok.returncode == 0 and "paper.le: ok (9 templates, 5 rules" in ok.stdout
    bad = tmp_path / "bad.le"
    bad.write_text("the templates are:\n*a x* is red.\nthe knowledge base k includes:\na x is red if\n"
                   "    the x flies.\n", encoding="utf-8")
    r = gaps("check", bad)
    assert r.returncode == 1 and r.stderr.startswith("bad.le:5:5: no template fits") and "hint:" in r.stderr
    j = gaps("check", bad, "--json")
    assert j.returncode == 1 and json.loads(j.stdout)["errors"][0]["line"] == 5


def test_query_by_name_and_by_sentence_with_explanations(tmp_path):
    doc = tmp_path / "p.le"
    doc.write_text(PAPER.read_text(encoding="utf-8") + """
scenario car is:
    173 is of type car.
    173 has red light.

scenario ambulance is:
    253 is of type ambulance.
    253 has red light.

query enter is:
    which vehicle can enter the junction.
""", encoding="utf-8")
    r = gaps("query", doc, "--query", "enter", "--scenario", "ambulance", "--json")
    assert r.returncode == 0 and json.loads(r.stdout) == {"answers": ["253 can enter the junction"]}
    r = gaps("query", doc, "-q", "173 can enter the junction", "-s", "car", "--explain")
    assert r.stdout.startswith("no answers") and "173 has green light is not established" in r.stdout
    r = gaps("query", doc, "-q", "enter", "-s", "ambulance", "--explain", "--json")
    tree = json.loads(r.stdout)["proofs"][0][0]
    assert tree["label"] == "HC 176" and tree["source"] == {"file": "p.le", "line": 26}
    assert tree["text"] == "253 can enter the junction" and tree["children"][1]["sentence"][0] == "$not"
    r = gaps("query", doc, "-q", "which vehicle can enter the junction", "-f", "9 has green light.")
    assert r.stdout.strip() == "9 can enter the junction"


def test_prolog_shows_clauses_with_their_source_lines():
    r = gaps("prolog", PAPER)
    assert r.returncode == 0
    assert "% paper.le:26 [HC 176]\ncan(Vehicle, 'enter the junction') :-" in r.stdout
    assert "\\+ must_give_way_to(Vehicle, OtherVehicle)" in r.stdout


@pytest.mark.skipif(not SUITE.is_dir(), reason="no conformance suite")
def test_verify_counts_passes_and_failures():
    r = gaps("verify", SUITE / "gst.le")
    assert r.returncode == 0 and r.stdout.strip().endswith("12 passed, 0 failed (2 after normalising dates "
                                                           "and punctuation spacing)")
    r = gaps("verify", SUITE, "--json")
    report = json.loads(r.stdout)
    assert report["passed"] + report["failed"] == 163 and report["passed"] >= 155
