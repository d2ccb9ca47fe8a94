"""Running `gaps` in-process for the command-line tests, as a user would type it."""
from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner, Result

from cli.main import app

HOSTILE_RAW = b'{"v": 1, "run": "\x1b[31mred[bold]big[/bold]\xff\xfe'   # escapes, markup, not UTF-8
HOSTILE_ORIGIN = "zenoh:gaps/\x1b]0;owned\x07"


def gaps(*args: str, db: Path | None, columns: int = 200, input: bytes | str | None = None) -> Result:
    """`gaps ARGS --db DB` (no --db for None) with the terminal `columns` wide; no traceback may
    reach the user."""
    line = [*args, "--db", str(db)] if db is not None else list(args)
    result = CliRunner().invoke(app, line, env={"COLUMNS": str(columns)}, input=input)
    assert "Traceback" not in result.output
    return result
