"""`gaps`: look at what was recorded, judge it, explain it.

Each `cli/<topic>.py` module registers its commands on the app from `cli/app.py`.
"""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional

import typer

from cli.app import DbOption, JsonOption, RunOption, app, db_path, fail, open_existing, print_json

@app.command()
def demo(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
         report: Optional[Path] = typer.Option(
             None, "--report", help="Where to write the HTML report (default: gaps-report.html beside the store; "
                                    ".md or .json by suffix).")) -> None:
    """Replay the paper's two junction scenarios over Zenoh into the store, explain the verdicts and
    write the HTML report."""
    from cli.demo import demo_events, publish_through_zenoh, write_report
    path = db_path(db)
    events = demo_events()
    totals = publish_through_zenoh(path, events)
    run = events[0]["run"]
    if not json_out:
        typer.echo(f"Published {len(events)} events of run {run} over Zenoh; stored {totals['stored']}, "
                   f"duplicates {totals['duplicates']}, rejected {totals['rejected']} → {path}\n")
    _report(path, [run], json_out)
    target = report or path.parent / "gaps-report.html"
    try:
        written = write_report(path, run, target)
    except (OSError, ValueError) as exc:
        fail(f"cannot write the report to {target}: {exc}")
    typer.echo(f"Report of run {run}: {written.resolve()} (open it in a browser; `gaps report --run {run} -o FILE --pdf` "
               "prints a PDF)", err=json_out)


@app.command()
def incidents(run: Optional[str] = RunOption, db: Optional[Path] = DbOption,
              json_out: bool = JsonOption,
              rules: Optional[list[Path]] = typer.Option(
                  None, "--rules", help="Judge with this LE rulebook first (repeatable); a stage it does not "
                                        "define keeps the run's own or the current rulebook."),
              vehicle: Optional[str] = typer.Option(None, "--vehicle", help="Only this vehicle's incidents.")) -> None:
    """Every potential violation of a run, validated: punishable, mitigated or dismissed."""
    for path in rules or []:
        if not path.is_file():
            fail(f"no such rulebook file: {path}")
    with open_existing(db) as store:
        known = runs_of(store)
    if run and run not in known:
        fail(f"no run {run!r} in {db_path(db)}; runs: {', '.join(known) or 'none'}")
    _report(db_path(db), [run] if run else known, json_out, [str(p) for p in rules or []], vehicle)


def runs_of(store) -> list[str]:
    return [r["run"] for r in store.runs()]


def _report(path: Path, runs: list[str], json_out: bool, rules: Optional[list[str]] = None,
            vehicle: Optional[str] = None) -> None:
    from cli.progress import stderr_progress
    from explain import explain_incident
    from explain.evidence import chain_status
    from reasoner.investigation import Investigation
    from store import Store
    with Store.open_read_only(path) as store:
        inv = Investigation(store, rules=rules)
        with stderr_progress("judging incidents") as progress:      # the bar is gone before printing
            found = [inc for r in runs for inc in inv.incidents(r, progress)
                     if vehicle is None or inc["vehicle"] == vehicle]
        if json_out:
            print_json([{k: v for k, v in inc.items() if k not in ("proofs", "scenarios")} for inc in found])
            return
        if not found:
            typer.echo("No potential violations recorded" + (f" for vehicle {vehicle}." if vehicle else "."))
        chains = {r: chain_status(store, r) for r in {inc["run"] for inc in found}}
        for n, inc in enumerate(found, 1):
            typer.echo(f"── incident {n}: {inc['run']} {inc['id']} ──")
            typer.echo(explain_incident(inc, inv.rulebook, store, chain=chains[inc["run"]]) + "\n")


from cli import explain  # noqa: E402,F401  (gaps explain --run R INCIDENT)
from cli import ledger  # noqa: E402,F401  (registers its commands after the ones above)
from cli import migrate  # noqa: E402,F401  (gaps migrate SRC DST)
from cli import report  # noqa: E402,F401  (gaps report --run R -o FILE)
from cli import rules  # noqa: E402,F401  (gaps rules check|query|prolog|verify)
from cli import scene  # noqa: E402,F401  (gaps scene --run R --at T)
from cli import transfer  # noqa: E402,F401  (gaps import / gaps export)


def main() -> None:
    from reasoner.le.errors import LEError
    from reasoner.prolog_home import PrologUnavailable
    try:
        app()
    except KeyboardInterrupt:
        sys.exit(130)
    except PrologUnavailable as exc:      # a set-up problem, not a bug: say how to fix it
        typer.echo(f"gaps: {exc}", err=True)
        sys.exit(3)
    except LEError as exc:                # a rulebook that does not compile
        typer.echo(f"gaps: rulebook error: {exc}", err=True)
        sys.exit(2)
