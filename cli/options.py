"""The options and arguments several commands share, declared once so they read alike everywhere."""
from __future__ import annotations

import typer

from cli import completion

DbOption = typer.Option(None, "--db", help="SQLite event store (default: $GAPS_DB or ./gaps.db).")
JsonOption = typer.Option(False, "--json", help="Print JSON instead of text.")
RunOption = typer.Option(None, "--run", help="Run id (default: every run).", autocompletion=completion.runs)
RunRequired = typer.Option(..., "--run", help="Run id.", autocompletion=completion.runs)
RulesOption = typer.Option(None, "--rules", metavar="FILE.le…", help="Judge with this LE rulebook first (repeatable).")
ZenohConfigOption = typer.Option(None, "--config", metavar="FILE", help="A Zenoh config file (JSON5: TLS with the "
                                 "producer's certificate, user/password; docs/serve.md \"A hardened deployment\"); "
                                 "--listen/--connect given here are written over it.")
InsecureOption = typer.Option(False, "--insecure-beyond-loopback", help="Publish even though this producer can be "
                              "reached beyond loopback without Zenoh authentication in --config (logged).")
IncidentHelp = "Incident id (monitor/m1:3) or its number in `gaps incidents` order (1, 2, ...)."

STDIO = "-"


def is_stdio(path: object) -> bool:
    """Whether a file argument is `-`: standard input or output rather than a file."""
    return str(path) == STDIO
