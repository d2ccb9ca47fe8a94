"""Scene at a random t: state_at latency at 100 thousand, 1 million and 10 million events.

    .venv/bin/python bench/scene_at_t.py [--sizes 100k,1m,10m] [--queries 200] [--dir /tmp/gaps-bench]

DESIGN's target: median <= 5 ms at 10 million events, growing sub-linearly. Each size is one
synthetic run of DESIGN's catalogue: 200 vehicles around a square of four light-controlled
junctions, entity.state at 10 Hz, a perception and a decision per vehicle per second, ADS
hand-overs, signals cycling, a monitor per junction observing the vehicles in its range. The
store files are generated once (the 10-million-event one takes several minutes) and kept under
--dir with their snapshots; later runs reuse them. A file is renamed into place only when
complete, so an interrupted generation is simply redone.
"""

from __future__ import annotations

import argparse
import hashlib
import math
import multiprocessing
import os
import random
import resource
import statistics
import time
from pathlib import Path
from typing import Any, Iterator

from store import State, Store
from store import snapshots
from store.state import SNAPSHOT_EVERY, build_snapshots, state_at
from machine import calibration, machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file

RUN = "bench-scene"
T0 = 1_732_184_100_000_000_000
SECOND = 1_000_000_000
VEHICLES = 200
SIDE = 400.0  # metres between neighbouring junctions
LOOP = 4 * SIDE
MONITOR_RANGE = 50.0
GENERATOR = 3  # bump when the synthetic run changes, so cached files are regenerated
WARM_UP = 30  # untimed queries before the timed ones
SIZES = {"100k": 100_000, "1m": 1_000_000, "10m": 10_000_000}
RULEBOOK = "hashed only: the bench needs a sha256 to cite"
RULEBOOK_SHA = hashlib.sha256(RULEBOOK.encode()).hexdigest()

# Junction i sits at corner i of the square, reached after i sides of the loop.
CORNERS = [(0.0, 0.0), (SIDE, 0.0), (SIDE, SIDE), (0.0, SIDE)]
JUNCTIONS = [f"J{i + 1}" for i in range(4)]
HEADINGS = [0.0, 90.0, 180.0, 270.0]  # of the side that leaves corner i
APPROACHES = ["north", "east", "south", "west"]
CYCLE = [("green", 20), ("amber", 3), ("red", 23)]  # seconds; north/south, east/west offset by half


# --- the synthetic world ------------------------------------------------------------------------


def world_map() -> dict[str, Any]:
    roads = [{"id": f"R{i + 1}", "from": list(CORNERS[i]), "to": list(CORNERS[(i + 1) % 4])} for i in range(4)]
    junctions = [{"id": j, "x": x, "y": y, "control": "lights"} for j, (x, y) in zip(JUNCTIONS, CORNERS)]
    monitors = [
        {"id": f"m{i + 1}", "junction": j, "x": x + 5, "y": y + 5, "heading_deg": 225.0,
         "range_m": MONITOR_RANGE, "fov_deg": 360.0}
        for i, (j, (x, y)) in enumerate(zip(JUNCTIONS, CORNERS))
    ]
    return {"roads": roads, "junctions": junctions, "monitors": monitors}


def place(distance: float) -> tuple[float, float, float, int]:
    """Position on the loop: x, y, heading and the side (= index of the corner it left)."""
    distance %= LOOP
    side, along = int(distance // SIDE), distance % SIDE
    (x0, y0), (x1, y1) = CORNERS[side], CORNERS[(side + 1) % 4]
    f = along / SIDE
    return x0 + (x1 - x0) * f, y0 + (y1 - y0) * f, HEADINGS[side], side


def colour(junction: int, approach: int, second: int) -> str:
    """Fixed-time signal plan: approaches 0/2 and 1/3 alternate, junctions staggered."""
    period = sum(d for _, d in CYCLE)
    phase = (second + junction * 7 + (approach % 2) * period // 2) % period
    for name, duration in CYCLE:
        if phase < duration:
            return name
        phase -= duration
    return "red"


class Vehicle:
    def __init__(self, ident: int, rng: random.Random) -> None:
        self.id = str(ident)
        self.src = f"vehicle/{ident}"
        self.start = rng.uniform(0, LOOP)
        self.speed = round(rng.uniform(7.0, 14.0), 2)  # as a speedometer would report it
        self.autonomous = rng.random() < 0.6
        self.engaged = False
        self.type = "ambulance" if ident % 50 == 7 else "bus" if ident % 20 == 3 else "car"


class Events:
    """Numbers each source's events from 0, as the envelope requires."""

    def __init__(self) -> None:
        self.seqs: dict[str, int] = {}

    def __call__(self, src: str, t: int, kind: str, body: dict[str, Any]) -> dict[str, Any]:
        seq = self.seqs[src] = self.seqs.get(src, -1) + 1
        return {"v": 1, "run": RUN, "src": src, "seq": seq, "t": t, "kind": kind, "body": body}


def synthetic_run(n: int, seed: int = 7) -> Iterator[dict[str, Any]]:
    """The first n events of the synthetic run, in time order."""
    rng = random.Random(seed)
    vehicles = [Vehicle(i, rng) for i in range(VEHICLES)]
    start = {"map": world_map(), "seed": seed, "config": {"generator": GENERATOR},
             "rulebooks": [{"name": "bench", "version": "1", "sha256": RULEBOOK_SHA, "text": RULEBOOK}]}
    for produced, ev in enumerate(_run_events(vehicles, Events(), start), 1):
        yield ev
        if produced == n:
            return


def _run_events(vehicles: list[Vehicle], event: Events, start: dict[str, Any]) -> Iterator[dict[str, Any]]:
    yield event("sim/world", T0, "run.start", start)
    for v in vehicles:
        body = {"type": v.type, "driver": "autonomous" if v.autonomous else "human",
                "automation_level": 4 if v.autonomous else 0, "plate": f"BN{int(v.id):03d}AV",
                "emergency": v.type == "ambulance"}
        yield event(v.src, T0 + int(v.id) * 1000 + 1, "entity.spawn", body)
        if v.autonomous:
            v.engaged = True
            yield event(v.src, T0 + int(v.id) * 1000 + 2, "ads.event", {"event": "activated"})
    tick = 0
    while True:
        yield from _tick(vehicles, event, tick)
        tick += 1


def _tick(vehicles: list[Vehicle], event: Events, tick: int) -> Iterator[dict[str, Any]]:
    """Everything published in one 100 ms tick."""
    t = T0 + SECOND + tick * SECOND // 10  # a second after the spawns
    second, whole = divmod(tick, 10)
    if whole == 0:
        yield from _signals(event, t, second)
    for v in vehicles:
        vt = t + (int(v.id) + 1) * 1000  # after the signals, spread over the tick
        x, y, heading, side = place(v.start + v.speed * tick / 10)
        corner = min(range(4), key=lambda c: math.dist((x, y), CORNERS[c]))
        near = math.dist((x, y), CORNERS[corner])
        junction = JUNCTIONS[corner] if near < 15 else None
        body = {"x": round(x, 2), "y": round(y, 2), "heading_deg": heading, "speed_mps": v.speed,
                "road": f"R{side + 1}", "junction": junction}
        yield event(v.src, vt, "entity.state", body)
        if whole == int(v.id) % 10:
            light = colour(corner, side, second)
            yield from _vehicle_second(v, event, vt + 10, light, junction)
            if near < MONITOR_RANGE:
                monitor = f"monitor/m{corner + 1}"
                facts = [f"{v.id} has {light} light", f"{v.id} has speed of {round(v.speed * 2.237)}"]
                if junction:
                    facts.append(f"{v.id} is in the junction")
                seen = {"vehicle": v.id, "facts": facts, "speed_mps": v.speed, "x": body["x"], "y": body["y"]}
                yield event(monitor, vt + 20, "monitor.observation", seen)
            if v.autonomous:
                yield from _handover(v, event, vt + 30, second)


def _vehicle_second(v: Vehicle, event: Events, t: int, light: str, junction: str | None) -> Iterator[dict]:
    """A vehicle's perception and decision, once a second."""
    facts = [f"{v.id} is of type {v.type}", f"{v.id} has {light} light",
             f"{v.id} has speed of {round(v.speed * 2.237)}"]
    if v.engaged:
        facts.append(f"{v.id} is driving itself")
    if junction:
        facts.append(f"{v.id} is in the junction")
    yield event(v.src, t, "vehicle.perception", {"facts": facts})
    permitted = light == "green"
    yield event(v.src, t + 1, "vehicle.decision",
                {"goal": f"{v.id} can enter the junction", "action": "enter the junction",
                 "permitted": permitted, "proceeds": permitted, "rulebook": RULEBOOK_SHA})


def _handover(v: Vehicle, event: Events, t: int, second: int) -> Iterator[dict[str, Any]]:
    """Every ten minutes each automated vehicle asks its driver to take over, who does, and
    hands back a minute later."""
    phase = (second + int(v.id) * 3) % 600
    if phase == 0:
        yield event(v.src, t, "ads.event", {"event": "transition_demand", "reason": "end of ODD"})
    elif phase == 5:
        v.engaged = False
        yield event(v.src, t, "ads.event", {"event": "driver_override"})
    elif phase == 60:
        v.engaged = True
        yield event(v.src, t, "ads.event", {"event": "activated"})


def _signals(event: Events, t: int, second: int) -> Iterator[dict[str, Any]]:
    """Each junction reports an approach when its colour changes, and all of them every 5 s."""
    for j, junction in enumerate(JUNCTIONS):
        for a, approach in enumerate(APPROACHES):
            now = colour(j, a, second)
            if second % 5 == 0 or now != colour(j, a, second - 1):
                yield event(f"signal/{junction}", t + j, "signal.state",
                            {"junction": junction, "approach": approach, "colour": now})


# --- the store files ------------------------------------------------------------------------------


def store_file(directory: Path, label: str, n: int) -> Path:
    """The cached file for a size, generated if missing."""
    path = directory / f"scene-{label}-g{GENERATOR}.db"
    if path.exists():
        return path
    partial = path.with_suffix(".partial")
    for leftover in directory.glob(partial.name + "*"):
        leftover.unlink()
    started = time.perf_counter()
    with Store(partial, durable=False) as store:
        batch: list[dict[str, Any]] = []
        for ev in synthetic_run(n):
            batch.append(ev)
            if len(batch) == 50_000:
                store.append(batch, origin="bench")
                batch.clear()
        store.append(batch, origin="bench")
        assert store.count(RUN) == n
    if partial.with_name(partial.name + "-wal").exists():
        raise SystemExit(f"{partial} was not checkpointed on close; not renaming it")
    partial.rename(path)
    print(f"  generated {label}: {n:,} events in {time.perf_counter() - started:.0f} s")
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
