"""`gaps scene` at a random t of the one-hour, 200-vehicle simulated run.

    .venv/bin/python bench/scene.py [--queries 200] [--rounds 2] [--dir /tmp/gaps-bench] [--json]

Issue 6's target: the scene at a random time, median <= 20 ms at 10 million events. Measured on
the store file bench/sim_runs.py records (the working copy bench/incidents.py judged; recorded if
missing) with reasoner.scene.scene, two ways, as `gaps scene` asks them:

    whole     scene(store, run, t): every vehicle present (about 200), signals, monitors; nothing judged
    vehicle   scene(store, run, t, vehicle=V), V a random vehicle present at t: its scenarios, action,
              who was in control, and the validator's answer on whether its action was lawful (one
              Prolog query)

Random t are drawn from a minute after the run's start (FILLED_NS), when vehicles are on their way.

The state snapshots the scene starts from are built first if missing (timed, not part of the
figures); then WARM_UP untimed queries, then --queries random t per way per round. One Store and
one Investigation (rulebooks loaded once) serve every query, as in a long-running reader.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import statistics
import time
from pathlib import Path
from typing import Any, Callable

from machine import machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file
from sim_runs import RUN, work_file  # bench/sim_runs.py, beside this file
from store import Store
from store.cache import snapshots
from store.state import build_snapshots

TARGET_MS = 20.0
WARM_UP = 30
FILLED_NS = 60_000_000_000   # random t from a minute in: the first vehicles are on their way by then


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def timed(call: Callable[[], Any]) -> tuple[float, float, Any]:
    started, cpu = time.perf_counter(), time.process_time()
    out = call()
    return (time.perf_counter() - started) * 1000, (time.process_time() - cpu) * 1000, out


def measure(store: Store, queries: int, seed: int) -> dict[str, Any]:
    from reasoner.investigation import Investigation
    from reasoner.scene import scene

    span = next(r for r in store.runs() if r.run == RUN)
    rng = random.Random(seed)
    investigation = Investigation(store)
    ts = [rng.randint(span.first_t + FILLED_NS, span.last_t) for _ in range(queries + WARM_UP)]
    out: dict[str, dict[str, list[float]]] = {"whole": {"wall": [], "cpu": []}, "vehicle": {"wall": [], "cpu": []}}
    sizes: list[int] = []
    for i, t in enumerate(ts):
        wall, cpu, whole = timed(lambda: scene(store, RUN, t))
        v = rng.choice(whole.vehicles).vehicle     # vehicles come and go: one present at t
        wall_v, cpu_v, _ = timed(lambda: scene(store, RUN, t, vehicle=v, investigation=investigation))
        if i >= WARM_UP:
            out["whole"]["wall"].append(wall)
            out["whole"]["cpu"].append(cpu)
            out["vehicle"]["wall"].append(wall_v)
            out["vehicle"]["cpu"].append(cpu_v)
            sizes.append(len(whole.vehicles))
    return {**out, "vehicles_in_scene": statistics.median(sizes), "events": span.events}


def summary(values: list[float]) -> dict[str, float]:
    return {"median_ms": statistics.median(values), "p90_ms": percentile(values, 0.9), "max_ms": max(values)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", type=Path, default=Path("/tmp/gaps-bench"))
    parser.add_argument("--queries", type=int, default=50 if quick() else 200)
    parser.add_argument("--rounds", type=int, default=1 if quick() else 2)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)
    path = work_file(args.dir, fresh=False)
    with Store(path, durable=False) as store:
        started = time.perf_counter()
        count = build_snapshots(store, RUN)
        built = time.perf_counter() - started
        if not args.json:
            print(f"{count:,} snapshots ({built:.0f} s to build what was missing)", flush=True)
        pooled: dict[str, dict[str, list[float]]] = {"whole": {"wall": [], "cpu": []},
                                                     "vehicle": {"wall": [], "cpu": []}}
        rounds = []
        for r in range(args.rounds):
            load_before = os.getloadavg()[0]
            result = measure(store, args.queries, args.seed + r)
            load_after = os.getloadavg()[0]
            rounds.append({"load_average": [round(load_before, 2), round(load_after, 2)],
                           **{way: summary(result[way]["wall"]) for way in ("whole", "vehicle")}})
            for way in pooled:
                for key in ("wall", "cpu"):
                    pooled[way][key] += result[way][key]
            if not args.json:
                print(f"round {r + 1}: load average {load_before:.2f} before, {load_after:.2f} after", flush=True)
                for way in ("whole", "vehicle"):
                    s = summary(result[way]["wall"])
                    print(f"  {way:>7}: median {s['median_ms']:6.2f} ms  p90 {s['p90_ms']:6.2f} ms  "
                          f"max {s['max_ms']:7.2f} ms  (CPU median {statistics.median(result[way]['cpu']):.2f} ms)")
        snapshot_count = snapshots.count(store, RUN)
    report = {
        "run": RUN, "events": result["events"], "file_bytes": path.stat().st_size, "snapshots": snapshot_count,
        "machine": machine(), "queries_per_round": args.queries, "rounds": rounds,
        "vehicles_in_scene": result["vehicles_in_scene"], "target_median_ms": TARGET_MS,
        **{way: {**summary(pooled[way]["wall"]), "cpu_median_ms": statistics.median(pooled[way]["cpu"])}
           for way in ("whole", "vehicle")},
    }
    record("scene", "gaps scene at a random time of the simulated run", [
        Figure("scene(store, run, t), the whole scene", report["whole"]["median_ms"], "ms",
               tuple(r["whole"]["median_ms"] for r in rounds), target=f"median ≤ {TARGET_MS:.0f} ms",
               note=f"p90 {report['whole']['p90_ms']:.1f} ms"),
        Figure("scene(..., vehicle=V), one vehicle, judged by the validator", report["vehicle"]["median_ms"], "ms",
               tuple(r["vehicle"]["median_ms"] for r in rounds), note=f"p90 {report['vehicle']['p90_ms']:.1f} ms")],
        notes=f"{RUN}: {report['events']:,} events, {report['vehicles_in_scene']:.0f} vehicles in a scene; "
              f"{args.rounds} round(s) of {args.queries} random t; runs are the rounds' medians")
    if args.json:
        print(json.dumps(report, indent=2))
        return
    print(f"machine: {report['machine']}")
    print(f"{RUN}: {report['events']:,} events, file {report['file_bytes'] / 1e9:.1f} GB, "
          f"{snapshot_count:,} snapshots; {report['vehicles_in_scene']:.0f} vehicles in a scene")
    print(f"all rounds ({args.rounds} x {args.queries} random t):")
    for way in ("whole", "vehicle"):
        s = report[way]
        verdict = "met" if s["median_ms"] <= TARGET_MS else "NOT met"
        print(f"  {way:>7}: median {s['median_ms']:6.2f} ms  p90 {s['p90_ms']:6.2f} ms  max {s['max_ms']:7.2f} ms  "
              f"(CPU median {s['cpu_median_ms']:.2f} ms); target median <= {TARGET_MS:.0f} ms: {verdict}")


if __name__ == "__main__":
    main()
