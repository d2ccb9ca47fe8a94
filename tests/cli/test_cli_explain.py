"""`gaps explain --run R INCIDENT`: by id or number, every format and level, why-not on request,
one-line errors with exit code 2 for what names nothing."""
import json

import pytest

from sim_replay.paper import RUN
from tests.helpers.cli import gaps


def test_by_number_and_by_id_agree(paper_db):
    first = gaps("explain", "--run", RUN, "1", db=paper_db)
    assert first.exit_code == 0, first.output
    assert first.stdout.startswith("Vehicle 173 committed a punishable violation of Highway Code rule 176")
    assert gaps("explain", "--run", RUN, "monitor/m1:1", db=paper_db).stdout == first.stdout


@pytest.mark.parametrize("fmt, start", [("md", "# Vehicle 173"), ("html", "<!DOCTYPE html>"), ("json", "{")])
def test_formats(paper_db, fmt, start):
    result = gaps("explain", "--run", RUN, "1", "--format", fmt, "--level", "full", db=paper_db)
    assert result.exit_code == 0, result.output
    assert result.stdout.startswith(start)
    if fmt == "json":
        assert json.loads(result.stdout)["incident"]["verdict"] == "punishable"


def test_json_flag_and_why_not(paper_db):
    result = gaps("explain", "--run", RUN, "2", "--json", "--why-not", "253 can enter the junction", db=paper_db)
    doc = json.loads(result.stdout)
    assert doc["incident"]["vehicle"] == "253"
    assert [w["question"] for w in doc["why_not"]] == ["253 can enter the junction"]
    assert doc["why_not"][0]["holds"] is True


@pytest.mark.parametrize("args, message", [
    (["--run", RUN, "9"], "no incident '9' in run 'paper-junctions'; incidents: 1=monitor/m1:1, 2=monitor/m1:3"),
    (["--run", "nope", "1"], "no run 'nope'"),
    (["--run", RUN, "1", "--format", "pdf"], "unknown format 'pdf'"),
    (["--run", RUN, "1", "--level", "loud"], "unknown level 'loud'"),
])
def test_errors(paper_db, args, message):
    result = gaps("explain", *args, db=paper_db)
    assert result.exit_code == 2 and message in result.output
    assert len(result.output.strip().splitlines()) == 1
