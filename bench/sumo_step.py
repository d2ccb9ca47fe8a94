"""SUMO stepping alone: N vehicles at 10 Hz, read by subscriptions, in this process through libsumo.

The simulation's target (DESIGN "Performance and reliability targets") is 1,000 vehicles at 10 Hz at
least as fast as real time on one core while publishing everything; this is its reference, SUMO's
own share measured alone, so that the full simulation can later be reported as a ratio to it:

    sumo alone        libsumo.simulationStep() with every vehicle subscribed (SUMO computes the
                      subscribed values inside the step) and the results fetched
    World.step        the same step through sim_replay.sumo_world: the tick as frozen snapshots
                      (positions, speeds, lanes, distance to the line, the light per approach)
    getters           the step with each value read by its own call per vehicle instead of
                      subscriptions (what the issue measured first), for comparison

The paper's map holds a few hundred vehicles at most, so the bench runs on a left-hand grid of
signal junctions that netgenerate builds (10 x 10 junctions 200 m apart, one lane each way at 30 mph;
built once into /tmp/gaps-bench), or on `--net FILE`. N vehicles drive seeded random routes; each that
arrives is replaced, so N stay on the network. The three loops take turns, `--runs` times each, after
a warm-up in which the N vehicles enter; each figure is the median.

    .venv/bin/python bench/sumo_step.py [--vehicles 1000] [--steps 600] [--runs 3] [--net FILE]
"""
from __future__ import annotations

import argparse
import os
import random
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import libsumo  # noqa: E402

from sim_replay.sumo_world import VEHICLE_VARS, World  # noqa: E402
from machine import machine  # noqa: E402  (bench/machine.py, beside this file)
from results import Figure, quick, record  # noqa: E402  (bench/results.py, beside this file)

STEP_S = 0.1
GRID = Path(os.environ.get("GAPS_BENCH_DIR", "/tmp/gaps-bench")) / "grid10-lefthand.net.xml"
tc = libsumo.constants


def grid_net() -> Path:
    """The benchmark's grid network, built with netgenerate once (deterministic: same bytes)."""
    if GRID.is_file():
        return GRID
    try:
        import sumo  # the eclipse-sumo wheel (the 'net' extra)
        netgenerate = str(Path(sumo.SUMO_HOME) / "bin" / "netgenerate")
    except ImportError:
        sys.exit("bench/sumo_step.py: netgenerate is needed to build the grid (pip install eclipse-sumo), or give --net")
    GRID.parent.mkdir(parents=True, exist_ok=True)
    subprocess.run([netgenerate, "--grid", "--grid.number", "10", "--grid.length", "200",
                    "--grid.attach-length", "100", "--default.lanenumber", "1", "--default.speed", "13.4112",
                    "--default-junction-type", "traffic_light", "--lefthand", "--no-turnarounds",
                    "--offset.disable-normalization", "--output-file", str(GRID)], check=True, capture_output=True)
    return GRID


class Traffic:
    """Keeps N vehicles on the network: seeded random routes between the grid's fringe edges, a new
    vehicle for each that arrives."""

    def __init__(self, world: World, n: int, seed: int) -> None:
        self.world, self.rng, self.count = world, random.Random(seed), 0
        net = world.network.net
        self.edges = sorted(e.getID() for e in net.getEdges(withInternal=False) if e.allows("passenger"))
        for _ in range(n):
            self.add(depart_pos="random")

    def add(self, depart_pos: str = "base") -> None:
        while True:
            a, b = self.rng.sample(self.edges, 2)
            try:
                route = self.world.route(a, b)
            except Exception:                 # unreachable pair: draw again
                continue
            if len(route) >= 4:
                break
        self.world.add_vehicle(f"b{self.count}", "car", route, depart_pos=depart_pos, depart_speed="max")
        self.count += 1

    def replace(self, arrived) -> None:
        for _ in arrived:
            self.add()


def world_loop(world: World, traffic: Traffic, steps: int) -> tuple[float, float, float]:
    """(steps per wall second, per CPU second, mean vehicles) stepping through World.step."""
    seen = 0
    wall, cpu = time.perf_counter(), time.process_time()
    for _ in range(steps):
        snap = world.step()
        seen += len(snap.vehicles)
        traffic.replace([a for a in snap.arrived if a.startswith("b")])
    return _rates(steps, wall, cpu) + (seen / steps,)


def sumo_loop(traffic: Traffic, steps: int, getters: bool = False) -> tuple[float, float, float]:
    """The same, straight on libsumo: the step, departures subscribed, the results fetched (or, with
    `getters`, each value read by its own call)."""
    seen = 0
    step, results = libsumo.simulationStep, libsumo.vehicle.getAllSubscriptionResults
    sim_results, subscribe = libsumo.simulation.getSubscriptionResults, libsumo.vehicle.subscribe
    v = libsumo.vehicle
    wall, cpu = time.perf_counter(), time.process_time()
    for _ in range(steps):
        step()
        sim = sim_results()
        for ident in sim[tc.VAR_DEPARTED_VEHICLES_IDS]:
            subscribe(ident, VEHICLE_VARS)
        if getters:
            ids = v.getIDList()
            for ident in ids:
                v.getPosition(ident), v.getAngle(ident), v.getSpeed(ident), v.getAcceleration(ident)
                v.getLaneID(ident), v.getLanePosition(ident), v.getSignals(ident)
            seen += len(ids)
        else:
            seen += len(results())
        traffic.replace(sim[tc.VAR_ARRIVED_VEHICLES_IDS])
    return _rates(steps, wall, cpu) + (seen / steps,)


def _rates(steps: int, wall: float, cpu: float) -> tuple[float, float]:
    return steps / (time.perf_counter() - wall), steps / max(time.process_time() - cpu, 1e-9)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--vehicles", type=int, default=200 if quick() else 1000)
    ap.add_argument("--steps", type=int, default=100 if quick() else 600, help="steps per timed run (0.1 s each)")
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--net", type=Path, default=None, help="a .net.xml (default: the generated grid)")
    args = ap.parse_args()
    net = args.net or grid_net()

    with World(net, seed=args.seed, step_s=STEP_S) as world:
        traffic = Traffic(world, args.vehicles, args.seed)
        warm = 0
        while True:                                  # until the N vehicles are all on the network
            snap = world.step()
            traffic.replace([a for a in snap.arrived if a.startswith("b")])
            warm += 1
            if len(snap.vehicles) >= args.vehicles * 0.98 or warm >= 3000:
                break
        print(f"warm-up: {warm} steps, {len(snap.vehicles)} vehicles on {net.name}", flush=True)
        runs: dict[str, list[tuple[float, float, float]]] = {"sumo": [], "world": [], "getters": []}
        for n in range(args.runs):
            runs["sumo"].append(sumo_loop(traffic, args.steps))
            runs["world"].append(world_loop(world, traffic, args.steps))
            runs["getters"].append(sumo_loop(traffic, args.steps, getters=True))
            print(f"run {n + 1}: " + ", ".join(f"{k} {r[-1][0]:,.1f} steps/s ({r[-1][2]:,.0f} vehicles)"
                                               for k, r in runs.items()), flush=True)
        version = libsumo.getVersion()[1]

    def median(key: str, i: int = 0) -> float:
        return statistics.median(r[i] for r in runs[key])

    vehicles = statistics.median(r[2] for rs in runs.values() for r in rs)
    load = f"load average {', '.join(f'{x:.2f}' for x in os.getloadavg())}"
    print(f"machine: {machine()}, {version}, {load}")
    labels = {"sumo": f"SUMO alone: simulationStep + subscriptions, {args.vehicles:,} vehicles",
              "world": "World.step: the step and its snapshot",
              "getters": "SUMO with per-vehicle getters instead of subscriptions"}
    figures = []
    for key in ("sumo", "world", "getters"):
        rate = median(key)
        print(f"{labels[key]:62s} {rate:8,.1f} steps/s = {rate * STEP_S:6.2f} x real time at 10 Hz "
              f"(runs {', '.join(f'{r[0]:,.1f}' for r in runs[key])}; {median(key, 1):,.1f} per CPU second)")
        figures.append(Figure(labels[key], rate, "steps/s", tuple(r[0] for r in runs[key]),
                              peer="" if key == "sumo" else labels["sumo"],
                              note=f"{rate * STEP_S:.2f} x real time at 10 Hz; {median(key, 1):,.1f} steps per CPU second"))
    figures.append(Figure("real-time factor of World.step", median("world") * STEP_S, "x real time",
                          tuple(r[0] * STEP_S for r in runs["world"]),
                          target="the whole simulation, publishing: >= 1 at 1,000 vehicles, one core",
                          note="SUMO's share of the simulation's budget; the agents and publishing come on top"))
    record("sumo_step", "SUMO stepping alone (the simulation's reference)", figures,
           machine_extra=f"{version}, {load}",
           notes=f"{net.name}: {vehicles:,.0f} vehicles on average, 0.1 s steps, seed {args.seed}; "
                 f"{args.runs} runs of {args.steps} steps per figure, taking turns",
           details={"vehicles": args.vehicles, "vehicles_mean": vehicles, "steps": args.steps, "net": net.name,
                    "warm_up_steps": warm})


if __name__ == "__main__":
    main()
