"""`gaps`: look at what was recorded, judge it, explain it.

The app is built here, explicitly: each `cli/<command>.py` module holds its command as a plain
function and this module lists them in the order `gaps --help` shows them. A new command is a
new module and one line below.
"""
from __future__ import annotations

import signal
import sys
from typing import Optional

import typer

from cli import (demo, explain, fetch, help, incidents, keys, migrate, quarantine, regress, replay, report, rules, runs,
                 scene, serve, sim, transfer, verify)
from cli.app import new_app


def build() -> typer.Typer:
    """The `gaps` app with every command and group registered."""
    app = new_app()
    app.callback()(_version_option)
    app.command()(demo.demo)
    app.command()(sim.sim)
    app.command()(replay.replay)
    app.command()(serve.serve)
    app.command()(runs.runs)
    app.command()(scene.scene)
    app.command()(incidents.incidents)
    app.command()(explain.explain)
    app.command()(report.report)
    app.command()(regress.regress)
    app.command()(verify.verify)
    app.command()(quarantine.quarantine)
    app.command("import")(transfer.import_)
    app.command()(transfer.export)
    app.command()(fetch.fetch)
    app.command()(migrate.migrate)
    app.add_typer(_rules_group(), name="rules")
    app.add_typer(_keys_group(), name="keys")
    app.command("help")(help.help_)
    return app


def _rules_group() -> typer.Typer:
    group = new_app(help=rules.HELP)
    for command in (rules.check, rules.query, rules.prolog, rules.verify):
        group.command()(command)
    return group


def _keys_group() -> typer.Typer:
    group = new_app(help=keys.HELP)
    group.command()(keys.new)
    group.command()(keys.public)
    group.command()(keys.checkpoint)
    return group


def _print_version(asked: bool) -> None:
    if asked:
        from explain import tool_version
        typer.echo(f"gaps (mind-the-gaps) {tool_version()}")
        raise typer.Exit(0)


def _version_option(version: Optional[bool] = typer.Option(
        None, "--version", "-V", is_eager=True, expose_value=True, callback=_print_version,
        help="Print the version of gaps and exit.")) -> None:
    """mind-the-gaps: forensic audit of traffic-rule compliance."""


app = build()


class Terminated(BaseException):
    """SIGTERM, raised wherever the command is (not an Exception: nothing catches it on the way),
    so that it unwinds as Ctrl-C does: every `with` closes, and the temporary stores a regression
    or a replay imports recordings into are deleted, not left behind (some 7 GB for an hour's
    recording) by the default action, which ends the process where it stands."""


def _terminated(signum: int, frame: object) -> None:
    raise Terminated()


def main() -> None:
    """Run `gaps`; every GapsError is already a message and an exit code (cli.app.GapsGroup).
    Ctrl-C exits 130 and SIGTERM 143 (128 + the signal), each after unwinding; `gaps serve`
    handles both itself (it stores what it received first)."""
    signal.signal(signal.SIGTERM, _terminated)
    try:
        app()
    except KeyboardInterrupt:
        sys.exit(130)
    except Terminated:
        print("gaps: stopped by SIGTERM", file=sys.stderr)
        sys.exit(143)

if __name__ == "__main__":
    main()
