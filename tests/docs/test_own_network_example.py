"""docs/simulation.md "Your own network" runs as written: each `$ command` of its session is run in a
fresh folder (`gaps` in this process, as tests/helpers/cli.py runs it, to save its start-up; the
others in a shell with SUMO's `netgenerate` first on PATH), and prints what the page shows (`…` stands for any text: timings and counts that vary). A `$ cat FILE` shows
a file the reader writes, so the test writes it as shown; a command the page shows answering
`gaps: ...` must fail with exit 2 (README: a user's mistake) and say that on standard error."""
from __future__ import annotations

import os
import re
import shlex
import subprocess
from pathlib import Path

import pytest

from tests.helpers.cli import gaps
from tests.helpers.sumo_tools import sumo_tool

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "simulation.md"
SECTION = "## Your own network"


def session(text: str) -> list[tuple[str, list[str]]]:
    """The (command, expected output lines) of the section's first ```text block."""
    body = text.split(SECTION, 1)[1].split("\n## ", 1)[0]
    block = re.split(r"```text[^\n]*\n", body, maxsplit=1)[1].split("\n```", 1)[0]
    steps: list[tuple[str, list[str]]] = []
    for line in block.splitlines():
        if line.startswith("$ "):
            steps.append((line[2:], []))
        else:
            assert steps, f"{PAGE}: output before any command in {SECTION!r}"
            steps[-1][1].append(line)
    return steps


def _matches(expected: list[str], got: list[str]) -> bool:
    if len(expected) != len(got):
        return False
    return all(re.fullmatch(".*?".join(re.escape(part) for part in want.split("…")), line)
               for want, line in zip(expected, got))


def test_the_section_has_a_session_to_run():
    steps = session(PAGE.read_text(encoding="utf-8"))
    commands = [c.split()[0] for c, _ in steps]
    assert commands.count("gaps") >= 3 and "netgenerate" in commands


def test_your_own_network_runs_as_the_page_shows(tmp_path, monkeypatch):
    if sumo_tool("netgenerate") is None:
        pytest.skip("netgenerate is not installed (the eclipse-sumo wheel)")
    env = {**os.environ, "PATH": os.pathsep.join([str(Path(sumo_tool("netgenerate")).parent),
                                                   os.environ.get("PATH", "")])}
    monkeypatch.chdir(tmp_path)
    monkeypatch.delenv("GAPS_DB", raising=False)
    for command, expected in session(PAGE.read_text(encoding="utf-8")):
        words = shlex.split(command)
        if words[0] == "cat":
            (tmp_path / words[1]).write_text("\n".join(expected) + "\n")
        if words[0] == "gaps":
            result = gaps(*words[1:])
            code, out, err = result.exit_code, result.stdout, result.stderr
        else:
            done = subprocess.run(words, cwd=tmp_path, env=env, capture_output=True, text=True, timeout=60)
            code, out, err = done.returncode, done.stdout, done.stderr
        refused = bool(expected) and expected[0].startswith("gaps: ")
        assert code == (2 if refused else 0), f"$ {command}\n{out}{err}"
        got = (err if refused else out).splitlines()
        assert _matches(expected, got), f"$ {command}\nthe page shows:\n" + "\n".join(expected) + \
            "\nit printed:\n" + "\n".join(got)
