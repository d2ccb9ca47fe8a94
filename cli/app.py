"""The `gaps` Typer app and what every command shares: --db, --json, errors, JSON output.

Heavy imports (Zenoh, SWI-Prolog) happen inside the commands that need them, so `gaps --help`
and the store-only commands start fast.
"""
from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Optional

import typer

app = typer.Typer(help="mind-the-gaps: forensic audit of traffic-rule compliance.",
                  no_args_is_help=True, add_completion=False, pretty_exceptions_enable=False)

DbOption = typer.Option(None, "--db", help="SQLite event store (default: $GAPS_DB or ./gaps.db).")
JsonOption = typer.Option(False, "--json", help="Print JSON instead of text.")
RunOption = typer.Option(None, "--run", help="Run id (default: every run).")


def db_path(db: Optional[Path]) -> Path:
    return Path(db or os.environ.get("GAPS_DB") or "gaps.db")


def open_existing(db: Optional[Path]):
    """Open a store that must already exist, read-only: a read command never creates one by
    mistake, and never changes the file it reads (docs/store.md)."""
    from store import Store, StoreError
    path = db_path(db)
    if not path.is_file():
        fail(f"no event store at {path} (run `gaps demo` or pass --db)")
    try:
        return Store.open_read_only(path)
    except StoreError as exc:  # not an event store, an older or newer schema, unreadable
        fail(str(exc), exc.exit_code)


def fail(message: str, code: int = 2) -> None:
    typer.echo(f"gaps: {message}", err=True)
    raise typer.Exit(code)


def print_json(data) -> None:
    typer.echo(json.dumps(data, indent=2, ensure_ascii=False, default=str))


