"""`gaps incidents` lines a reader can use (issue 39): `None` printed in the rule column of a
dismissed incident; on a store of two runs, lines without their run, both numbered 1; the number
`gaps explain --run R N` takes missing from `--json`."""
from __future__ import annotations

import dataclasses
import json

import pytest

from explain.listing import incident_line
from reasoner.api import Case
from sim_replay.paper import RUN, paper_run
from store import Store
from tests.helpers.cli import gaps


@pytest.fixture(scope="module")
def two_runs(tmp_path_factory):
    path = tmp_path_factory.mktemp("lines") / "gaps.db"
    with Store(path) as store:
        store.append(paper_run(RUN))
        store.append(paper_run("paper-again"))
    return path


def test_without_run_each_run_heads_its_own_numbered_lines(two_runs):
    out = gaps("incidents", db=two_runs).stdout
    lines = out.splitlines()
    heads = [i for i, line in enumerate(lines) if line.startswith("run ")]
    assert [lines[i].split()[1] for i in heads] == ["paper-again", RUN], out
    first, second = lines[heads[0] + 1:heads[1]], lines[heads[1] + 1:]
    assert [line.split()[0] for line in first] == ["1", "2"] and [line.split()[0] for line in second] == ["1", "2"]
    assert "gaps explain --run paper-again N" in lines[heads[0]]


def test_one_run_needs_no_heading(two_runs):
    out = gaps("incidents", "--run", RUN, db=two_runs).stdout
    assert not any(line.startswith("run ") for line in out.splitlines()), out


def test_json_carries_the_number_explain_takes(two_runs):
    listed = json.loads(gaps("incidents", "--json", db=two_runs).stdout)
    assert [(i["run"], i["number"]) for i in listed] == [("paper-again", 1), ("paper-again", 2), (RUN, 1), (RUN, 2)]
    second = listed[1]
    explained = json.loads(gaps("explain", "--run", "paper-again", str(second["number"]), "--format", "json",
                                db=two_runs).stdout)
    assert explained["incident"]["id"] == second["id"]


def test_an_incident_without_a_rule_says_so_not_none(two_runs):
    with Case(Store.open_read_only(two_runs)) as case:
        inc = case.incidents(RUN)[0]
    line = incident_line(dataclasses.replace(inc, rule=None), 1)
    assert "None" not in line and "no rule" in line, line
