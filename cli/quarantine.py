"""`gaps quarantine`: what the store refused, when, from where, why, and the bytes received; with
`--prune`, the rows removed and a summary of them recorded (store/quarantine.py)."""
from __future__ import annotations

import base64
import hashlib
import time
from pathlib import Path
from typing import Any, Optional

import typer

from cli.app import db_path, fail, open_existing, print_json
from cli.options import DbOption, JsonOption
from cli.safe_text import preview
from cli.tables import cells, show, table
from reasoner import format_time_short

PREVIEW_BYTES = 60


def quarantine(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
               limit: int = typer.Option(20, "--limit", min=1, help="Show the latest N refusals."),
               prune: bool = typer.Option(False, "--prune", help="Remove the rows (all, or those --before T) "
                                          "and record a summary of them: counts per reason and origin, the "
                                          "time span, a digest. Writes to the store."),
               before: Optional[str] = typer.Option(None, "--before", metavar="T", help="With --prune: only rows "
                                                    "whose last refusal came before T (2026-11-26T08:00:00Z, or an "
                                                    "age: 7d, 12h, 30m).")) -> None:
    """List what the store refused: when, from where, why, how often, and the first bytes received.

    Identical refusals (same source, reason and bytes: a file's line numbers aside) are one row with
    a count. The bytes are shown
    escaped, so a hostile producer's text cannot drive the terminal. Past the quarantine's cap,
    refusals are counted per origin, not kept; pruned rows are summarised. See docs/store.md.
    """
    if before is not None and not prune:
        fail("--before goes with --prune (it says which rows to remove)")
    if prune:
        _prune(db, before, json_out)
        return
    with open_existing(db) as store:
        total = store.quarantine_count()
        items = store.quarantined(limit, latest=True)
        summary = store.quarantine_summary()
    if json_out:
        print_json({"total": total, "shown": len(items), "items": [_quarantine_json(q) for q in items],
                    "held": summary["held"], "over_cap": summary["over_cap"], "prunes": summary["prunes"]})
        return
    if items:
        _print_quarantine(items, total)
    elif not summary["prunes"] and not summary["over_cap"]:
        typer.echo("Nothing was refused.")
    else:
        typer.echo("The quarantine keeps no rows now.")
    _print_beyond(summary)


def _prune(db: Optional[Path], before: Optional[str], json_out: bool) -> None:
    """Open the store to write (it must exist), prune, say what was removed."""
    from store import Store, StoreError, parse_before
    open_existing(db).close()  # an event store at this schema: pruning never migrates one in passing
    path = db_path(db)
    now = time.time_ns()
    try:
        cutoff = now + 1 if before is None else parse_before(before, now)
    except ValueError as exc:
        fail(str(exc))
    try:
        with Store(path) as store:
            pruned = store.prune_quarantine(cutoff)
            left = store.quarantine_count()
    except StoreError as exc:
        fail(str(exc), exc.exit_code)
    if json_out:
        print_json({"pruned": pruned.to_json() if pruned else None, "rows_left": left})
    elif pruned is None:
        typer.echo("Nothing to prune.")
    else:
        typer.echo(f"Pruned {pruned.rows:,} rows ({pruned.samples:,} refusals, {pruned.bytes:,} bytes, "
                   f"{_short(pruned.first_at)} to {_short(pruned.last_at)}); "
                   f"{left:,} rows left. Recorded as prune {pruned.id} (digest {pruned.digest[:16]}…).")


def _short(t: int | None) -> str:
    """A prune's first or last refusal time (None only for a prune of no rows, never shown)."""
    return "-" if t is None else format_time_short(t)


def _quarantine_json(item: dict[str, Any]) -> dict[str, Any]:
    raw = item["raw"]
    return {"id": item["id"], "received_at": item["received_at"],
            "received": format_time_short(item["received_at"]), "count": item["count"],
            "last_at": item["last_at"], "origin": item["origin"], "last_origin": item["last_origin"], "reason": item["reason"], "raw_bytes": len(raw),
            "raw_sha256": hashlib.sha256(raw).hexdigest(), "raw_preview": preview(raw, PREVIEW_BYTES),
            "raw_base64": base64.b64encode(raw).decode("ascii")}


def _print_quarantine(items: list[dict[str, Any]], total: int) -> None:
    from rich.text import Text
    drawn = table("id", "received (UTC)", "times", "origin", "reason", "first bytes")
    for q in items:
        shown = Text(preview(q["raw"], PREVIEW_BYTES))  # escaped already
        drawn.add_row(*cells(q["id"], format_time_short(q["received_at"]), f"{q['count']:,}", q["origin"],
                             q["reason"]), shown)
    show(drawn)
    if total > len(items):
        typer.echo(f"Showing the latest {len(items)} of {total} refusals (--limit N for more, --json for all bytes).")


def _print_beyond(summary: dict[str, Any]) -> None:
    """What the rows shown do not hold: refusals past the cap, and what prunes removed."""
    over = summary["over_cap"]
    if over:
        samples = sum(o["samples"] for o in over)
        typer.echo(f"Past the quarantine's cap: {samples:,} refusals from {len(over):,} origin(s) counted, their "
                   f"bytes not kept (--json lists them); `gaps quarantine --prune` makes room.")
    for p in summary["prunes"]:
        typer.echo(f"Pruned at {format_time_short(p['pruned_at'])}: {p['rows']:,} rows ({p['samples']:,} refusals, "
                   f"{p['bytes']:,} bytes) received {format_time_short(p['first_at'])} to "
                   f"{format_time_short(p['last_at'])}; digest {p['digest'][:16]}… (--json: per reason and origin).")
