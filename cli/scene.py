"""`gaps scene --run R --at T`: what the record says was going on at one moment.

The scene is the reasoner's `Case.scene` (the time forms reasoner/when.py's), its text
`explain.scene_lines`; this module reads the options and prints, with every recorded string
escaped (cli/safe_text.py). `--svg FILE` writes the scene as a picture instead
(`explain.scene_picture_svg`, the report's drawing): the junction of `--vehicle`, else `--junction`, else the busiest one, zoomed so
that lanes and road users can be read. Exit codes: 0 shown; 2 for what names nothing (no store, no
such run, a time that cannot be read, a vehicle not present at that time, a junction not on the
map, a folder that does not exist).
"""
from __future__ import annotations

from pathlib import Path
from typing import Optional

import typer

from cli.app import db_path, fail, open_existing, print_json, writable_output
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
          svg: Optional[Path] = typer.Option(
              None, "--svg", help="Write the scene as an SVG picture to this file instead of printing it."),
          junction: Optional[str] = typer.Option(
              None, "--junction", help="With --svg: zoom to this junction (default: --vehicle's, else the busiest)."),
          db: Optional[Path] = DbOption, json_out: bool = JsonOption) -> None:
    """Show the scene at a time: signals, monitors and every vehicle present.

    Per vehicle: its position, who was in control, the Vehicle, Monitor and Validator Scenarios
    and the Vehicle Action, each fact with the event it came from. With --svg: a picture of the
    lanes, stop lines, signals per approach, monitors' cones and the road users present, in mph.
    """
    if svg is not None:
        _picture(run, at, vehicle, junction, svg, db)
        return
    from reasoner import Case
    with open_existing(db) as store:
        found = Case(store).scene(run, at, vehicle=vehicle, judge=judge)
    if json_out:
        print_json(found.to_json())
        return
    from explain import scene_lines
    for line in scene_lines(found):
        typer.echo(printable(line))


def _picture(run: str, at: str, vehicle: Optional[str], junction: Optional[str], target: Path,
             db: Optional[Path]) -> None:
    """`--svg`: the scene picture written to `target`, and one line saying what it shows."""
    from explain import scene_picture_svg
    from reasoner import Case
    from store import write_text
    if not target.parent.is_dir():
        fail(f"no such folder for the picture: {target.parent}")
    writable_output(target, db)
    with open_existing(db) as store:
        pic = scene_picture_svg(Case(store), run, at, vehicle=vehicle, junction=junction)
    try:
        write_text(target, pic.svg, [db_path(db)])
    except OSError as exc:
        fail(f"cannot write {target}: {exc.strerror or exc}")
    where = f"junction {pic.junction}" if pic.junction is not None else "the whole map"
    typer.echo(printable(f"Scene of run {run} at {pic.offset} from the run start ({where}; {pic.shown} road "
                         f"user{'' if pic.shown == 1 else 's'} present on the map) written to {target}"))
