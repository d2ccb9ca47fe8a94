"""Running `gaps` in-process for the command-line tests, as a user would type it."""
from __future__ import annotations

from pathlib import Path

from typer.testing import CliRunner, Result

from cli.main import app

HOSTILE_RAW = b'{"v": 1, "run": "\x1b[31mred[bold]big[/bold]\xff\xfe'   # escapes, markup, not UTF-8
HOSTILE_ORIGIN = "zenoh:gaps/\x1b]0;owned\x07"


def gaps(*args: object, db: Path | None = None, columns: int = 200, input: bytes | str | None = None) -> Result:
    """`gaps ARGS --db DB` (no --db for None) with the terminal `columns` wide; no traceback may
    reach the user, and nothing but a deliberate exit may end the command."""
    line = [str(a) for a in args] + (["--db", str(db)] if db is not None else [])
    result = CliRunner().invoke(app, line, env={"COLUMNS": str(columns)}, input=input)
    assert "Traceback" not in result.output
    assert result.exception is None or isinstance(result.exception, SystemExit), result.exception
    return result
