"""Commands about the log itself: what runs it holds, what it refused, whether it is intact."""
from __future__ import annotations

import base64
import hashlib
from pathlib import Path
from typing import Any, Optional

import typer

from cli.app import DbOption, JsonOption, RunOption, app, open_existing, print_json
from cli.progress import stderr_progress
from cli.safe_text import preview, printable
from cli.times import duration, iso_utc
from store import Store

PREVIEW_BYTES = 60


@app.command()
def verify(run: Optional[str] = RunOption, db: Optional[Path] = DbOption,
           json_out: bool = JsonOption,
           with_snapshots: bool = typer.Option(
               False, "--snapshots",
               help="Also re-fold each run and name the state snapshots (the cache behind state at a time) "
                    "that differ from its events.")) -> None:
    """Recompute the hash chains, Merkle roots and checkpoints; exit 1 and name the first event
    that does not match if any (exit 2 for a usage error such as a missing store).

    With --snapshots, also exit 1 if a state snapshot differs from a fresh fold of its run's
    events. Snapshots are not evidence (nothing chains them) but state at a time answers from
    them, so a wrong one is worth finding; deleting them is safe, they are rebuilt from the events."""
    wrong: dict[str, list] = {}
    with open_existing(db) as store:
        with stderr_progress("verifying") as progress:
            report = store.verify(run, progress)
        if with_snapshots:
            wrong = _wrong_snapshots(store, [r["run"] for r in report.runs])
    ok = report.ok and not any(wrong.values())
    if json_out:
        print_json({**report.as_dict(), "ok": ok, **({"snapshots": wrong} if with_snapshots else {})})
    else:
        for r in report.runs:
            typer.echo(f"{printable(r['run'])}: {r['events']} events, chain {'ok' if r['ok'] else 'BROKEN'}, "
                       f"head {r['head']}")
        if report.problem:
            p = report.problem
            typer.echo(f"FAILED at run {_text(p['run'])} src {_text(p['src'])} seq {p['seq']} "
                       f"(chain position {p['chain_pos']}): {printable(p['what'])}")
        else:
            typer.echo("verified: every chain and checkpoint matches")
        for name, positions in wrong.items():
            if positions:
                t, seq, src = positions[0]
                typer.echo(f"SNAPSHOTS WRONG in run {_text(name)}: {len(positions)} differ from the events, the first "
                           f"after src {_text(src)} seq {seq} (t {t}); they are a cache: clearing them is safe")
        if with_snapshots and not any(wrong.values()):
            typer.echo("snapshots: every state snapshot matches its events")
    raise typer.Exit(0 if ok else 1)


def _wrong_snapshots(store: Store, runs: list[str]) -> dict[str, list[list]]:
    """Per run, the positions [t, seq, src] of the snapshots that differ from a fresh fold."""
    from store import check_snapshots

    with stderr_progress("checking snapshots") as progress:
        wrong = {}
        for i, name in enumerate(runs):
            wrong[name] = [list(position) for position in check_snapshots(store, name)]
            if progress is not None:
                progress(i + 1, len(runs))
    return wrong


@app.command()
def runs(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
         gaps: bool = typer.Option(False, "--gaps", help="Also list the seqs missing per source."),
         check: bool = typer.Option(True, "--verify/--no-verify",
                                    help="Verify each run's chain for the status column, or skip it.")) -> None:
    """The runs in the store: events, sources, time span (UTC), duration and chain status."""
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


@app.command()
def quarantine(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
               limit: int = typer.Option(20, "--limit", min=1, help="Show the latest N refusals.")) -> None:
    """What the store refused: when, from where, why, and the first bytes received (escaped)."""
    with open_existing(db) as store:
        total = store.quarantine_count()
        items = store.quarantined(limit, latest=True)
    if json_out:
        print_json({"total": total, "shown": len(items), "items": [_quarantine_json(q) for q in items]})
        return
    if not items:
        typer.echo("Nothing was refused.")
        return
    _print_quarantine(items, total)


# --- rows -----------------------------------------------------------------------------------------

def _run_row(summary: dict[str, Any]) -> dict[str, Any]:
    first, last = summary["first_t"], summary["last_t"]
    return {"run": summary["run"], "events": summary["events"], "sources": summary["sources"],
            "first_t": first, "last_t": last, "start": iso_utc(first), "end": iso_utc(last),
            "duration_ns": last - first}


def _quarantine_json(item: dict[str, Any]) -> dict[str, Any]:
    raw = item["raw"]
    return {"id": item["id"], "received_at": item["received_at"], "received": iso_utc(item["received_at"]),
            "origin": item["origin"], "reason": item["reason"], "raw_bytes": len(raw),
            "raw_sha256": hashlib.sha256(raw).hexdigest(), "raw_preview": preview(raw, PREVIEW_BYTES),
            "raw_base64": base64.b64encode(raw).decode("ascii")}


# --- tables ---------------------------------------------------------------------------------------

def _print_runs(rows: list[dict[str, Any]]) -> None:
    if not rows:
        typer.echo("The store holds no runs.")
        return
    table = _table("run", "events", "sources", "start (UTC)", "end (UTC)", "duration", "chain")
    for r in rows:
        table.add_row(*_cells(r["run"], r["events"], len(r["sources"]), r["start"], r["end"],
                              duration(r["duration_ns"]), r["chain"]))
    _print(table)


def _print_gaps(missing: list[dict[str, Any]]) -> None:
    if not missing:
        typer.echo("No gaps: every source's seqs run from 0 to its highest without a hole.")
        return
    table = _table("run", "src", "missing seqs", "events missing", "highest seq")
    for g in missing:
        ranges = ", ".join(str(a) if a == b else f"{a}-{b}" for a, b in g["missing"])
        lost = sum(b - a + 1 for a, b in g["missing"])
        table.add_row(*_cells(g["run"], g["src"], ranges, lost, g["highest"]))
    _print(table)


def _print_quarantine(items: list[dict[str, Any]], total: int) -> None:
    table = _table("id", "received (UTC)", "origin", "reason", "first bytes")
    for q in items:
        from rich.text import Text
        shown = Text(preview(q["raw"], PREVIEW_BYTES))  # escaped already
        table.add_row(*_cells(q["id"], iso_utc(q["received_at"]), q["origin"], q["reason"]), shown)
    _print(table)
    if total > len(items):
        typer.echo(f"Showing the latest {len(items)} of {total} refusals (--limit N for more, --json for all bytes).")


def _table(*headers: str):
    from rich.table import Table
    return Table(*headers)


def _cells(*values: Any) -> list:
    """Cells as rich Text: never read as markup, and with control characters escaped."""
    from rich.text import Text
    return [Text(printable(str(value))) for value in values]


def _print(table) -> None:
    from rich.console import Console
    Console(highlight=False).print(table)


def _text(value: Any) -> str:
    return "null" if value is None else printable(str(value))
