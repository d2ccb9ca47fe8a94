"""`gaps quarantine`: what the store refused, when, from where, why, and the bytes received."""
from __future__ import annotations

import base64
import hashlib
from pathlib import Path
from typing import Any, Optional

import typer

from cli.app import open_existing, print_json
from cli.options import DbOption, JsonOption
from cli.safe_text import preview
from cli.tables import cells, show, table
from reasoner.when import format_time_short

PREVIEW_BYTES = 60


def quarantine(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
               limit: int = typer.Option(20, "--limit", min=1, help="Show the latest N refusals.")) -> None:
    """List what the store refused: when, from where, why, and the first bytes received.

    The bytes are shown escaped, so a hostile producer's text cannot drive the terminal.
    """
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


def _quarantine_json(item: dict[str, Any]) -> dict[str, Any]:
    raw = item["raw"]
    return {"id": item["id"], "received_at": item["received_at"],
            "received": format_time_short(item["received_at"]),
            "origin": item["origin"], "reason": item["reason"], "raw_bytes": len(raw),
            "raw_sha256": hashlib.sha256(raw).hexdigest(), "raw_preview": preview(raw, PREVIEW_BYTES),
            "raw_base64": base64.b64encode(raw).decode("ascii")}


def _print_quarantine(items: list[dict[str, Any]], total: int) -> None:
    from rich.text import Text
    drawn = table("id", "received (UTC)", "origin", "reason", "first bytes")
    for q in items:
        shown = Text(preview(q["raw"], PREVIEW_BYTES))  # escaped already
        drawn.add_row(*cells(q["id"], format_time_short(q["received_at"]), q["origin"], q["reason"]), shown)
    show(drawn)
    if total > len(items):
        typer.echo(f"Showing the latest {len(items)} of {total} refusals (--limit N for more, --json for all bytes).")
