"""A recording put back on the wire as if it were live (`gaps replay`).

Each event goes out on its own key, in the order its run's chain holds it, with its recorded
spacing in time scaled by a speed (1: real time; None: as fast as the wire takes it). The events
come from a store (a run in chain order, `Store.history`) or from a recording file, which is first
imported into a temporary store: the file's own checks apply, and an MCAP file's chain order
attachment puts the events back in the order they were first appended. So an ingest that receives
the replay appends the same events in the same order, and its chain heads are the recording's.

They go out through sim_replay.outlets, the simulation's own way onto the wire: RELIABLE with BLOCK
(a slow ingest slows the replay, nothing is dropped), the producer's cache for an ingest that
restarts, liveliness per source. Each run is its own stream with its own clock.
"""
from __future__ import annotations

import tempfile
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Iterator, Sequence

from store import Store, parse_json, parse_json_all
from store.transfer import ImportReport, import_file

from .held_runs import refuse_if_held
from .outlets import OutletSummary, Outlets
from .publisher import PUT_RUN

Progress = Callable[[int, int], None]


@dataclass(frozen=True)
class Replayed:
    """What one run's replay sent."""

    run: str
    events: int
    sent: OutletSummary

    def to_json(self) -> dict:
        return {"run": self.run, "events": self.events, "sent": self.sent.to_json()}


class NothingToReplay(ValueError):
    """The runs asked for are not in the recording (or it holds none)."""


@contextmanager
def recording(path: str | Path) -> Iterator[tuple[Store, ImportReport]]:
    """The recording file imported into a temporary store, and what the import found."""
    with tempfile.TemporaryDirectory(prefix="gaps-replay-") as tmp:
        with Store(Path(tmp) / "replay.db", durable=False) as store:
            yield store, import_file(store, path)


def chosen_runs(store: Store, runs: Sequence[str] = ()) -> list[str]:
    """The runs to replay: those asked for (each must be there), else every run."""
    present = store.run_names()
    missing = [r for r in runs if r not in present]
    if missing or not present:
        raise NothingToReplay(f"no run {', '.join(map(repr, missing))} in the recording (it holds: "
                              f"{', '.join(present) or 'none'})" if missing else "the recording holds no events")
    return list(runs) or present


def run_events(store: Store, run: str) -> Iterator[dict]:
    """A run's events as stored, in chain order."""
    for row in store.history(run):
        yield parse_json(row.event)


def stored_runs_of(store: Store, run: str, size: int = PUT_RUN) -> Iterator[tuple[list[dict], list[bytes]]]:
    """A run's events in chain order, in runs of up to `size`: each event with its stored text's
    bytes, which are its canonical form (what its hash covers), so that a replay at full speed
    puts them as they are, back to back, instead of encoding each event again."""
    texts: list[str] = []
    for row in store.history(run):
        texts.append(row.event)
        if len(texts) >= size:
            yield parse_json_all(texts), [text.encode() for text in texts]
            texts = []
    if texts:
        yield parse_json_all(texts), [text.encode() for text in texts]


def replay(store: Store, runs: Sequence[str], *, listen: Sequence[str] = (), connect: Sequence[str] = (),
           speed: float | None = 1.0, wait_s: float = 30.0, progress: Progress | None = None,
           config_file: str | Path | None = None, insecure: bool = False) -> list[Replayed]:
    """Publish each run's events, one run after another, to the endpoints given or as the Zenoh
    ``config_file`` says (Outlets); what each sent."""
    total = sum(store.count(run) for run in runs)
    done, out = 0, []
    for run in runs:
        with Outlets(listen=listen, connect=connect, speed=speed, wait_s=wait_s, config_file=config_file,
                     insecure=insecure) as outlets:
            first = next(run_events(store, run), None)
            if first is not None and outlets.session is not None:   # one run, one producer
                outlets.await_ingest(first)
                refuse_if_held(outlets.session, store, run)
            if speed is None:   # as fast as the wire takes it: the stored bytes, puts back to back
                for events, payloads in stored_runs_of(store, run):
                    outlets.put_all(events, payloads)
                    done += len(events)
                    if progress is not None:
                        progress(done, total)
            else:
                for event in run_events(store, run):
                    outlets.put(event)
                    done += 1
                    if progress is not None and done % 1000 == 0:
                        progress(done, total)
        sent = outlets.summary()
        out.append(Replayed(run, sent.published, sent))
    if progress is not None:
        progress(done, total)
    return out
