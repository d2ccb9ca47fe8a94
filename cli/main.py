"""`gaps`: look at what was recorded, judge it, explain it.

Heavy imports (Zenoh, SWI-Prolog) happen inside the commands that need them, so `gaps --help`
and the store-only commands start fast.
"""
from __future__ import annotations

import json
import os
import sys
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
    """Open a store that must already exist: a read command never creates one by mistake."""
    from store import Store
    path = db_path(db)
    if not path.is_file():
        fail(f"no event store at {path} (run `gaps demo` or pass --db)")
    return Store(path)


def fail(message: str, code: int = 2) -> None:
    typer.echo(f"gaps: {message}", err=True)
    raise typer.Exit(code)


def print_json(data) -> None:
    typer.echo(json.dumps(data, indent=2, ensure_ascii=False, default=str))


@app.command()
def demo(db: Optional[Path] = DbOption, json_out: bool = JsonOption) -> None:
    """Replay the paper's two junction scenarios over Zenoh into the store and explain the verdicts."""
    from cli.demo import demo_events, publish_through_zenoh
    path = db_path(db)
    events = demo_events()
    totals = publish_through_zenoh(path, events)
    run = events[0]["run"]
    if not json_out:
        typer.echo(f"Published {len(events)} events of run {run} over Zenoh; stored {totals['stored']}, "
                   f"duplicates {totals['duplicates']}, rejected {totals['rejected']} → {path}\n")
    _report(path, [run], json_out)


@app.command()
def incidents(run: Optional[str] = RunOption, db: Optional[Path] = DbOption,
              json_out: bool = JsonOption) -> None:
    """Every potential violation of a run, validated: punishable, mitigated or dismissed."""
    with open_existing(db) as store:
        known = runs_of(store)
    if run and run not in known:
        fail(f"no run {run!r} in {db_path(db)}; runs: {', '.join(known) or 'none'}")
    _report(db_path(db), [run] if run else known, json_out)


def runs_of(store) -> list[str]:
    return [r["run"] for r in store.runs()]


def _report(path: Path, runs: list[str], json_out: bool) -> None:
    from explain import explain_incident
    from reasoner.investigation import Investigation
    from store import Store
    with Store(path) as store:
        inv = Investigation(store)
        found = [inc for r in runs for inc in inv.incidents(r)]
        if json_out:
            print_json([{k: v for k, v in inc.items() if k not in ("proofs", "scenarios")} for inc in found])
            return
        if not found:
            typer.echo("No potential violations recorded.")
        for inc in found:
            rb = inv.rulebook_for(inc["run"], inc["rulebook"]["sha256"]).rulebook
            typer.echo(f"── incident {inc['run']} {inc['id']} ──")
            typer.echo(explain_incident(inc, rb) + "\n")


@app.command()
def verify(run: Optional[str] = RunOption, db: Optional[Path] = DbOption,
           json_out: bool = JsonOption) -> None:
    """Recompute the hash chains and checkpoints; exit 1 and name the first bad event if any."""
    with open_existing(db) as store:
        report = store.verify(run)
    if json_out:
        print_json(report.as_dict())
    else:
        for r in report.runs:
            typer.echo(f"{r['run']}: {r['events']} events, chain {'ok' if r['ok'] else 'BROKEN'}, "
                       f"head {r['head']}")
        if report.problem:
            p = report.problem
            typer.echo(f"FAILED at run {p['run']} src {p['src']} seq {p['seq']} "
                       f"(chain position {p['chain_pos']}): {p['what']}")
        else:
            typer.echo("verified: every chain and checkpoint matches")
    raise typer.Exit(0 if report.ok else 1)


@app.command()
def runs(db: Optional[Path] = DbOption, json_out: bool = JsonOption) -> None:
    """The runs in the store with their event counts and time spans."""
    with open_existing(db) as store:
        rows = store.runs()
    if json_out:
        print_json(rows)
        return
    for r in rows:
        typer.echo(f"{r['run']}: {r['events']} events, t {r['first_t']} .. {r['last_t']}")


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
