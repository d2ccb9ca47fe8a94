"""Helpers for the ingest tests: real Zenoh sessions on loopback ports, real SQLite files.

Scouting is off everywhere and every endpoint is explicit, so parallel test runs and other Zenoh nodes on
the machine cannot join in.
"""
from __future__ import annotations

import socket
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from ingest import IngestService
from sim_replay.publisher import EventPublisher, zenoh_config

RUN = "test-run"
T0 = 1_732_184_100_000_000_000  # ns
MATCH_TIMEOUT_S = 5.0

BODIES: dict[str, Callable[[str], dict]] = {
    "vehicle.perception": lambda ident: {"facts": [f"{ident} has red light", f"{ident} is of type car"]},
    "vehicle.decision": lambda ident: {
        "goal": f"{ident} can enter the junction", "action": "enter the junction", "proceeds": False,
    },
    "entity.state": lambda ident: {"x": 1.5, "y": -2.0, "speed_mps": 8.3},
    "signal.state": lambda ident: {"junction": "j1", "colour": "red"},
    "monitor.observation": lambda ident: {"vehicle": "173", "facts": ["173 has red light"]},
}


def make_event(src: str, seq: int, kind: str = "vehicle.perception", *, run: str = RUN, **body: object) -> dict:
    """A valid event; ``body`` entries override the kind's default body."""
    ident = src.partition("/")[2]
    return {
        "v": 1, "run": run, "src": src, "seq": seq, "t": T0 + seq * 100_000_000,
        "kind": kind, "body": {**BODIES[kind](ident), **body},
    }


def free_endpoint() -> str:
    """A loopback TCP endpoint on a port the OS just handed out."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{sock.getsockname()[1]}"


@contextmanager
def linked(db_path: Path, topology: str, **ingest_options: object) -> Iterator[tuple[EventPublisher, IngestService]]:
    """A publisher and an ingest joined over one loopback link, listener opened first.

    topology: ``pub-listens`` (ingest peer connects), ``ingest-listens`` (publisher connects) or
    ``ingest-client`` (ingest in client mode connects to the publishing peer).
    """
    endpoint = free_endpoint()
    publisher = ingest = None
    try:
        if topology == "ingest-listens":
            ingest = IngestService(db_path, listen=[endpoint], **ingest_options)
            publisher = EventPublisher(config=zenoh_config(connect=[endpoint]))
        else:
            publisher = EventPublisher(config=zenoh_config(listen=[endpoint]))
            mode = "client" if topology == "ingest-client" else "peer"
            ingest = IngestService(db_path, connect=[endpoint], mode=mode, **ingest_options)
        yield publisher, ingest
    finally:
        if ingest is not None:
            ingest.stop()
        if publisher is not None:
            publisher.close()


def await_match(publisher: EventPublisher, event: dict) -> None:
    """Pub/sub keeps no history: publish only once the ingest's subscription has reached the publisher."""
    assert publisher.wait_until_matched(event, MATCH_TIMEOUT_S), "ingest subscription never matched"
