"""Help a person can read (issue 39): real placeholders instead of Python types (`--json <bool>`,
`--rules <list[Path]>`), a plain usage line, `--faults` not cut, and `gaps help [COMMAND]`."""
from __future__ import annotations

import re

import pytest
import typer

from cli.main import app
from tests.helpers.cli import gaps


def _commands() -> list[tuple[str, ...]]:
    group = typer.main.get_command(app)
    found = []
    for name, command in group.commands.items():
        found.append((name,))
        for sub in getattr(command, "commands", {}):
            found.append((name, sub))
    return found


PYTHON_TYPES = re.compile(r"<(bool|str|int|float|path|list\[[^\]]*\]|[a-z]+ range)>|\[\[")


@pytest.mark.parametrize("command", [(), *_commands()], ids=lambda c: " ".join(c) or "gaps")
def test_help_shows_placeholders_not_python_types(command):
    shown = gaps(*command, "--help", columns=100)
    assert shown.exit_code == 0, shown.output
    assert not PYTHON_TYPES.search(shown.stdout), PYTHON_TYPES.search(shown.stdout)[0] + "\n" + shown.stdout


def test_the_issue_s_placeholders():
    incidents = gaps("incidents", "--help", columns=120).stdout
    assert re.search(r"--json\s+Print JSON", incidents), incidents
    assert re.search(r"--rules\s+FILE\.le…", incidents), incidents
    assert re.search(r"--run\s+RUN\b", incidents)
    sim = gaps("sim", "--help", columns=100).stdout
    assert re.search(r"--faults\s+NAME=RATE,…", sim), sim
    regress = gaps("regress", "--help", columns=100).stdout
    assert "[FILES.mcap]..." in regress and "[[" not in regress


def test_faults_help_is_not_cut_at_80_columns():
    sim = gaps("sim", "--help", columns=80).stdout
    block = sim[sim.index("--faults"):sim.index("--run ")]
    assert "…" not in block.replace("NAME=RATE,…", ""), block


def test_gaps_help_is_gaps_dash_dash_help():
    assert gaps("help").stdout == gaps("--help").stdout


@pytest.mark.parametrize("command", [("incidents",), ("rules", "check"), ("keys",)])
def test_gaps_help_command_is_its_help(command):
    asked = gaps("help", *command)
    assert asked.exit_code == 0, asked.output
    assert asked.stdout == gaps(*command, "--help").stdout


def test_gaps_help_of_an_unknown_command_says_which_there_are():
    asked = gaps("help", "incidnets")
    assert asked.exit_code == 2
    assert "no command 'incidnets'" in asked.stderr and "incidents" in asked.stderr


@pytest.mark.parametrize("command, said", [(("keys", "new"), "FOLDER/ROLE/ID.key"), (("serve",), "gaps/@heads/RUN")])
def test_help_text_is_not_eaten_as_markup(command, said):
    """Help is rendered as Markdown: a `<run>` in it vanished as an HTML tag ("gaps/@heads/;")."""
    assert said in gaps(*command, "--help", columns=200).stdout
