"""`gaps demo`: sim_replay → Zenoh → ingest → store → reasoner → explain, on the paper's run.

Only composition lives here: each step is a call into the room that owns it.
"""
from __future__ import annotations

import socket
from pathlib import Path
from typing import Callable, Iterable, Optional

import typer

from cli.app import db_path, fail, open_existing
from cli.incidents import show_incidents
from cli.options import DbOption, JsonOption
from explain import write_report
from reasoner.api import Case
from sim_replay.outlets import OutletSummary


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
    totals, _ = publish_through_zenoh(path, events)
    run = events[0]["run"]
    if not json_out:
        typer.echo(f"Published {len(events)} events of run {run} over Zenoh; stored {totals['stored']}, "
                   f"duplicates {totals['duplicates']}, rejected {totals['rejected']} → {path}\n")
    target = report or path.parent / "gaps-report.html"
    with open_existing(path) as store:
        case = Case(store)              # judged once, for the listing and the report
        show_incidents(case, run, json_out, explain=True)
        try:
            written = write_report(case, run, target)
        except OSError as exc:
            fail(f"cannot write the report to {target}: {exc.strerror or exc}")
    typer.echo(f"Report of run {run}: {written.resolve()} (open it in a browser; `gaps report --run {run} -o FILE --pdf` "
               "prints a PDF)", err=json_out)


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def publish_through_zenoh(db: Path, events: Iterable[dict], timeout_s: float = 30.0, *,
                          record: Path | None = None, speed: float | None = None,
                          each: Callable[[dict], None] | None = None) -> tuple[dict, OutletSummary]:
    """Publish the events over a loopback Zenoh link into an in-process ingest on the store (and
    record them, paced, as asked); return the ingest's totals and what went out."""
    from ingest.service import IngestService
    from sim_replay.outlets import Outlets
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    with IngestService(db, listen=[endpoint]) as ingest:
        with Outlets(connect=[endpoint], record=record, speed=speed, wait_s=timeout_s) as out:
            for event in events:
                out.put(event)
                if each is not None:
                    each(event)
        sent = out.summary()
        if not ingest.wait_until_settled(sent.published, timeout_s):
            raise RuntimeError(f"not every event reached the store within {timeout_s} s: {ingest.stats()}")
        return ingest.stats(), sent
