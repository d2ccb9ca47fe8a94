"""The `gaps` Typer app: how every command reports a mistake, opens the store and prints JSON.

Heavy imports (Zenoh, SWI-Prolog) happen inside the commands that need them, so `gaps --help`
and the store-only commands start fast. A command raises a `GapsError` (store/errors.py) for a
user's mistake; `GapsGroup` turns it into one line on stderr and the error's exit code, so no
command repeats that and no traceback reaches the user.
"""
from __future__ import annotations

import json
import os
import sqlite3
from pathlib import Path
from typing import Any, NoReturn, Optional

import typer
from typer.core import TyperGroup

from store import GapsError, NoSuchRun, Store, StoreError

HELP = "mind-the-gaps: forensic audit of traffic-rule compliance."
CONTEXT = {"help_option_names": ["-h", "--help"]}


class GapsGroup(TyperGroup):
    """The command group that reports a GapsError as `gaps: <message>` with its exit code."""

    def invoke(self, ctx: typer.Context) -> Any:
        from store import caches_opened, unwritten_caches
        already, opened = len(unwritten_caches()), caches_opened()
        try:
            return super().invoke(ctx)
        except GapsError as exc:
            typer.echo(f"gaps: {_what(exc)}{exc}", err=True)
            raise typer.Exit(exc.exit_code) from None
        except sqlite3.DatabaseError as exc:  # a damaged or hostile file, read past the store's own checks
            from store import damaged_caches
            damaged = damaged_caches(since=opened)
            if damaged:     # derived data never accuses the evidence
                typer.echo(f"gaps: SQLite could not read the cache file {damaged[0]}: {exc}; it holds only what "
                           "reads derived from the store, never evidence: delete it and run again (it is rebuilt "
                           "from the events)", err=True)
                raise typer.Exit(2) from None
            typer.echo(f"gaps: SQLite could not read the store: {exc}{_DAMAGE_HINT}", err=True)
            raise typer.Exit(1) from None
        finally:
            for why in unwritten_caches()[already:]:
                typer.echo(f"gaps: warning: the cache could not be written ({why}); the results were computed "
                           "from the store without it (the evidence is not in question)", err=True)


_DAMAGE_HINT = "; the file may be damaged or altered: `gaps verify` says what and where"


def _what(exc: GapsError) -> str:
    """A rulebook's error is said to be one: its message starts with the rulebook's file:line."""
    from reasoner.le.errors import LEError
    return "rulebook error: " if isinstance(exc, LEError) else ""


def new_app(help: str = HELP) -> typer.Typer:
    """An empty `gaps` app (or command group) with -h, shell completion and the error handling."""
    return typer.Typer(cls=GapsGroup, help=help, no_args_is_help=True, context_settings=CONTEXT,
                       rich_markup_mode="markdown",
                       pretty_exceptions_enable=False)


def db_path(db: Optional[Path]) -> Path:
    return Path(db or os.environ.get("GAPS_DB") or "gaps.db")


def open_existing(db: Optional[Path]) -> Store:
    """Open a store that must already exist, read-only: a read command never creates one by
    mistake, and never changes the file it reads (docs/store.md)."""
    path = db_path(db)
    if not path.is_file():
        fail(f"no event store at {path} (run `gaps demo` or pass --db)")
    try:
        return Store.open_read_only(path)
    except StoreError as exc:  # not an event store, an older or newer schema, unreadable
        fail(str(exc), exc.exit_code)


def writable_output(path: Optional[Path], db: Optional[Path] = None) -> None:
    """Refuse, before any work, an output file that is or resolves to the store (`db`), one of its
    companions or any SQLite file, or that is not a regular file (store/output_files.py: OutputRefused,
    exit 2). `-` and None pass: standard output, or no file asked for."""
    from store import check_output
    if path is not None and str(path) != "-":
        check_output(path, [db_path(db)])


def require_run(store: Store, run: Optional[str]) -> None:
    """The one check of a --run value: NoSuchRun ("no run 'x'; runs: a, b", exit 2) for a run
    the store does not hold; None (every run) passes."""
    if run is None:
        return
    known = [r.run for r in store.runs()]
    if run not in known:
        raise NoSuchRun(run, known)


def check_files(paths: Optional[list[Path]], what: str = "rulebook file") -> list[str]:
    """The paths as strings, after checking each names a file (exit 2 naming the first that does not)."""
    for path in paths or []:
        if not path.is_file():
            fail(f"no such {what}: {path}")
    return [str(p) for p in paths or []]


def fail(message: str, code: int = 2) -> NoReturn:
    typer.echo(f"gaps: {message}", err=True)
    raise typer.Exit(code)


def print_json(data: Any) -> None:
    typer.echo(json.dumps(data, indent=2, ensure_ascii=False, default=str))
