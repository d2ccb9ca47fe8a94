"""`gaps regress` as a user types it: exit codes, the report, --json, --junit, golden runs."""
from __future__ import annotations

import hashlib
import json
import os
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from tests.helpers.cli import gaps
from tests.reasoner import regress_runs as R

GOLDEN = Path(__file__).parents[1] / "golden" / "golden-sim.json"


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    return R.build_store(tmp_path_factory.mktemp("regress-cli") / "gaps.db")


def _sha(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_nothing_changed_exits_0_and_reading_changes_no_store(db):
    before = _sha(db)
    result = gaps("regress", "--rules", "reasoner/rules/penalties.le", "--run", R.RUN, db=db)
    assert result.exit_code == 0, result.output
    assert "Nothing changed: 3 incident(s) and 4 decision(s) of 1 run(s) judged alike." in result.output
    assert _sha(db) == before


def test_a_flipped_verdict_exits_1_with_the_rule_change_report_first(db, tmp_path):
    old = R.edited(tmp_path / "old", "validators.le")
    new = R.edited(tmp_path / "new", "validators.le", cut=(R.AMBER_TOO_CLOSE,))
    result = gaps("regress", "--rules", new, "--baseline", old, "--run", R.RUN, db=db)
    assert result.exit_code == 1, result.output
    out = result.output
    assert out.startswith(f"Rule changes, {old} -> {new}")
    assert "  removed HC 175 " in out and f"-> {R.RUN} monitor/m1:1: verdict flipped, mitigated -> punishable" in out
    assert 'because HC 175 no longer has the rule "a vehicle may go on at the amber light' in out
    assert out.rstrip().endswith("Changed: 1 verdict flipped, 1 decision changed.")


def test_json_and_junit_say_the_same(db, tmp_path):
    new = R.edited(tmp_path, "penalties.le", old="traffic light offence carries a fixed penalty of 100 pounds",
                   new="traffic light offence carries a fixed penalty of 200 pounds")
    junit = tmp_path / "regress.xml"
    result = gaps("regress", "--rules", new, "--all", "--json", "--junit", junit, db=db)
    assert result.exit_code == 1, result.output
    data = json.loads(result.output)
    assert data["changed"] is True and data["counts"]["penalty"] == 2
    (rule,) = data["rule_changes"][0]["changes"]
    assert rule["kind"] == "changed" and len(rule["flipped"]) == 2
    root = ET.fromstring(junit.read_bytes())
    cases = root.findall(".//testcase")
    assert len(cases) == data["counts"]["incidents"] + data["counts"]["decisions"] == 7
    failures = root.findall(".//failure")
    assert len(failures) == 2 == int(root.get("failures"))
    assert all(f.get("type") == "penalty" and "200 pounds" in f.text for f in failures)


@pytest.mark.parametrize("args, says", [
    (["--rules", "nope.le", "--run", R.RUN], "no such rulebook file or directory: nope.le"),
    (["--rules", "reasoner/rules/penalties.le", "--run", "nope"], "no run 'nope'"),
    (["--rules", "reasoner/rules/penalties.le"], "name the runs with --run R (repeatable) or --all"),
    (["--run", R.RUN], "name the new rulebook with --rules"),
])
def test_mistakes_exit_2_with_a_message(db, args, says):
    result = gaps("regress", *args, db=db)
    assert result.exit_code == 2 and says in result.output


def test_a_rulebook_that_does_not_parse_or_is_used_by_no_stage_exits_2(db, tmp_path):
    bad = tmp_path / "bad.le"
    bad.write_text("the templates are:\n*a vehicle* is shiny.\n\nthe knowledge base k includes:\n"
                   "a vehicle is shiny if\n    the vehicle is glossy.\n")
    result = gaps("regress", "--rules", bad, "--run", R.RUN, db=db)
    assert result.exit_code == 2 and "rulebook error: " in result.output and f"{bad}:" in result.output
    useless = tmp_path / "useless.le"
    useless.write_text("the templates are:\n*a vehicle* is shiny.\n\nthe knowledge base k includes:\n"
                       "a vehicle is shiny if\n    the vehicle is shiny.\n")
    result = gaps("regress", "--rules", useless, "--run", R.RUN, db=db)
    assert result.exit_code == 2 and "is used by no stage" in result.output


def test_golden_approval_on_a_small_store(db, tmp_path):
    golden = tmp_path / "golden.json"
    made = gaps("regress", "--golden", golden, "--update-golden", "--run", R.RUN, db=db)
    assert made.exit_code == 0, made.output
    approved = json.loads(golden.read_text())
    assert [i["verdict"] for i in approved["runs"][R.RUN]["incidents"]] == ["mitigated", "punishable", "punishable"]
    assert gaps("regress", "--golden", golden, db=db).exit_code == 0
    new = R.edited(tmp_path / "new", "validators.le", cut=(R.AMBER_TOO_CLOSE,))
    flipped = gaps("regress", "--golden", golden, "--rules", new, db=db)
    assert flipped.exit_code == 1 and "verdict flipped: mitigated -> punishable" in flipped.output
    assert "not approved" in flipped.output
    assert gaps("regress", "--golden", golden, "--rules", new, "--update-golden", db=db).exit_code == 0
    assert gaps("regress", "--golden", golden, "--rules", new, db=db).exit_code == 0


def test_the_golden_runs_are_judged_as_approved():
    """The CI check: a change to reasoner/rules/ that flips a golden verdict fails here until
    approved with `gaps regress --golden tests/golden/golden-sim.json --update-golden`."""
    result = gaps("regress", "--golden", GOLDEN)
    assert result.exit_code == 0, result.output
    assert "Nothing changed" in result.output
    # and it prints what docs/regress.md shows (run here once, not again by tests/docs: 20 s)
    from tests.docs.test_doc_commands import ROOT, fences, matches, steps
    (shown,) = [lines for fence in fences(ROOT / "docs" / "regress.md") for command, lines in steps(fence)
                if command == "gaps regress --golden tests/golden/golden-sim.json"]
    assert matches(shown, result.output.splitlines()), result.output



def test_a_recording_regresses_straight_as_the_store_it_was_exported_from(db, tmp_path):
    from store import Store
    from store.transfer import export_run
    recording = tmp_path / "run.mcap"
    with Store.open_read_only(db) as store:
        export_run(store, R.RUN, recording)
    new = R.edited(tmp_path, "validators.le", cut=(R.AMBER_TOO_CLOSE,))
    straight = gaps("regress", recording, "--rules", new, "--json")
    from_store = gaps("regress", "--rules", new, "--all", "--json", db=db)
    assert straight.exit_code == from_store.exit_code == 1, straight.output
    assert json.loads(straight.output) == json.loads(from_store.output)
    assert list(tmp_path.glob("*.db")) == []                 # the store it was judged in is gone


def test_two_local_workers_print_what_one_process_prints(db, tmp_path):
    """About 12 s: a LocalCluster of two processes starts, each with its own Prolog engine. Both
    commands run in fresh processes (a rulebook is named by the path a process first loaded it
    from)."""
    new = R.edited(tmp_path, "validators.le", cut=(R.AMBER_TOO_CLOSE,))
    root = Path(__file__).parents[2]

    def command(*more: str) -> subprocess.CompletedProcess:
        return subprocess.run([sys.executable, "-m", "cli.main", "regress", "--rules", str(new), "--all", "--json",
                               "--db", str(db), *more], cwd=root, env={**os.environ, "PYTHONPATH": str(root)},
                              capture_output=True, text=True, timeout=300)
    one, two = command(), command("--workers", "2")
    assert one.returncode == two.returncode == 1, two.stderr
    assert one.stdout == two.stdout and "Traceback" not in two.stderr


@pytest.mark.parametrize("args, says", [
    (["nope.mcap", "--rules", "reasoner/rules/penalties.le"], "no such file: nope.mcap"),
    (["tests/golden/golden-sim.mcap", "--rules", "reasoner/rules/penalties.le", "--run", R.RUN],
     "regress either recordings (FILES.mcap) or a store's runs"),
    (["--golden", str(GOLDEN), "--workers", "2"], "--golden judges its own runs in one process"),
])
def test_recording_and_cluster_mistakes_exit_2_with_a_message(db, args, says):
    result = gaps("regress", *args, db=db)
    assert result.exit_code == 2 and says in result.output, result.output


def test_golden_junit_cases_carry_times(db, tmp_path):
    """`gaps regress --junit` had no `time` attributes (issue 39); a golden run's cases too."""
    import xml.etree.ElementTree as ET
    golden, junit = tmp_path / "golden.json", tmp_path / "golden.xml"
    assert gaps("regress", "--golden", golden, "--update-golden", "--run", R.RUN, db=db).exit_code == 0
    assert gaps("regress", "--golden", golden, "--junit", junit, db=db).exit_code == 0
    root = ET.fromstring(junit.read_bytes())
    cases = root.findall(".//testcase")
    assert cases and all(float(c.get("time")) >= 0 for c in cases)
    assert float(root.get("time")) > 0
