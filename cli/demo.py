"""Wiring for `gaps demo`: sim_replay → Zenoh → ingest → store → reasoner → explain.

Only composition lives here: each step is a call into the room that owns it.
"""
from __future__ import annotations

import socket
from pathlib import Path

from ingest.service import IngestService
from sim_replay.paper import paper_run
from sim_replay.publisher import EventPublisher, zenoh_config


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def publish_through_zenoh(db: Path, events: list[dict], timeout_s: float = 30.0) -> dict:
    """Publish the events over a loopback Zenoh link into the store; return the ingest's totals."""
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    with IngestService(db, listen=[endpoint]) as ingest:
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as pub:
            if not pub.wait_until_matched(events[0], timeout_s):
                raise RuntimeError(f"the ingest did not subscribe within {timeout_s} s on {endpoint}")
            pub.publish_all(events)
        if not ingest.wait_until_settled(len(events), timeout_s):
            raise RuntimeError(f"not every event reached the store within {timeout_s} s: {ingest.stats()}")
        return ingest.stats()


def demo_events() -> list[dict]:
    return paper_run()


def write_report(db: Path, run: str, target: Path) -> Path:
    """The run's report (explain/report.py) written to `target`, in the format its suffix names."""
    from explain.report import build_report, format_for, render_report
    from store import Store
    fmt = format_for(target)
    with Store(db) as store:
        report = build_report(store, run)
    target.write_text(render_report(report, fmt), encoding="utf-8")
    return target
