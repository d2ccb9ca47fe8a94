"""A burst into an ingest, drained, in a process of its own: the resident memory it leaves behind.

    python -m tests.helpers.drained_burst RUNS EVENTS_PER_RUN BATCH DB

An IngestService in this process takes a burst of RUNS short runs (EVENTS_PER_RUN events each, 10
sources, each run ended by its run.end) from a second Zenoh session put with BLOCK congestion
control, as a fleet's producer puts them. The writer's first commit waits until the whole burst has
been put, so the burst waits in the ingest's queue whole, as it does behind a busy writer. The
writer's batches are of BATCH samples, without fsync (a test keeps the interpreter's share, which
grows with a batch, small beside the queue's, and quick). Printed
(JSON): the resident memory once the ingest was warm and quiet before the burst, and once every
event is stored and the ingest has been quiet for twice QUIET_S (when it gives memory back, ingest/idle_memory.py),
and what the store counted. Only this process is changed (Store.append_candidates wrapped here).
"""
from __future__ import annotations

import json
import multiprocessing as mp
import sys
import threading
import time
from pathlib import Path

import zenoh

from ingest import IngestService
from ingest.idle_memory import QUIET_S
from sim_replay.publisher import zenoh_config
from store import Store
from store.canonical import canonical_json
from tests.helpers.ingest_testkit import free_endpoint, make_event

SOURCES = 10
_put_all = threading.Event()
_original = Store.append_candidates


def _held_append(self: Store, candidates):
    """The store's append, once the burst has been put (the first waits for it)."""
    _put_all.wait(120)
    return _original(self, candidates)


def rss_mb() -> float:
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    raise RuntimeError("no VmRSS in /proc/self/status")


def burst(runs: int, per_run: int, first: int = 0) -> list[tuple[str, bytes]]:
    """RUNS runs of `per_run` events over SOURCES sources, the last one its run.end."""
    items = []
    for n in range(first, first + runs):
        run = f"burst-{n:05d}"
        for i in range(per_run - 1):
            event = make_event(f"vehicle/{i % SOURCES}", i // SOURCES, "entity.state", run=run, x=float(i))
            items.append((event, event["kind"]))
        end = make_event("sim/burst", 0, "entity.state", run=run)
        end.update(kind="run.end", body={"reason": "end of the burst"})
        items.append((end, "run.end"))
    return [(f"gaps/{e['run']}/{e['src']}/{kind}", canonical_json(e)) for e, kind in items]


def settled(ingest: IngestService, total: int, timeout: float = 120.0) -> dict:
    """The ingest's counts once `total` samples have an outcome and it has been quiet for 2 x QUIET_S."""
    deadline = time.monotonic() + timeout
    while True:
        stats = ingest.stats()
        if sum(stats[k] for k in ("stored", "duplicates", "rejected", "failed")) >= total:
            time.sleep(2 * QUIET_S + 0.5)
            return ingest.stats()
        if time.monotonic() > deadline:
            raise TimeoutError(f"{total} samples not settled: {stats}")
        time.sleep(0.05)


def main() -> None:
    runs, per_run, batch, db = int(sys.argv[1]), int(sys.argv[2]), int(sys.argv[3]), sys.argv[4]
    Store.append_candidates = _held_append
    endpoint = free_endpoint()
    ingest = IngestService(db, listen=[endpoint], batch_size=batch, durable=False)
    ctx = mp.get_context("spawn")
    go, put_all = ctx.Event(), ctx.Event()
    producer = ctx.Process(target=produce, args=(endpoint, runs, per_run, go, put_all), daemon=True)
    producer.start()
    try:
        _put_all.set()
        warm = 20 * per_run                    # the ingest's own warm-up (its first runs), before the idle figure
        settled(ingest, warm)
        idle = rss_mb()
        _put_all.clear()
        go.set()
        if not put_all.wait(120):
            raise TimeoutError("the producer did not put its burst")
        _put_all.set()
        stats = settled(ingest, warm + runs * per_run)
        print(json.dumps({"idle_mb": idle, "after_mb": rss_mb(), "burst": runs * per_run, **{
            k: stats[k] for k in ("received", "stored", "duplicates", "rejected", "failed")}}))
    finally:
        producer.join(30)
        ingest.stop()


def produce(endpoint: str, runs: int, per_run: int, go, put_all) -> None:
    """The producer's process: 20 runs to warm the ingest, then, on `go`, the burst."""
    session = zenoh.open(zenoh_config(connect=[endpoint]))
    try:
        time.sleep(1.0)                        # the subscription reached this session
        put(session, burst(20, per_run, first=runs))
        items = burst(runs, per_run)
        go.wait(120)
        put(session, items)
        put_all.set()
        time.sleep(1.0)                        # the last samples leave before the session closes
    finally:
        session.close()


def put(session: zenoh.Session, items: list[tuple[str, bytes]]) -> None:
    for key, payload in items:
        session.put(key, payload, encoding=zenoh.Encoding.APPLICATION_JSON,
                    congestion_control=zenoh.CongestionControl.BLOCK)


if __name__ == "__main__":
    main()
