"""The whole simulation, publishing into a running ingest, against SUMO stepping alone in the same run.

Issue 13's target: 1,000 vehicles at 10 Hz at least as fast as real time on one core while publishing
everything into a running ingest; events/s, rulebook queries/s and SUMO's share of the time reported,
as a ratio to SUMO stepping alone measured in the same run.

    .venv/bin/python bench/sim.py [--vehicles 1000] [--seconds 60] [--seed 1] [--depart-within 0.1]

On bench/sumo_step.py's left-hand 10 x 10 signal grid (the paper's map holds a few hundred vehicles),
with two monitors at grid junctions (written beside the grid). In order, in this one process:

    sumo alone   N vehicles kept on the grid (sumo_step.Traffic), stepped with subscriptions for the
                 run's number of steps after they are all on: steps per second
    simulation   sim_replay.simulation with N vehicles set off within the first `depart-within` share
                 of the run, every event published over loopback Zenoh into an ingest in this process
                 that appends them to a store file; World.step timed inside it (SUMO's share)

Vehicles on the network are counted from the entity.state events published (per step, on average),
so the two loops are compared at the vehicle counts they really had.

Open (2026-11-25): the quick size runs (200 vehicles, 20 s: 4.1x real time, 7,316 events/s, SUMO's
step 23% of the time); the full size stalled after SUMO alone (64.3 steps/s = 6.4x real time with
1,000 vehicles), the process idle and the simulation not advancing. The same simulation in a fresh
process (no SUMO-alone loop before it), publishing into an ingest in that process, completed: 60 s
of world time, 357,664 events published in 55.6-70.9 s (1.08-0.85x real time), every one stored
(settled 11 s later). So the first suspect is libsumo started a second time in one process after a
large run; the fix is to measure SUMO alone in a child process.
"""
from __future__ import annotations

import argparse
import json
import os
import socket
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).parent))

from machine import machine  # noqa: E402
from results import Figure, quick, record  # noqa: E402
from sumo_step import STEP_S, Traffic, grid_net, sumo_loop  # noqa: E402

from sim_replay import sumo_world  # noqa: E402
from sim_replay.sim_config import SimConfig  # noqa: E402
from sim_replay.simulation import Simulation  # noqa: E402

MONITORS = [{"id": "g1", "junction": "B1", "x": 315.0, "y": 310.0, "heading_deg": 190.0, "range_m": 80.0, "fov_deg": 90.0},
            {"id": "g2", "junction": "C2", "x": 485.0, "y": 490.0, "heading_deg": 10.0, "range_m": 80.0, "fov_deg": 90.0}]


def sumo_alone(net: Path, vehicles: int, steps: int, seed: int) -> tuple[float, float]:
    """(steps per second, mean vehicles) of SUMO alone with N vehicles kept on the network."""
    with sumo_world.World(net, seed=seed, step_s=STEP_S) as world:
        traffic = Traffic(world, vehicles, seed)
        for _ in range(3000):
            snap = world.step()
            traffic.replace([a for a in snap.arrived if a.startswith("b")])
            if len(snap.vehicles) >= vehicles * 0.98:
                break
        rate, _, mean = sumo_loop(traffic, steps)
    return rate, mean


def simulation(net: Path, monitors: Path, args: argparse.Namespace) -> dict:
    """The simulation published into an ingest here; its wall time, events, queries, SUMO's share."""
    from ingest.service import IngestService
    from sim_replay.outlets import Outlets
    stepping = [0.0]
    real_step = sumo_world.World.step

    def timed_step(self):
        started = time.perf_counter()
        try:
            return real_step(self)
        finally:
            stepping[0] += time.perf_counter() - started

    sumo_world.World.step = timed_step
    config = SimConfig(run="bench-sim", seed=args.seed, net=str(net), monitors=str(monitors), vehicles=args.vehicles,
                       duration_s=args.seconds, depart_within=args.depart_within, pedestrians=0)
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        endpoint = f"tcp/127.0.0.1:{s.getsockname()[1]}"
    with tempfile.TemporaryDirectory(dir=os.environ.get("GAPS_BENCH_DIR", "/tmp")) as folder:
        try:
            with IngestService(Path(folder) / "sim.db", listen=[endpoint], durable=False) as ingest:
                started = time.perf_counter()
                sim = Simulation(config)
                with Outlets(connect=[endpoint]) as out:
                    for event in sim.events():
                        out.put(event)
                published = time.perf_counter() - started
                ingest.wait_until_settled(out.summary().published, 600)
                settled = time.perf_counter() - started
                stats = ingest.stats()
        finally:
            sumo_world.World.step = real_step
    summary = sim.summary
    states = summary.by_kind.get("entity.state", 0)
    return {"wall_s": published, "settled_s": settled, "events": summary.events, "stored": stats["stored"],
            "queries": summary.rulebook_queries, "sumo_s": stepping[0], "steps": round(args.seconds / STEP_S),
            "vehicles_mean": states / (args.seconds / STEP_S), "potential_violations": summary.potential_violations}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--vehicles", type=int, default=200 if quick() else 1000)
    ap.add_argument("--seconds", type=float, default=20.0 if quick() else 60.0, help="world seconds simulated")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--depart-within", type=float, default=0.1, help="share of the run over which vehicles set off")
    args = ap.parse_args()
    net = grid_net()
    monitors = net.with_name("grid10-lefthand.monitors.json")
    monitors.write_text(json.dumps({"monitors": MONITORS}), encoding="utf-8")
    steps = round(args.seconds / STEP_S)

    alone, alone_vehicles = sumo_alone(net, args.vehicles, steps, args.seed)
    print(f"SUMO alone: {alone:,.1f} steps/s with {alone_vehicles:,.0f} vehicles ({alone * STEP_S:.2f} x real time)",
          flush=True)
    got = simulation(net, monitors, args)
    sim_rate = steps / got["wall_s"]
    print(f"simulation: {args.seconds:g} s of world time in {got['wall_s']:.1f} s ({args.seconds / got['wall_s']:.2f} x "
          f"real time), {got['vehicles_mean']:,.0f} vehicles on the network on average; {got['events']:,} events "
          f"({got['events'] / got['wall_s']:,.0f}/s), {got['queries']:,} rulebook queries ({got['queries'] / got['wall_s']:,.0f}/s), "
          f"stored {got['stored']:,} (all settled after {got['settled_s']:.1f} s); SUMO's step "
          f"{got['sumo_s']:.1f} s = {got['sumo_s'] / got['wall_s']:.0%} of the time")
    print(f"ratio to SUMO alone: {sim_rate / alone:.2f} (simulation steps/s over SUMO-alone steps/s)")
    print(f"machine: {machine()}")
    figures = [
        Figure("SUMO alone", alone, "steps/s", note=f"{alone_vehicles:,.0f} vehicles kept on the grid"),
        Figure("the simulation, publishing into an ingest", sim_rate, "steps/s", peer="SUMO alone",
               note=f"{got['vehicles_mean']:,.0f} vehicles on average"),
        Figure("real-time factor of the simulation", args.seconds / got["wall_s"], "x real time",
               target=">= 1 at 1,000 vehicles, one core"),
        Figure("events published", got["events"] / got["wall_s"], "events/s"),
        Figure("rulebook queries", got["queries"] / got["wall_s"], "queries/s"),
        Figure("SUMO's share of the simulation's time", 100 * got["sumo_s"] / got["wall_s"], "%"),
    ]
    record("sim", "The whole simulation, publishing into a running ingest", figures,
           notes=f"grid10-lefthand, {args.vehicles:,} vehicles set off within {args.depart_within:.0%} of "
                 f"{args.seconds:g} s, seed {args.seed}, two monitors; an ingest in this process, store not durable",
           details={k: v for k, v in got.items()})


if __name__ == "__main__":
    main()
