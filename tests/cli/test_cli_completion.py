"""Shell completion of run names and incident numbers (issue 39), reading the store without
writing anything: not the store, not a cache beside it."""
from __future__ import annotations

import hashlib

import pytest
from typer.testing import CliRunner

from cli.main import app
from sim_replay.paper import RUN, paper_run
from store import Store


def complete(line: str, db) -> list[str]:
    """What bash is offered for the last word of `line` (typer's own completion protocol)."""
    words = line.split(" ")
    env = {"_GAPS_COMPLETE": "complete_bash", "COMP_WORDS": line, "COMP_CWORD": str(len(words) - 1),
           "GAPS_DB": str(db)}
    result = CliRunner().invoke(app, [], env=env, prog_name="gaps")
    assert result.exit_code == 0 and "Traceback" not in result.output, result.output
    return result.stdout.split()


def snapshot(folder) -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.iterdir())}


@pytest.fixture
def two_runs(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append(paper_run(RUN))
        store.append(paper_run("paper-again"))
    return path


def test_run_names_complete_and_nothing_is_written(two_runs):
    before = snapshot(two_runs.parent)
    assert complete("gaps incidents --run ", two_runs) == ["paper-again", "paper-junctions"]
    assert complete("gaps scene --run paper-j", two_runs) == ["paper-junctions"]
    assert complete(f"gaps runs --db {two_runs} --run", two_runs) == []      # runs takes no --run
    assert snapshot(two_runs.parent) == before


def test_incident_numbers_complete_for_the_run_typed_and_nothing_is_written(two_runs):
    before = snapshot(two_runs.parent)
    assert complete(f"gaps explain --run {RUN} ", two_runs) == ["1", "2"]
    assert complete(f"gaps explain --run {RUN} 2", two_runs) == ["2"]
    assert complete("gaps explain ", two_runs) == []                          # no run typed yet
    assert snapshot(two_runs.parent) == before, "completion wrote beside the store"


def test_no_store_completes_nothing(tmp_path):
    assert complete("gaps incidents --run ", tmp_path / "none.db") == []
    (tmp_path / "not.db").write_text("not a store")
    assert complete("gaps incidents --run ", tmp_path / "not.db") == []
