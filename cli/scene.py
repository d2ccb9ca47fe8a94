"""`gaps scene --run R --at T`: what the record says was going on at one moment.

The scene is reasoner/scene.py's, its text explain/scene_text.py's, the time forms
reasoner/when.py's; this module reads the options and prints, with every recorded string escaped
(cli/safe_text.py). Exit codes: 0 shown; 2 for what names nothing (no store, no such run, a time
that cannot be read, a vehicle not present at that time).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli.app import fail, open_existing, print_json, require_run
from cli.options import DbOption, JsonOption, RunRequired
from cli.safe_text import printable

AT_HELP = ("When: ns since the epoch (1732176010000000000), seconds from the run start (12.5s, 1m30s) "
           "or ISO 8601 with a zone (2024-11-21T08:00:10.25Z).")


def scene(run: str = RunRequired,
          at: str = typer.Option(..., "--at", help=AT_HELP),
          vehicle: Optional[str] = typer.Option(None, "--vehicle", help="Only this vehicle (its id, e.g. 173)."),
          judge: Optional[bool] = typer.Option(
              None, "--judge/--no-judge",
              help="Ask the validator rulebook whether each goal is lawful (default: with --vehicle)."),
          db: Optional[Path] = DbOption, json_out: bool = JsonOption) -> None:
    """Show the scene at a time: signals, monitors and every vehicle present.

    Per vehicle: its position, who was in control, the Vehicle, Monitor and Validator Scenarios
    and the Vehicle Action, each fact with the event it came from.
    """
    from reasoner.scene import SceneError, run_start
    from reasoner.scene import scene as scene_at
    from reasoner.when import TimeError, parse_time
    with open_existing(db) as store:
        require_run(store, run)
        try:
            t = parse_time(at, run_start(store, run))
            found = scene_at(store, run, t, vehicle=vehicle, judge=judge)
        except (SceneError, TimeError) as exc:
            fail(str(exc))
    if json_out:
        print_json(found.to_json())
        return
    from explain.scene_text import scene_lines
    for line in scene_lines(found):
        typer.echo(printable(line))
