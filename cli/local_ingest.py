"""An ingest in this process, fed over a loopback Zenoh link: how `gaps demo` and `gaps sim --db`
store what they publish, through the same ingest.serve.Server as `gaps serve` (its store lock
included: a `gaps serve` already writing the store refuses them, exit 4), without its signals and
status line. Composition only: the ingest is ingest's, the publishing sim_replay.outlets'."""
from __future__ import annotations

import socket
from pathlib import Path
from typing import TYPE_CHECKING, Iterable

if TYPE_CHECKING:
    from sim_replay import OutletSummary
    from store.keys import Signer


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def publish_through_zenoh(db: Path, events: Iterable[dict] | Iterable[list[dict]], timeout_s: float = 30.0, *,
                          record: Path | None = None, speed: float | None = None,
                          signer: Signer | None = None) -> tuple[dict, OutletSummary]:
    """Publish the events over a loopback Zenoh link into an in-process ingest on the store (and
    record them, paced, and signed, as asked); return the ingest's totals and what went out.
    `events` may come a tick at a time (lists, as Simulation.batches gives them: put together).
    The ingest may trail a fast producer by a hundred thousand events: it is waited for as long
    as it keeps storing, and a TimeoutError says so when it stops for timeout_s."""
    from ingest import Server, ServeOptions
    from sim_replay import Outlets
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    with Server(ServeOptions(db, listen=(endpoint,))) as server:
        ingest = server.service
        assert ingest is not None           # made when the server is entered
        with Outlets(connect=[endpoint], record=record, speed=speed, wait_s=timeout_s, signer=signer) as out:
            for item in events:
                if isinstance(item, list):
                    out.put_all(item)
                else:
                    out.put(item)
        sent = out.summary()
        progress = -1
        while not ingest.wait_until_settled(sent.published, timeout_s):
            stats = ingest.stats()
            done = stats["stored"] + stats["duplicates"] + stats["rejected"] + stats["failed"]
            if done == progress:
                raise TimeoutError(f"not every event reached the store within {timeout_s:g} s: {stats}")
            progress = done
        return ingest.stats(), sent
