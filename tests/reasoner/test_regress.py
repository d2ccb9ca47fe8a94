"""Regression of modified rulebooks over a small recorded run (tests/reasoner/regress_runs.py):
what each kind of rule change does to the verdicts and decisions, and the reasons given."""
from __future__ import annotations

import pytest

from reasoner.bundled import bundled
from reasoner.regress import regress
from reasoner.regress.books import RegressError
from reasoner.regress.diff import diff_rulebooks
from reasoner.engine import get_engine
from store import NoSuchRun, Store

from tests.reasoner import regress_runs as R


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    return R.build_store(tmp_path_factory.mktemp("regress") / "gaps.db")


def _run(db, rules, baseline=None):
    with Store.open_read_only(db) as store:
        return regress(store, [str(r) for r in rules], [str(b) for b in baseline] if baseline else None, [R.RUN])


def _changes(result, kind=None):
    return [(case, ch) for case, ch in result.changes if kind is None or ch.kind == kind]


def test_the_rules_in_force_change_nothing(db):
    result = _run(db, ["reasoner/rules/validators.le"])
    assert not result.changed
    assert len(result.runs[0].incidents) == 3 and len(result.runs[0].decisions) == 4


def test_removing_the_amber_exception_flips_the_amber_verdict_and_says_which_rule(db, tmp_path):
    new = R.edited(tmp_path, "validators.le", cut=(R.AMBER_TOO_CLOSE,))
    result = _run(db, [new])
    ((case, change),) = _changes(result, "verdict")
    assert case.vehicle == "5" and (change.before, change.after) == ("mitigated", "punishable")
    (rule,) = change.rules
    assert rule.kind == "removed" and rule.label == "HC 175" and "too close to the stop line" in rule.old.text
    assert change.reasons[0].startswith('HC 175 no longer has the rule "a vehicle may go on at the amber light')
    # validators.le also answers the vehicle stage (it restates the Highway Code's permissions)
    ((case, change),) = _changes(result, "decision")
    assert case.id == "vehicle/5:3" and (change.before, change.after) == ("permitted", "forbidden")


def test_a_monitor_rule_removed_and_one_added_make_incidents_vanish_and_appear(db, tmp_path):
    new = R.edited(tmp_path, "monitors.le", cut=(R.RED_CROSSED, R.RED_SNAPSHOT), add=R.GREEN_RULE)
    result = _run(db, [new])
    (gone,) = _changes(result, "gone")
    (new_one,) = _changes(result, "new")
    (flipped,) = _changes(result, "verdict")
    assert gone[0].vehicle == "9" and gone[1].before.startswith("punishable HC 176") and gone[1].after is None
    assert "no longer has the rule" in gone[1].reasons[0] and "has red light" in gone[1].reasons[0]
    assert new_one[0].vehicle == "11" and new_one[1].before is None and new_one[1].after.startswith("mitigated")
    assert new_one[1].rules[0].kind == "added" and "has green light" in new_one[1].rules[0].new.text
    # the recorded potential violation of 7 stays, but the monitor rules no longer derive it
    assert flipped[0].vehicle == "7" and (flipped[1].before, flipped[1].after) == ("punishable", "dismissed")


def test_a_changed_fine_changes_the_penalty_and_cites_the_penalty_rule(db, tmp_path):
    new = R.edited(tmp_path, "penalties.le", old="traffic light offence carries a fixed penalty of 100 pounds",
                   new="traffic light offence carries a fixed penalty of 200 pounds")
    result = _run(db, [new])
    changes = _changes(result)
    assert {c.vehicle for c, _ in changes} == {"7", "9"} and {ch.kind for _, ch in changes} == {"penalty"}
    change = changes[0][1]
    assert change.before.startswith("£100") and change.after.startswith("£200")
    assert change.rules[0].kind == "changed" and "200 pounds" in change.rules[0].new.text


def test_a_highway_code_change_changes_the_decision_not_the_verdicts(db, tmp_path):
    new = R.edited(tmp_path, "highway_code.le", cut=(R.AMBER_TOO_CLOSE,))
    result = _run(db, [new])
    ((case, change),) = _changes(result)
    assert change.kind == "decision" and case.action == "5 can enter the junction"
    assert (change.before, change.after) == ("permitted", "forbidden")
    assert "highway_code.le:" in change.reasons[0] and change.rules[0].label == "HC 175"


def test_an_explicit_baseline_gives_the_rule_change_report_with_what_each_rule_flipped(db, tmp_path):
    old = R.edited(tmp_path / "old", "validators.le")
    new = R.edited(tmp_path / "new", "validators.le", cut=(R.AMBER_TOO_CLOSE,))
    result = _run(db, [new], baseline=[old])
    (diff,) = [d for d in result.diffs if "validator" in d.stages]
    (rule,) = diff.changes
    assert rule.kind == "removed" and rule.old.book == str(old)
    # with OLD given, validators.le answers the vehicle stage on both sides: one diff, two stages
    assert sorted(diff.stages) == ["validator", "vehicle"]
    assert sorted((c.vehicle, ch.kind) for c, ch in result.flipped_by(rule)) == [("5", "decision"), ("5", "verdict")]


def test_a_rulebook_no_stage_uses_is_an_error(db, tmp_path):
    useless = tmp_path / "useless.le"
    useless.write_text("the target language is: prolog.\n\nthe templates are:\n*a vehicle* is shiny.\n\n"
                       "the knowledge base k includes:\na vehicle is shiny if\n    the vehicle is shiny.\n")
    with pytest.raises(RegressError, match="used by no stage: it defines none of the stages' sentences"):
        _run(db, [useless])
    copy = R.edited(tmp_path / "copy", "penalties.le", old="100 pounds", new="90 pounds")
    with pytest.raises(RegressError, match="answered by rulebooks given before it: penalties by"):
        _run(db, ["reasoner/rules/penalties.le", copy])


def test_an_unknown_run_is_named(db):
    with Store.open_read_only(db) as store, pytest.raises(NoSuchRun):
        regress(store, ["reasoner/rules/validators.le"], runs=["nope"])


def test_a_rule_that_only_moved_is_not_a_change():
    engine = get_engine()
    old = engine.load(bundled("penalties.le"), "penalties.le")
    moved = bundled("penalties.le").replace("the knowledge base", "\n\nthe knowledge base", 1)
    assert diff_rulebooks(old, engine.load(moved, "moved.le")).changes == ()
