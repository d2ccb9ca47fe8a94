"""`gaps runs`: the runs in the store, their time span and chain status, and the seqs missing."""
from __future__ import annotations

from pathlib import Path
from typing import Any, Optional

import typer

from cli.app import open_existing, print_json
from cli.options import DbOption, JsonOption
from cli.progress import stderr_progress
from cli.tables import cells, show, table
from reasoner.when import format_duration, format_time_short
from store import RunSummary


def runs(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
         gaps: bool = typer.Option(False, "--gaps", help="Also list the seqs missing per source."),
         check: bool = typer.Option(True, "--verify/--no-verify",
                                    help="Verify each run's chain for the status column, or skip it.")) -> None:
    """List the runs in the store with their events, sources, time span and chain status."""
    with open_existing(db) as store:
        rows = [_run_row(r) for r in store.runs()]
        status: dict[str, bool] = {}
        if check:
            with stderr_progress("verifying") as progress:
                status = {r["run"]: r["ok"] for r in store.verify(progress=progress).runs}
        for row in rows:
            row["chain"] = ("verified" if status[row["run"]] else "broken") if check else "not checked"
        missing = store.gaps() if gaps else None
    if json_out:
        print_json({"runs": rows, "gaps": missing} if gaps else rows)
        return
    _print_runs(rows)
    if missing is not None:
        _print_gaps(missing)


def _run_row(summary: RunSummary) -> dict[str, Any]:
    first, last = summary.first_t, summary.last_t
    return {"run": summary.run, "events": summary.events, "sources": list(summary.sources),
            "first_t": first, "last_t": last, "start": format_time_short(first), "end": format_time_short(last),
            "duration_ns": last - first}


def _print_runs(rows: list[dict[str, Any]]) -> None:
    if not rows:
        typer.echo("The store holds no runs.")
        return
    drawn = table("run", "events", "sources", "start (UTC)", "end (UTC)", "duration", "chain")
    for r in rows:
        drawn.add_row(*cells(r["run"], r["events"], len(r["sources"]), r["start"], r["end"],
                             format_duration(r["duration_ns"]), r["chain"]))
    show(drawn)


def _print_gaps(missing: list[dict[str, Any]]) -> None:
    if not missing:
        typer.echo("No gaps: every source's seqs run from 0 to its highest without a hole.")
        return
    drawn = table("run", "src", "missing seqs", "events missing", "highest seq")
    for g in missing:
        ranges = ", ".join(str(a) if a == b else f"{a}-{b}" for a, b in g["missing"])
        lost = sum(b - a + 1 for a, b in g["missing"])
        drawn.add_row(*cells(g["run"], g["src"], ranges, lost, g["highest"]))
    show(drawn)
