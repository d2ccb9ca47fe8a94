"""`gaps replay`: a recording, or a stored run, put back on the wire as if live."""
from __future__ import annotations

import json
from pathlib import Path
from typing import Any, Optional

import typer

from cli.app import db_path, fail, open_existing
from cli.options import InsecureOption, JsonOption, ZenohConfigOption
from cli.sim import parse_speed
from reasoner import format_seconds


def replay(
    file: Optional[Path] = typer.Argument(None, help="A recording (MCAP or JSONL) to replay; without it, --db."),
    run: list[str] = typer.Option([], "--run", help="A run to replay (repeatable; default: every run)."),
    db: Optional[Path] = typer.Option(None, "--db", help="Replay runs of this store instead of a file."),
    speed: str = typer.Option("1", "--speed", help="1 (real time), 10 (ten times faster), or max."),
    listen: list[str] = typer.Option([], "--listen", help="Zenoh endpoint to listen on for an ingest (repeatable)."),
    connect: list[str] = typer.Option([], "--connect", help="Zenoh endpoint of a running `gaps serve` (repeatable)."),
    zenoh_file: Optional[Path] = ZenohConfigOption,
    insecure: bool = InsecureOption,
    json_out: bool = JsonOption,
) -> None:
    """Republish a recording onto Zenoh as if live, in chain order and at its recorded pace.

    Each event goes on its own key, so that an ingest (or any Zenoh tool) receives it as it first
    did, and an ingest rebuilds the same chains."""
    if (file is None) == (db is None):
        fail("give a recording FILE or --db STORE (one of them)")
    if not (listen or connect or zenoh_file):
        fail("nowhere to publish: give --connect ENDPOINT (a running `gaps serve`), --listen ENDPOINT, "
             "or --config FILE (a Zenoh config with its endpoints)")
    if file is not None and not file.is_file():
        fail(f"no such recording: {file}")
    pace = parse_speed(speed)
    wire = {"listen": listen, "connect": connect, "config_file": zenoh_file, "insecure": insecure}
    from sim_replay import NothingToReplay, recording
    from store import GapsError, StoreFault
    try:
        if file is not None:
            with recording(file) as (store, imported):
                out = _send(store, run, wire, pace, imported.to_json())
        else:
            with open_existing(db) as store:
                out = _send(store, run, wire, pace, None)
    except StoreFault:
        raise           # SQLite could not read the store: said as every command says it (cli/app.py)
    except (NothingToReplay, GapsError, TimeoutError, OSError) as exc:
        fail(str(exc))
    out["source"] = str(file or db_path(db))
    if json_out:
        typer.echo(json.dumps(out, indent=2, default=str))
        return
    for r in out["runs"]:
        s = r["sent"]
        typer.echo(f"Replayed run {r['run']}: {r['events']:,} events from {s['sources']} sources, "
                   f"{format_seconds(s['world_s'], 3)} of recorded time in {format_seconds(s['wall_s'])}")


def _send(store: Any, runs: list[str], wire: dict, pace: float | None, imported: dict | None) -> dict:
    from cli.progress import stderr_progress
    from sim_replay import chosen_runs, replay_runs
    with stderr_progress("replaying") as bar:
        sent = replay_runs(store, chosen_runs(store, runs), **wire, speed=pace, progress=bar)
    return {"imported": imported, "runs": [r.to_json() for r in sent]}
