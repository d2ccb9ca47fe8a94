"""`gaps runs`: the runs in the store, their time span and chain status, the seqs missing, and
each source's liveliness as the ingest recorded it."""
from __future__ import annotations

from pathlib import Path
from typing import Any, Optional

import typer

from cli.app import open_existing, print_json
from cli.options import DbOption, JsonOption
from cli.progress import stderr_progress
from cli.tables import cells, show, table
from reasoner import format_duration, format_time_short
from store import RunSummary
from store.wire import SourceLife, WireMiss


def runs(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
         gaps: bool = typer.Option(False, "--gaps", help="Also list the seqs missing per source, and samples "
                                   "lost on the wire beyond their publisher's cache."),
         live: bool = typer.Option(False, "--live", help="Also list when each source's liveliness token "
                                   "appeared and disappeared (recorded by gaps serve)."),
         check: bool = typer.Option(True, "--verify/--no-verify",
                                    help="Verify each run's chain for the status column, or skip it.")) -> None:
    """List the runs in the store with their events, sources, time span and chain status."""
    with open_existing(db) as store:
        rows = [_run_row(r) for r in store.runs()]
        status: dict[str, str] = {}
        if check:
            with stderr_progress("verifying") as progress:
                report = store.verify(progress=progress)
            damaged = report.integrity is not None and not report.integrity.ok
            status = {r.run: "broken" if not r.ok else "file damaged" if damaged else "verified"
                      for r in report.runs}
        for row in rows:
            row["chain"] = status.get(row["run"], "broken") if check else "not checked"
        missing = store.gaps() if gaps else None
        misses = store.wire_misses() if gaps else []
        lives = [life for r in rows for life in store.lives(r["run"])] if live else []
    if json_out:
        extra = {**({"gaps": missing, "wire_misses": [m.to_json() for m in misses]} if gaps else {}),
                 **({"liveliness": [life.to_json() for life in lives]} if live else {})}
        print_json({"runs": rows, **extra} if extra else rows)
        return
    _print_runs(rows)
    if missing is not None:
        _print_gaps(missing)
        _print_misses(misses)
    if live:
        _print_lives(lives)


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
        drawn.add_row(*cells(r["run"], f"{r['events']:,}", len(r["sources"]), r["start"], r["end"],
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


def _print_misses(misses: list[WireMiss]) -> None:
    if not misses:
        return
    drawn = table("run", "src", "kind", "samples lost on the wire", "after seq", "noticed (UTC)")
    for m in misses:
        drawn.add_row(*cells(m.run, m.src, m.kind, m.count, "-" if m.after_seq is None else m.after_seq,
                             format_time_short(m.at)))
    show(drawn)


def _print_lives(lives: list[SourceLife]) -> None:
    if not lives:
        typer.echo("No liveliness recorded: these runs were not received by gaps serve, or their sources "
                   "declared no tokens.")
        return
    drawn = table("run", "src", "token appeared (UTC)", "disappeared (UTC)", "last seq then")
    for life in lives:
        gone = "alive" if life.disappeared_at is None else format_time_short(life.disappeared_at)
        drawn.add_row(*cells(life.run, life.src, "-" if life.appeared_at is None else format_time_short(life.appeared_at),
                             gone, "-" if life.last_seq is None else life.last_seq))
    show(drawn)
