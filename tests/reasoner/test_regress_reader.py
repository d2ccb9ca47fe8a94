"""A regression reports only changes a reader can see, and its JUnit cases carry times (issue 39:
raising the traffic-light fine reported, for an incident whose self-driving entity is liable,
"penalty changed: no fixed penalty + 0 points → no fixed penalty + 0 points", counted among the
changes and written as a JUnit failure; `gaps regress --junit` had no `time` attributes)."""
from __future__ import annotations

import dataclasses
import xml.etree.ElementTree as ET

import pytest

from reasoner.engine import get_engine
from reasoner.regress import Regressor, regress
from reasoner.regress.books import load_given
from reasoner.regress.junit import junit_xml
from store import Store
from tests.reasoner import regress_runs as R


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    return R.build_store(tmp_path_factory.mktemp("regress-reader") / "gaps.db")


def test_a_penalty_that_reads_the_same_is_no_change(db):
    engine = get_engine()
    with Store.open_read_only(db) as store:
        regressor = Regressor(store, engine, load_given(engine, ["reasoner/rules/penalties.le"], "--rules"), None)
        (punished,) = [i for i in regressor.before.incidents(R.RUN) if i.vehicle == "7"]
        # the self-driving entity is offered no fixed penalty, whatever the law sets for the offence
        offered = dataclasses.replace(punished.penalty, fine_gbp=None, points=0, fine_gbp_by_law=100)
        before = dataclasses.replace(punished, penalty=offered, liable="authorised self-driving entity")
        after = dataclasses.replace(before, penalty=dataclasses.replace(offered, fine_gbp_by_law=200))
        assert regressor._incident(R.RUN, before, after, {}).changes == ()
        # what a reader does see is still a change
        seen = dataclasses.replace(before, penalty=dataclasses.replace(offered, points=3))
        assert [c.kind for c in regressor._incident(R.RUN, before, seen, {}).changes] == ["penalty"]


def test_every_junit_case_and_suite_carries_a_time(db, tmp_path):
    new = R.edited(tmp_path, "penalties.le", old="traffic light offence carries a fixed penalty of 100 pounds",
                   new="traffic light offence carries a fixed penalty of 200 pounds")
    with Store.open_read_only(db) as store:
        result = regress(store, [str(new)], None, [R.RUN])
    root = ET.fromstring(junit_xml(result))
    suites, cases = root.findall("testsuite"), root.findall(".//testcase")
    assert suites and cases
    for element in [root, *suites, *cases]:
        assert float(element.get("time")) >= 0, ET.tostring(element)[:200]
    assert float(root.get("time")) > 0
    assert abs(sum(float(s.get("time")) for s in suites) - float(root.get("time"))) < 0.01


def test_a_golden_run_names_each_hash_with_its_own_rulebook():
    """A golden-run message labelled highway_code.le's approved hash as validators.le (the name the
    stage has now), when validators.le came to answer the vehicle stage."""
    from reasoner.regress.golden import _why
    approved = {"vehicle": {"name": "highway_code.le", "sha256": "a" * 64}}
    now = {"vehicle": {"name": "validators.le", "sha256": "b" * 64}}
    said = _why(approved, now)[0]
    assert "vehicle: highway_code.le aaaaaaaaaaaa -> validators.le bbbbbbbbbbbb" in said, said
    same_book = _why({"vehicle": {"name": "validators.le", "sha256": "a" * 64}}, now)[0]
    assert "vehicle: validators.le aaaaaaaaaaaa -> bbbbbbbbbbbb" in same_book, same_book
