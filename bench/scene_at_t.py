"""Scene at a random t: state_at latency at 100 thousand, 1 million and 10 million events.

    .venv/bin/python bench/scene_at_t.py [--sizes 100k,1m,10m] [--queries 200] [--dir /tmp/gaps-bench]

DESIGN's target: median <= 5 ms at 10 million events, growing sub-linearly. Each size is the first
N events of the simulated run of bench/sim_runs.py (the town map, about 200 vehicles through the
hour; recorded if missing), copied into a store file of its own: entity.state at 10 Hz, the
monitors' observations, perceptions, decisions and traces, signals, ADS events. A size larger than
the run is the whole run (the figure names the events it really has). The files are made once and
kept under --dir with their snapshots, named after the run they are cut from; later runs reuse
them. A file is renamed into place only when complete, so an interrupted copy is simply redone.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import random
import resource
import statistics
import time
from itertools import islice
from pathlib import Path
from typing import Any

from store import State, Store
from store.cache import snapshots
from store.state import SNAPSHOT_EVERY, build_snapshots, state_at
from machine import calibration, machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file
from sim_runs import RUN, recorded  # bench/sim_runs.py, beside this file

WARM_UP = 30  # untimed queries before the timed ones
SIZES = {"100k": 100_000, "1m": 1_000_000, "10m": 10_000_000}
BATCH = 50_000


def store_file(directory: Path, label: str, n: int) -> Path:
    """The cached file for a size, cut from the recorded run if missing."""
    base = recorded(directory)
    path = directory / f"scene-{label}-{base.stem}.db"
    if path.exists():
        return path
    partial = path.with_suffix(".partial")
    for leftover in directory.glob(partial.name + "*"):
        leftover.unlink()
    started = time.perf_counter()
    with Store.open_read_only(base) as source, Store(partial, durable=False) as store:
        batch: list[dict[str, Any]] = []
        for ev in islice(source.events(RUN), n):
            batch.append(ev)
            if len(batch) == BATCH:
                store.append(batch, origin="bench")
                batch.clear()
        store.append(batch, origin="bench")
        copied = store.count(RUN)
        assert copied == min(n, source.count(RUN))
    if partial.with_name(partial.name + "-wal").exists():
        raise SystemExit(f"{partial} was not checkpointed on close; not renaming it")
    partial.rename(path)
    print(f"  cut {label}: the first {copied:,} events of {RUN} in {time.perf_counter() - started:.0f} s")
    return path


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def prepare(path: Path, every: int) -> tuple[int, float]:
    """Snapshots every `every` events: kept from an earlier run if they have that spacing."""
    with Store(path, durable=False) as store:
        if snapshots.count(store, RUN) != store.count(RUN) // every:
            snapshots.clear(store)
        started = time.perf_counter()
        count = build_snapshots(store, RUN, every=every)
        return count, time.perf_counter() - started


def measure(path: Path, queries: int, seed: int) -> dict[str, Any]:
    """Wall and CPU time (ms) of state_at at random t, as a reader process sees it: one store
    open, queries one after another, WARM_UP untimed ones first, so that the allocator and caches settle."""
    with Store(path, durable=False) as store:
        span = store.runs()[0]
        rng = random.Random(seed)
        ts = [rng.randint(span.first_t, span.last_t) for _ in range(queries + WARM_UP)]
        wall: list[float] = []
        cpu: list[float] = []
        faults: list[int] = []
        for i, t in enumerate(ts):
            started, started_cpu, faulted = time.perf_counter(), time.process_time(), minor_faults()
            scene = state_at(store, RUN, t)
            if i >= WARM_UP:
                wall.append((time.perf_counter() - started) * 1000)
                cpu.append((time.process_time() - started_cpu) * 1000)
                faults.append(minor_faults() - faulted)
        return {"wall": wall, "cpu": cpu, "faults": faults, "events": span.events, "scene": scene,
                "snapshots": snapshots.count(store, RUN), "snapshot_bytes": snapshots.disk_bytes(store, RUN),
                "file_bytes": path.stat().st_size}


def measure_apart(path: Path, queries: int, seed: int) -> dict[str, Any]:
    """measure() in a fresh process, as a reader would be: reading one file after another in
    the same process left the allocator in a state that cost the later files page faults."""
    with multiprocessing.get_context("spawn").Pool(1) as pool:
        return pool.apply(measure, (path, queries, seed))


def minor_faults() -> int:
    """Pages this process has faulted in: on a virtual machine each can cost tens of µs."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_minflt


def timing(r: dict[str, Any]) -> str:
    wall = r["wall"]
    return (f"median {statistics.median(wall):5.2f} ms  p90 {percentile(wall, 0.9):5.2f} ms  "
            f"max {max(wall):6.2f} ms  (CPU median {statistics.median(r['cpu']):.2f} ms, "
            f"page faults median {statistics.median(r['faults']):.0f})")


def pieces(scene: State) -> int:
    """How many cited pieces a scene holds: its size as the reader sees it."""
    entity = sum(1 for record in scene.entities.values() for value in record.values() if value)
    seen = sum(len(m["observations"]) + len(m["potential_violations"]) for m in scene.monitors.values())
    signals = sum(len(approaches) for approaches in scene.signals.values())
    return entity + seen + signals




def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="100k" if quick() else "100k,1m,10m",
                        help=f"comma-separated, of {', '.join(SIZES)}")
    parser.add_argument("--queries", type=int, default=50 if quick() else 200)
    parser.add_argument("--dir", type=Path, default=Path("/tmp/gaps-bench"))
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--every", type=int, default=SNAPSHOT_EVERY, help="events between snapshots")
    parser.add_argument("--rounds", type=int, default=1 if quick() else 3,
                        help="rounds, each reported: the machine may be shared")
    args = parser.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)
    print(f"scene at t: {args.queries} random t per size, a snapshot every {args.every} events")
    print(f"machine: {machine()}")
    paths = {}
    for label in args.sizes.split(","):
        paths[label] = store_file(args.dir, label, SIZES[label])
        count, built = prepare(paths[label], args.every)
        print(f"  {label}: {count:,} snapshots ({built:.0f} s to build what was missing)", flush=True)
    pooled: dict[str, dict[str, Any]] = {}
    round_medians: dict[str, list[float]] = {}
    labels = list(paths)
    for round_ in range(args.rounds):
        load, before = os.getloadavg()[0], calibration()
        order = labels[round_ % len(labels):] + labels[:round_ % len(labels)]  # no size always goes first
        results = {label: measure_apart(paths[label], args.queries, args.seed + round_) for label in order}
        print(f"round {round_ + 1}: load average {load:.2f} before, {os.getloadavg()[0]:.2f} after; "
              f"calibration {before:.2f} ms before, {calibration():.2f} ms after")
        for label in labels:
            r = results[label]
            print(f"  {label:>4}: {timing(r)}")
            round_medians.setdefault(label, []).append(statistics.median(r["wall"]))
            into = pooled.setdefault(label, {**r, "wall": [], "cpu": [], "faults": []})
            for key in ("wall", "cpu", "faults"):
                into[key] += r[key]
    print(f"all rounds ({args.rounds} x {args.queries} random t per size):")
    for label, r in pooled.items():
        scene = r["scene"]
        print(f"  {label:>4}: {r['events']:>10,} events  {timing(r)}")
        events_only = (r["file_bytes"] - r["snapshot_bytes"]) / r["events"]
        print(f"        scene of {len(scene.entities)} entities, {pieces(scene)} pieces; "
              f"file {r['file_bytes'] / 1e6:,.0f} MB: {events_only:.0f} B/event for the log, "
              f"{r['snapshot_bytes'] / r['events']:.0f} B/event for {r['snapshots']:,} snapshots")
    if "100k" in pooled and "10m" in pooled:
        growth = statistics.median(pooled["10m"]["wall"]) / statistics.median(pooled["100k"]["wall"])
        print(f"growth of the median 100k -> 10m (100x the events): {growth:.2f}x")
    record_result(pooled, round_medians, args)


def record_result(pooled: dict[str, dict[str, Any]], round_medians: dict[str, list[float]],
                  args: argparse.Namespace) -> None:
    """Each size's median into bench/results.json; the largest size has the smallest as its peer,
    so that its ratio is the growth of the median."""
    labels = list(pooled)
    figures = []
    for label, r in pooled.items():
        events_only = (r["file_bytes"] - r["snapshot_bytes"]) / r["events"]
        figures.append(Figure(
            f"state_at, {r['events']:,} events", statistics.median(r["wall"]), "ms", tuple(round_medians[label]),
            target="median ≤ 5 ms at 10 million events" if label == "10m" else "",
            peer=f"state_at, {pooled[labels[0]]['events']:,} events" if label != labels[0] else "",
            note=f"p90 {percentile(r['wall'], 0.9):.1f} ms; file {r['file_bytes'] / 1e6:,.0f} MB "
                 f"({events_only:.0f} + {r['snapshot_bytes'] / r['events']:.0f} B/event)"))
    record("scene_at_t", "State at a random time (store.state_at)", figures,
           notes=f"{args.rounds} round(s) of {args.queries} random t per size, a fresh reader process per size, "
                 f"a snapshot every {args.every} events; runs are the rounds' medians")


if __name__ == "__main__":
    main()
