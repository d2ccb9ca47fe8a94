"""Where a producer's events go: onto Zenoh, into its own MCAP recording, at the pace asked.

    with Outlets(connect=["tcp/127.0.0.1:7447"], record="run.mcap", speed=1.0) as out:
        for event in events:
            out.put(event)
    out.summary()      # events published and recorded, sources, world and wall seconds

The simulation and the replay of a recording both end here, so that what reaches an ingest and
what the recording holds are the same events in the same order. Publishing is RELIABLE with
BLOCK (publisher.py): a slow ingest slows the producer down rather than losing events. With a
speed, world time is paced against the wall clock (1.0: real time; 10.0: ten times faster);
without one the events go as fast as they are made.
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from itertools import islice
from operator import itemgetter
from pathlib import Path
from types import TracebackType
from typing import Sequence

from store.keys import Signer
from store.transfer import Recorder

from .publisher import EventPublisher, zenoh_config

SECOND = 1_000_000_000
_SRC, _T = itemgetter("src"), itemgetter("t")


@dataclass(frozen=True)
class OutletSummary:
    """What went out: counts, sources, the world time covered and the wall time it took."""

    published: int
    recorded: int
    late_in_recording: int
    sources: int
    world_s: float
    wall_s: float
    recording: str | None
    recording_bytes: int

    def to_json(self) -> dict:
        return dict(self.__dict__)


class Outlets:
    """Publishes (when endpoints are given) and records (when a path is given) each event put."""

    def __init__(self, *, listen: Sequence[str] = (), connect: Sequence[str] = (), mode: str | None = None,
                 record: str | Path | None = None, speed: float | None = None, wait_s: float = 30.0,
                 signer: Signer | None = None, config_file: str | Path | None = None,
                 insecure: bool = False) -> None:
        """Publish to the endpoints given, or as the Zenoh ``config_file`` says (store.session_config;
        the endpoints given written over it); ``mode`` default peer, or the file's. A producer
        reachable beyond loopback without Zenoh authentication is refused unless ``insecure``
        (EventPublisher)."""
        if speed is not None and not speed > 0:
            raise ValueError(f"speed must be positive (1 = real time) or None (as fast as possible), not {speed!r}")
        self.endpoints = (tuple(listen), tuple(connect))
        self.config_file, self.insecure = config_file, insecure
        self.mode, self.record_path, self.speed, self.wait_s = mode, record, speed, wait_s
        self.signer = signer  # signs each event once, before it is published and recorded alike
        self._publisher: EventPublisher | None = None
        self._recorder: Recorder | None = None
        self._published = 0
        self._sources: set[str] = set()
        self._first_t: int | None = None
        self._last_t: int | None = None
        self._wall0 = 0.0
        self._matched = False
        self._result: OutletSummary | None = None

    def __enter__(self) -> Outlets:
        listen, connect = self.endpoints
        if listen or connect or self.config_file is not None:
            config = zenoh_config(listen=listen, connect=connect, mode=self.mode, config_file=self.config_file)
            self._publisher = EventPublisher(config=config, events_signed=self.signer is not None,
                                             insecure=self.insecure)
        if self.record_path is not None:
            try:
                self._recorder = Recorder(self.record_path).__enter__()
            except BaseException:
                self._close_publisher()
                raise
        self._wall0 = time.monotonic()
        return self

    def put(self, event: dict) -> None:
        """Send one event on (blocking while Zenoh's queue is full, or until its time comes)."""
        if self.signer is not None:
            event = self.signer.sign(event)
        self._note(event)
        if self.speed is not None:
            due = self._wall0 + (event["t"] - self._first_t) / SECOND / self.speed
            ahead = due - time.monotonic()
            if ahead > 0:
                time.sleep(ahead)
        if self._publisher is not None:
            self._publisher.publish(event)
            self._published += 1
        if self._recorder is not None:
            self._recorder.add(event)

    def put_all(self, events: list[dict], payloads: Sequence[bytes] | None = None) -> None:
        """Send events on in order, as `put` each, but with their Zenoh puts back to back
        (EventPublisher.publish_all: a third of the cost of a put each at a thousand events a tick).
        Paced (a speed), each goes at its own time, one by one. ``payloads``: the events' canonical
        bytes as already written, published as they are (EventPublisher.publish_all); by default
        a simulation's tick's own (sim_events.Tick.payloads, with its keys, Tick.zenoh_keys), where it
        wrote them; ignored with a signer, which signs and encodes each event."""
        if self.speed is not None:
            for event in events:
                self.put(event)
            return
        keys = None
        if payloads is None:
            payloads = getattr(events, "payloads", None)
            keys = getattr(events, "zenoh_keys", None) if payloads is not None else None
        if self.signer is not None:
            events, payloads, keys = [self.signer.sign(event) for event in events], None, None
        self._note_all(events)
        if self._publisher is not None:
            self._published += self._publisher.publish_all(events, payloads, keys)
        if self._recorder is not None:
            for event in events:
                self._recorder.add(event)

    def await_ingest(self, event: dict) -> None:
        """Wait, as before the first put, for an ingest to subscribe to this event's key (a no-op
        when not publishing): what a producer asks of the ingests before it publishes."""
        if self._publisher is not None and not self._matched:
            self._matched = self._publisher.wait_until_matched(event, self.wait_s)
            if not self._matched:
                raise TimeoutError(f"no ingest subscribed within {self.wait_s:g} s on {self._where()}: "
                                   "is `gaps serve` running there?")

    @property
    def session(self):
        """The publishing Zenoh session, or None when only recording."""
        return None if self._publisher is None else self._publisher.session

    def _note(self, event: dict) -> None:
        """Count an event going out: its source, the world time covered; before the first, wait
        for an ingest to subscribe."""
        t = event["t"]
        first = self._first_t is None
        if first:
            self._first_t = t
        self._last_t = t if self._last_t is None else max(self._last_t, t)
        self._sources.add(event["src"])
        self.await_ingest(event)
        # The clock starts when the first event can go out (matched, and the ingests asked what
        # they hold: sim_replay/held_runs.py): paced from before, the events due while waiting
        # would go out in one burst.
        if first and self._publisher is not None:
            self._wall0 = time.monotonic()

    def _note_all(self, events: list[dict]) -> None:
        """`_note` each, the first alone (it may wait for an ingest) and the rest together."""
        if not events:
            return
        self._note(events[0])
        if len(events) > 1:
            rest = islice(events, 1, None)
            self._sources.update(map(_SRC, rest))
            last = max(map(_T, islice(events, 1, None)))
            if last > self._last_t:
                self._last_t = last

    def summary(self) -> OutletSummary:
        if self._result is not None:
            return self._result
        rec = self._recorder
        world = 0.0 if self._first_t is None or self._last_t is None else (self._last_t - self._first_t) / SECOND
        return OutletSummary(self._published, rec.report.events if rec and rec.report else 0, rec.late if rec else 0,
                             len(self._sources), world, time.monotonic() - self._wall0,
                             str(self.record_path) if self.record_path is not None else None,
                             rec.report.bytes if rec and rec.report else 0)

    def _where(self) -> str:
        listen, connect = self.endpoints
        named = [*(f"connect {e}" for e in connect), *(f"listen {e}" for e in listen)]
        return ", ".join(named + ([f"the endpoints of {self.config_file}"] if self.config_file is not None else []))

    def _close_publisher(self) -> None:
        if self._publisher is not None:
            self._publisher.close()
            self._publisher = None

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        try:
            if self._recorder is not None:
                self._recorder.__exit__(exc_type, exc, tb)
        finally:
            self._close_publisher()
        if exc_type is None:
            self._result = self.summary()
