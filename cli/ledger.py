"""Commands about the log itself: what runs it holds and whether it is intact."""
from __future__ import annotations

from typing import Optional
from pathlib import Path

import typer

from cli.app import DbOption, JsonOption, RunOption, app, open_existing, print_json


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
