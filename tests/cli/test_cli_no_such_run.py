"""A run id that names nothing is one message in every command: "no run 'typo'; runs: ...", exit 2."""
import pytest

from tests.helpers.cli import gaps

SAYS = "gaps: no run 'typo'; runs: r1, r2\n"


@pytest.mark.parametrize("args", [
    ["verify", "--run", "typo"],
    ["verify", "--run", "typo", "--json"],
    ["incidents", "--run", "typo"],
    ["incidents", "--run", "typo", "--json"],
    ["explain", "--run", "typo", "1"],
    ["scene", "--run", "typo", "--at", "1s"],
    ["report", "--run", "typo", "-o", "-"],
    ["export", "--run", "typo", "-o", "-"],
    ["export", "--run", "typo", "-o", "run.jsonl"],
])
def test_every_command_names_the_runs_there_are(db, args, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    result = gaps(*args, db=db)
    assert (result.exit_code, result.stderr, result.stdout) == (2, SAYS, "")
    assert not (tmp_path / "run.jsonl").exists()
