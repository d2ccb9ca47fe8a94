"""`gaps replay --speed 1|10|max`: the events arrive on Zenoh with the recording's relative timing,
scaled by the speed; at max they are not paced at all.

A subscriber on loopback notes when each event arrives; its offset from the first arrival is
compared with the recorded offset divided by the speed. The recorded gaps are uneven (20 ms to
0.5 s), so a replay that kept the order but not the spacing fails. The tolerance, 0.25 s on a
2.4 s replay, holds on a loaded 2-CPU machine (measured: 0.006 s at load 7; the sleeps are exact,
what varies is when the subscriber's thread gets to run). An ingest that subscribes after the
replay started must still get the recorded spacing (the clock used to start before the wait for
it, and the events due meanwhile went out in one burst: 0.5 s off here).
"""
from __future__ import annotations

import threading
import time

import orjson
import pytest

from sim_replay.replay import replay
from store import Store
from store.wire.contract import session_config
from tests.helpers.ingest_testkit import T0, free_endpoint, make_event

GAPS_MS = (0, 40, 500, 20, 300, 20, 20, 450, 100, 250, 60, 400, 30, 200)   # the recorded spacing
TOLERANCE_S = 0.25


def _store(tmp_path, run: str, stretch: int) -> Store:
    """One run: a vehicle's perceptions spaced GAPS_MS x stretch apart."""
    store = Store(tmp_path / f"{run}.db", durable=False)
    t = T0
    events = []
    for seq, gap in enumerate(GAPS_MS):
        t += gap * stretch * 1_000_000
        events.append({**make_event("vehicle/1", seq, run=run), "t": t})
    store.append(events)
    return store


class Arrivals:
    """A plain Zenoh subscriber listening on an endpoint: when each event's t arrived."""

    def __init__(self, endpoint: str, late_s: float = 0) -> None:
        self.seen: list[tuple[float, int]] = []
        self.lock = threading.Lock()
        self.session = self.sub = None
        self.opened = threading.Timer(late_s, self._open, [endpoint]) if late_s else None
        if self.opened:
            self.opened.start()
        else:
            self._open(endpoint)

    def _open(self, endpoint: str) -> None:
        import zenoh
        self.session = zenoh.open(session_config(listen=[endpoint]))
        self.sub = self.session.declare_subscriber("gaps/**", self._on)

    def _on(self, sample) -> None:
        arrived = time.monotonic()
        event = orjson.loads(sample.payload.to_bytes())
        with self.lock:
            self.seen.append((arrived, event["t"]))

    def offsets(self, n: int, timeout_s: float = 30.0) -> list[tuple[float, float]]:
        """(wall offset, recorded offset) of each of the n events, from the first."""
        deadline = time.monotonic() + timeout_s
        while len(self.seen) < n and time.monotonic() < deadline:
            time.sleep(0.02)
        with self.lock:
            seen = sorted(self.seen, key=lambda a: a[1])
        assert len(seen) == n, f"{len(seen)} of {n} events arrived"
        (a0, t0) = seen[0]
        return [(a - a0, (t - t0) / 1e9) for a, t in seen]

    def close(self) -> None:
        if self.opened:
            self.opened.join()
        self.sub.undeclare()
        self.session.close()


@pytest.mark.parametrize("speed, stretch, late_s", [(1.0, 1, 0), (10.0, 10, 0), (1.0, 1, 1.0)])
def test_replay_keeps_the_recorded_spacing_scaled_by_the_speed(tmp_path, speed, stretch, late_s):
    """late_s: the subscriber comes that long after the replay starts (it waits for one)."""
    endpoint = free_endpoint()
    arrivals = Arrivals(endpoint, late_s)
    try:
        with _store(tmp_path, "paced", stretch) as store:
            replay(store, ["paced"], connect=[endpoint], speed=speed, wait_s=10)
        offsets = arrivals.offsets(len(GAPS_MS))
    finally:
        arrivals.close()
    late = [(round(wall, 3), round(recorded / speed, 3)) for wall, recorded in offsets
            if abs(wall - recorded / speed) > TOLERANCE_S]
    worst = max(abs(wall - recorded / speed) for wall, recorded in offsets)
    print(f"speed {speed}, subscriber {late_s} s late: worst offset error {worst:.3f} s")
    assert not late, f"(arrived, due) off by more than {TOLERANCE_S} s: {late}"
    assert offsets[-1][0] >= offsets[-1][1] / speed - 0.05       # never ahead of the recording's time


def test_replay_at_max_speed_is_not_paced(tmp_path):
    endpoint = free_endpoint()
    arrivals = Arrivals(endpoint)
    try:
        with _store(tmp_path, "unpaced", 10) as store:          # 23.9 s of recorded time
            started = time.monotonic()
            replay(store, ["unpaced"], connect=[endpoint], speed=None, wait_s=10)
            took = time.monotonic() - started
        offsets = arrivals.offsets(len(GAPS_MS))
    finally:
        arrivals.close()
    recorded = offsets[-1][1]
    # paced, it would take the recorded 23.9 s; unpaced it takes the sessions' start and the puts (0.5-2.5 s on
    # a loaded two-core machine running the suite in two workers): half the recorded time tells the two apart
    assert recorded > 20 and offsets[-1][0] < 1.0 and took < recorded / 2, (offsets[-1], took)
