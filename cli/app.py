"""The `gaps` Typer app: how every command reports a mistake, opens the store and prints JSON.

Heavy imports (Zenoh, SWI-Prolog) happen inside the commands that need them, so `gaps --help`
and the store-only commands start fast. A command raises a `GapsError` (store/errors.py) for a
user's mistake; `GapsGroup` turns it into one line on stderr and the error's exit code, so no
command repeats that and no traceback reaches the user.
"""
from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any, NoReturn, Optional, get_args

import typer
from typer.core import TyperGroup

from store import GapsError, NoSuchRun, Store, StoreError, StoreFault, translating

HELP = "mind-the-gaps: forensic audit of traffic-rule compliance."
CONTEXT = {"help_option_names": ["-h", "--help"]}


class GapsGroup(TyperGroup):
    """The command group that reports a GapsError as `gaps: <message>` with its exit code, and
    goes on without a cache file it cannot read (derived data never stops a command). Its help
    shows placeholders a person reads (FILE, N, RUN), never Python's types."""

    def __init__(self, **attrs: Any) -> None:
        super().__init__(**attrs)
        for command in (self, *self.commands.values()):
            for param in command.params:
                name_placeholder(param)
            _flag_help_option(command)

    def get_params(self, ctx: Any) -> list:
        """Its own options, with those typer adds after it is made (--install-completion) named too."""
        params = super().get_params(ctx)
        for param in params:
            name_placeholder(param)
        return params

    def invoke(self, ctx: Any) -> Any:
        from store.cache import altered_caches, unread_caches, unwritten_caches
        already, wants_json = len(unwritten_caches()), "--json" in _command_line(ctx)
        unread_before, altered_before = len(unread_caches()), altered_caches()
        try:
            return self._invoke_without_unreadable_caches(ctx, wants_json)
        except StoreFault as exc:  # a damaged or hostile file, read past the store's own checks
            typer.echo(f"gaps: SQLite could not read the store: {exc}{_DAMAGE_HINT}", err=True)
            raise typer.Exit(1) from None
        except GapsError as exc:
            typer.echo(f"gaps: {_what(exc)}{exc}", err=True)
            raise typer.Exit(exc.exit_code) from None
        finally:
            for why in unwritten_caches()[already:]:
                _warn(wants_json, "cache_unwritten", why,
                      f"the cache could not be written ({why}); the results were computed from the store "
                      "without it (the evidence is not in question)")
            for path, why in dict(unread_caches()[unread_before:]).items():
                _warn(wants_json, "cache_unread", f"{path}: {why}",
                      f"could not read the cache file {path} ({why}); the command went on without it, "
                      "computing from the store (it holds only what reads derived from the store, never evidence: delete it "
                      "and it is rebuilt)")
            for path, n in altered_caches().items():
                if n > altered_before.get(path, 0):
                    _warn(wants_json, "cache_altered", f"{path}: {n - altered_before.get(path, 0)} entries",
                          f"the cache file {path} held {n - altered_before.get(path, 0)} entries whose seals did not "
                          "open (altered since gaps wrote them, or damaged); they were not used: the command computed "
                          "them from the store (the cache holds only what reads derived from it, never evidence: "
                          "delete it and it is rebuilt)")

    def _invoke_without_unreadable_caches(self, ctx: typer.Context, wants_json: bool) -> Any:
        """Run the command; if SQLite fails while this command had cache files open (damaged pages,
        an I/O error), run it once more without them (store.go_without_caches): if that answers,
        the cache was at fault and a warning names it; if it fails again, the store is. SQLite's
        errors reach here as the store's own (StoreFault): `translating` is the store's net for
        those its functions let through."""
        from store.cache import caches_opened, caches_opened_since, go_without_caches
        opened, args = caches_opened(), [*ctx._protected_args, *ctx.args]
        try:
            with translating():
                return super().invoke(ctx)
        except StoreFault as exc:
            caches = caches_opened_since(opened)
            if not caches:
                raise
            why = str(exc)
        go_without_caches(caches, why)
        ctx._protected_args, ctx.args = args[:1], args[1:]
        with translating():
            return super().invoke(ctx)


def name_placeholder(param: Any) -> None:
    """Give a parameter the placeholder its help shows, where its declaration gave none: nothing
    for a flag, FILE for a path, N for a whole number, else the option's name in capitals; `…`
    after an option that may be repeated (typer would show `<bool>`, `<path>`, `<list[str]>`)."""
    if getattr(param, "is_flag", False) or getattr(param, "count", False):
        param.metavar = ""
        return
    desc = getattr(param, "type_descriptor", None)
    if param.param_type_name == "argument":     # its name column shows the placeholder: no type beside it
        param.display_type_rich = lambda ctx: None
        param.metavar = param.metavar or (param.name or "VALUE").upper()
        return
    if param.metavar is not None or desc is None or desc.is_choice:
        return
    element = get_args(desc.annotation)[0] if desc.is_list else desc.annotation
    if desc.is_path:
        name = "FILE"
    elif element is int:
        name = "N"
    else:
        longest = max(param.opts, key=len).lstrip("-") if param.param_type_name == "option" else param.name
        name = longest.upper().replace("_", "-")
    repeated = param.param_type_name == "option" and (getattr(param, "multiple", False) or desc.is_list)
    param.metavar = name + ("…" if repeated else "")


def _flag_help_option(command: Any) -> None:
    """--help, made per call, is a flag too: no placeholder beside it."""
    made = command.get_help_option

    def get_help_option(ctx: Any) -> Any:
        option = made(ctx)
        if option is not None:
            option.metavar = ""
        return option
    command.get_help_option = get_help_option


def _command_line(ctx: typer.Context) -> list[str]:
    return [*ctx._protected_args, *ctx.args]


def _warn(wants_json: bool, warning: str, why: str, text: str) -> None:
    """A warning on stderr: one line of text, or with --json one JSON object on a line of its own
    ({"warning": ..., "why": ...}), so that stdout keeps the command's documented JSON shape."""
    if wants_json:
        typer.echo(json.dumps({"warning": warning, "why": why}, ensure_ascii=False), err=True)
    else:
        typer.echo(f"gaps: warning: {text}", err=True)


_DAMAGE_HINT = "; the file may be damaged or altered: `gaps verify` says what and where"


def _what(exc: GapsError) -> str:
    """A rulebook's error is said to be one: its message starts with the rulebook's file:line."""
    from reasoner import LEError
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
