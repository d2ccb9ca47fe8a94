"""`gaps demo`: sim_replay → Zenoh → ingest → store → reasoner → explain, on the paper's run.

Only composition lives here: each step is a call into the room that owns it.
"""
from __future__ import annotations

import socket
from pathlib import Path
from typing import Optional

import typer

from cli.app import db_path, fail, open_existing
from cli.incidents import show_incidents
from cli.options import DbOption, JsonOption
from reasoner.api import Case


def demo(db: Optional[Path] = DbOption, json_out: bool = JsonOption,
         report: Optional[Path] = typer.Option(
             None, "--report", help="Where to write the HTML report (default: gaps-report.html beside the store; "
                                    ".md or .json by suffix).")) -> None:
    """Replay the paper's two junction scenarios into the store, explain them and write a report.

    The events travel over a loopback Zenoh link into an in-process ingest, as a recorder's would.
    """
    from sim_replay.paper import paper_run
    path = db_path(db)
    events = paper_run()
    totals = publish_through_zenoh(path, events)
    run = events[0]["run"]
    if not json_out:
        typer.echo(f"Published {len(events)} events of run {run} over Zenoh; stored {totals['stored']}, "
                   f"duplicates {totals['duplicates']}, rejected {totals['rejected']} → {path}\n")
    with open_existing(path) as store:
        show_incidents(Case(store), run, json_out, explain=True)
    target = report or path.parent / "gaps-report.html"
    try:
        written = write_report(path, run, target)
    except (OSError, ValueError) as exc:
        fail(f"cannot write the report to {target}: {exc}")
    typer.echo(f"Report of run {run}: {written.resolve()} (open it in a browser; `gaps report --run {run} -o FILE --pdf` "
               "prints a PDF)", err=json_out)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def publish_through_zenoh(db: Path, events: list[dict], timeout_s: float = 30.0) -> dict:
    """Publish the events over a loopback Zenoh link into the store; return the ingest's totals."""
    from ingest.service import IngestService
    from sim_replay.publisher import EventPublisher, zenoh_config
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    with IngestService(db, listen=[endpoint]) as ingest:
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as pub:
            if not pub.wait_until_matched(events[0], timeout_s):
                raise RuntimeError(f"the ingest did not subscribe within {timeout_s} s on {endpoint}")
            pub.publish_all(events)
        if not ingest.wait_until_settled(len(events), timeout_s):
            raise RuntimeError(f"not every event reached the store within {timeout_s} s: {ingest.stats()}")
        return ingest.stats()


def write_report(db: Path, run: str, target: Path) -> Path:
    """The run's report written to `target`, in the format its suffix names."""
    from explain.report import build_report, format_for, render_report
    fmt = format_for(target)
    with open_existing(db) as store:
        built = build_report(store, run)
    target.write_text(render_report(built, fmt), encoding="utf-8")
    return target
