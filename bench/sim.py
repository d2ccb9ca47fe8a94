"""The whole simulation, publishing into a running ingest, against SUMO stepping alone in the same run.

Issue 13's target: 1,000 vehicles at 10 Hz at least as fast as real time on one core while publishing
everything into a running ingest; events/s, rulebook queries/s and SUMO's share of the time reported,
as a ratio to SUMO stepping alone measured in the same run.

    .venv/bin/python bench/sim.py [--vehicles 1120] [--warmup 60] [--seconds 60] [--seed 1]

On bench/sumo_step.py's left-hand 10 x 10 signal grid (the paper's map holds a few hundred vehicles),
with two monitors at grid junctions (written beside the grid). Three processes, one after another
or side by side:

    sumo alone   a child process on CPU 0: SUMO stepping alone with the simulation's own traffic
                 (`sumo_same`: the same config's departures, routes, types and seed, each put on
                 the network at the simulation's step; no agents, no events, no publishing),
                 stepped with the simulation's subscriptions through the same warm-up, the same
                 window timed: the reference of issue 40's ratio, run before the simulation and
                 after it, each figure the mean of the two. Between the first and the
                 simulation, in another child, the earlier reference (`sumo_alone`: N vehicles
                 of sumo_step.Traffic's random routes kept on the grid), reported beside it.
                 (Children, because libsumo started a second time in one process after a large
                 run stalled.)
    ingest       a child process on CPU 1, as `gaps serve` runs: IngestService listening on a
                 loopback port, appending to a store file (not durable); it reports what it stored
    simulation   this process, on CPU 0 (and Zenoh's threads with it): sim_replay.simulation with
                 N vehicles set off over the warm-up, every event published over Zenoh to the
                 ingest; only the window after the warm-up is timed (wall and CPU), World.step
                 timed inside it (SUMO's share)

Vehicles on the network are counted from the entity.state events of the window (per step, on
average), so the two loops are compared at the vehicle counts they really had. Where the machine is
shared, the wall figure carries the neighbours' load; the CPU figure (world seconds per CPU second
of the simulation's process) is what a core of its own would give, and the ratio by CPU time
(steps per CPU second of the simulation's process over those of SUMO alone's with the same traffic)
is issue 40's ratio without that load; the same by the main thread's CPU alone is printed beside
it. Fails if any published event was not stored.

Where the window's time goes is printed per phase, so that a slow run says why: the wall clock split
between SUMO's step, the simulation's own work (agents, monitors, events) and the outlets' put
(canonical JSON, Zenoh, the producer's cache); the main thread's wall split by the kernel's
scheduler statistics into running, waiting for the CPU (its neighbours: other processes on the
core, Zenoh's threads) and sleeping (a BLOCK put waiting for the ingest, the GIL); and the CPU of
the process's other threads (Zenoh's).
"""
from __future__ import annotations

import argparse
import json
import os
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).parent))

from machine import QUIET_MS, calibration_elsewhere, machine  # noqa: E402
from results import Figure, quick, record  # noqa: E402
from sumo_step import STEP_S, Traffic, grid_net, sumo_loop  # noqa: E402

from sim_replay import sumo_world  # noqa: E402
from sim_replay.sim_config import SimConfig  # noqa: E402
from sim_replay.simulation import Simulation  # noqa: E402

MONITORS = [{"id": "g1", "junction": "B1", "x": 315.0, "y": 310.0, "heading_deg": 190.0, "range_m": 80.0, "fov_deg": 90.0},
            {"id": "g2", "junction": "C2", "x": 485.0, "y": 490.0, "heading_deg": 10.0, "range_m": 80.0, "fov_deg": 90.0}]


def pin(cpu: int) -> str:
    """Keep this process (and the threads it starts from now on) on one CPU, when there are two or
    more: the target is "on one core", and the ingest is another process on another core."""
    if (os.cpu_count() or 1) < 2 or not hasattr(os, "sched_setaffinity"):
        return "not pinned (one CPU)"
    os.sched_setaffinity(0, {cpu})
    return f"pinned to CPU {cpu}"


def sumo_alone(net: Path, vehicles: int, steps: int, seed: int) -> dict:
    """Steps per second and mean vehicles of SUMO alone with N vehicles kept on the network (run in a
    child process: libsumo started twice in one process after a large run stalled the second)."""
    pin(0)
    with sumo_world.World(net, seed=seed, step_s=STEP_S) as world:
        traffic = Traffic(world, vehicles, seed)
        for _ in range(3000):
            snap = world.step()
            traffic.replace([a for a in snap.arrived if a.startswith("b")])
            if len(snap.vehicles) >= vehicles * 0.98:
                break
        rate, cpu_rate, mean = sumo_loop(traffic, steps)
    return {"steps_per_s": rate, "steps_per_cpu_s": cpu_rate, "vehicles_mean": mean}


def sim_config(net: Path, monitors: Path, args: argparse.Namespace) -> SimConfig:
    """The simulation's config: the one the simulation runs and the same-traffic reference drives."""
    return SimConfig(run="bench-sim", seed=args.seed, net=str(net), monitors=str(monitors), vehicles=args.vehicles,
                     duration_s=args.warmup + args.seconds, depart_within=args.depart_within, pedestrians=0)


def sumo_same(net: Path, monitors: Path, args: argparse.Namespace, log: list | None = None) -> dict:
    """SUMO stepping alone with the simulation's own traffic (the fair reference): the same config's
    departures (sim_replay.demand.plan from the same seed's "demand" stream), each put on the
    network at the step the simulation puts it there, on the route SUMO's router gives it, with the
    same type, departure position and speed, as Simulation._add does; SUMO started as World starts
    it for the simulation (the same options, traffic lights subscribed). No agents (SUMO's own
    drivers obey the lights and right of way: nobody is held, sped up or slowed), no events, no
    publishing. Each step is what the simulation's world step asks of SUMO: simulationStep, the
    departures subscribed, the vehicles' and lights' subscription results fetched. The warm-up is
    stepped untimed; the window's steps are timed by wall, process and thread CPU, as the
    simulation's are. Run in a child process on CPU 0, as the simulation runs. `log`, if given, gets
    (step, id, type, route) of each vehicle put on the network (tests/sim_replay/test_bench_reference.py
    holds it to the simulation's own)."""
    from sim_replay.demand import plan
    from sim_replay.faults import stream
    from sim_replay.sumo_world import VEHICLE_VARS, WorldError
    import libsumo
    config = sim_config(net, monitors, args)
    tc = libsumo.constants
    step, sim_results, subscribe = libsumo.simulationStep, libsumo.simulation.getSubscriptionResults, \
        libsumo.vehicle.subscribe
    results, lights = libsumo.vehicle.getAllSubscriptionResults, libsumo.trafficlight.getAllSubscriptionResults
    warm = round(args.warmup / STEP_S)
    total = round(config.duration_s / STEP_S)
    seen = added = 0
    with sumo_world.World(net, seed=config.seed) as world:
        departures, _ = plan(config, world.network, stream(config.seed, "demand"))
        di = 0
        for n in range(1, total + 1):
            if n == warm + 1:
                wall, cpu, thread = time.perf_counter(), time.process_time(), time.thread_time()
            t_before = round((n - 1) * STEP_S, 9)
            while di < len(departures) and departures[di].depart_s <= t_before:
                d = departures[di]
                di += 1
                try:
                    route = d.route or world.route(d.entry, d.exit, d.kind)
                    world.add_vehicle(d.id, d.kind, route, depart_pos=0.0, depart_speed="max")
                    added += 1
                except WorldError:
                    continue
                if log is not None:
                    log.append((n - 1, d.id, d.kind, tuple(route)))
            step()
            for ident in sim_results()[tc.VAR_DEPARTED_VEHICLES_IDS]:
                subscribe(ident, VEHICLE_VARS)
            got = results()
            lights()
            if n > warm:
                seen += len(got)
        wall, cpu, thread = time.perf_counter() - wall, time.process_time() - cpu, time.thread_time() - thread
    timed = total - warm
    return {"steps_per_s": timed / wall, "steps_per_cpu_s": timed / cpu, "steps_per_thread_cpu_s": timed / thread,
            "vehicles_mean": seen / timed, "added": added, "departures": len(departures)}


def serve(db: Path, endpoint: str) -> dict:
    """An ingest on its own core, as `gaps serve` would run: listens, says "ready" on stdout, reads
    the number of events to expect from stdin, and waits until they are all stored."""
    from ingest.service import IngestService
    pin(1)
    with IngestService(db, listen=[endpoint], durable=False) as ingest:
        print("ready", flush=True)
        expected = int(sys.stdin.readline())
        started = time.perf_counter()
        stored = -1
        while not ingest.wait_until_settled(expected, 30):
            now = ingest.stats()["stored"]
            if now == stored:
                break
            stored = now
        stats = ingest.stats()
        stats["settle_wait_s"] = time.perf_counter() - started
        stats["cpu_s"] = time.process_time()
    return stats


def scheduled() -> tuple[float, float]:
    """Seconds this thread has run on a CPU and waited for one (Linux's /proc/thread-self/schedstat;
    zeros elsewhere): wall time that is neither was spent asleep (a blocked put, the GIL)."""
    try:
        ran, waited, _ = Path("/proc/thread-self/schedstat").read_text().split()
    except (OSError, ValueError):
        return 0.0, 0.0
    return int(ran) / 1e9, int(waited) / 1e9


def phases(got: dict) -> str:
    """Where the window's wall time went, as printed beside the figures (see the module docstring)."""
    wall = got["wall_s"]
    own = got["generator_s"] - got["sumo_s"]
    slept = max(0.0, wall - got["ran_s"] - got["waited_s"])
    return (f"phases of the {wall:.1f} s: SUMO's step {got['sumo_s']:.1f} s (CPU {got['sumo_cpu_s']:.1f} s), the "
            f"simulation's own work {own:.1f} s, the outlets' put {got['put_s']:.1f} s (CPU "
            f"{got['put_cpu_s']:.1f} s), the loop "
            f"{wall - got['generator_s'] - got['put_s']:.1f} s; the main thread ran {got['ran_s']:.1f} s, waited for "
            f"the CPU {got['waited_s']:.1f} s, slept {slept:.1f} s; other threads' CPU (Zenoh's) "
            f"{got['cpu_s'] - got['thread_cpu_s']:.1f} s")


PARTS = (("libsumo.simulationStep", "libsumo", "simulationStep"),
         ("vehicles' subscription results", "libsumo.vehicle", "getAllSubscriptionResults"),
         ("World._vehicles (the snapshot's VehicleStates)", "sumo_world.World", "_vehicles"),
         ("Simulation._decide (agents' looks and questions)", "simulation.Simulation", "_decide"),
         ("Simulation._states (entity.states and their bytes)", "simulation.Simulation", "_states"),
         ("Witness.tick (the truth's per-tick look)", "witness.Witness", "tick"),
         ("Watchers.observe (the monitors)", "watchers.Watchers", "observe"),
         ("EventPublisher.publish_all (keys, Zenoh puts, the cache)", "publisher.EventPublisher", "publish_all"))
"""Parts of a tick whose CPU (of the simulation's thread) is summed in the timed window: measured
by the thread's clock around each call, as cProfile cannot without overstating code made of many
small calls (its cost per call is larger than theirs)."""


def time_parts(spent: dict[str, float], calls: dict[str, int], on: list[bool]) -> list[tuple[object, str, object]]:
    """Wrap each of PARTS to add its thread CPU to `spent` and count its calls in `calls` while on[0];
    returns what to put back."""
    import libsumo
    from sim_replay import publisher, simulation, sumo_world, watchers, witness
    where = {"libsumo": libsumo, "libsumo.vehicle": libsumo.vehicle, "sumo_world.World": sumo_world.World,
             "simulation.Simulation": simulation.Simulation, "witness.Witness": witness.Witness,
             "watchers.Watchers": watchers.Watchers, "publisher.EventPublisher": publisher.EventPublisher}
    undo = []
    for label, owner_name, name in PARTS:
        owner = where[owner_name]
        real = getattr(owner, name)

        def timed(*args, _real=real, _label=label, **kwargs):
            if not on[0]:
                return _real(*args, **kwargs)
            began = time.thread_time()
            try:
                return _real(*args, **kwargs)
            finally:
                spent[_label] = spent.get(_label, 0.0) + time.thread_time() - began
                calls[_label] = calls.get(_label, 0) + 1
        setattr(owner, name, timed)
        undo.append((owner, name, real))
    return undo


def child(part: str, *args: str, stdin: int | None = None) -> subprocess.Popen:
    return subprocess.Popen([sys.executable, __file__, "--part", part, *args], stdin=stdin,
                            stdout=subprocess.PIPE, text=True)


def last_json(proc: subprocess.Popen) -> dict:
    out, _ = proc.communicate()
    if proc.returncode != 0:
        raise SystemExit(f"bench/sim.py: the {proc.args[3]} part failed (exit {proc.returncode})")
    return json.loads(out.strip().splitlines()[-1])


def simulation(net: Path, monitors: Path, args: argparse.Namespace, folder: Path) -> dict:
    """The simulation in this process, on one core, published into an ingest in a child process on
    the other: its wall time, events, queries and SUMO's share (World.step timed inside it)."""
    from sim_replay.outlets import Outlets
    stepping = [0.0, 0.0]       # SUMO's step: wall, CPU of this thread
    real_step = sumo_world.World.step

    def timed_step(self):
        started, cpu = time.perf_counter(), time.thread_time()
        try:
            return real_step(self)
        finally:
            stepping[0] += time.perf_counter() - started
            stepping[1] += time.thread_time() - cpu

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        endpoint = f"tcp/127.0.0.1:{s.getsockname()[1]}"
    ingest = child("serve", str(folder / "sim.db"), endpoint, stdin=subprocess.PIPE)
    if ingest.stdout.readline().strip() != "ready":
        raise SystemExit("bench/sim.py: the ingest did not start")
    cpus = os.sched_getaffinity(0) if hasattr(os, "sched_getaffinity") else None
    pinned = pin(0)
    config = sim_config(net, monitors, args)
    sumo_world.World.step = timed_step
    spent: dict[str, float] = {}
    timing = [False]
    calls: dict[str, int] = {}
    undo = time_parts(spent, calls, timing) if args.parts else []
    window_from: int | None = None  # the first event's t (the run's start) + the warm-up
    mark: dict | None = None
    events = states = 0
    generating = putting = put_cpu = 0.0  # in the window: wall making the next tick, wall and CPU putting it
    clock = time.perf_counter
    try:
        sim = Simulation(config)
        with Outlets(connect=[endpoint]) as out:
            made = iter(sim.batches())
            while True:
                began = clock()
                batch = next(made, None)
                if batch is None:
                    break
                t = batch[0]["t"]
                if window_from is None:
                    window_from = t + int(args.warmup * 1e9)
                if mark is None and t >= window_from:
                    mark = {"wall": time.perf_counter(), "cpu": time.process_time(), "sumo": stepping[0],
                            "sumo_cpu": stepping[1], "thread_cpu": time.thread_time(), "scheduled": scheduled(),
                            "queries": sim.books.queries, "engine_asks": sim.books.engine_asks}
                    timing[0] = True
                    began = clock()
                if mark is None:
                    out.put_all(batch)
                    continue
                events += len(batch)
                states += sum(1 for event in batch if event["kind"] == "entity.state")
                made_at, cpu = clock(), time.thread_time()
                generating += made_at - began
                out.put_all(batch)
                put_cpu += time.thread_time() - cpu
                putting += clock() - made_at
        wall, cpu = time.perf_counter() - mark["wall"], time.process_time() - mark["cpu"]
        thread_cpu = time.thread_time() - mark["thread_cpu"]
        ran, waited = (now - before for now, before in zip(scheduled(), mark["scheduled"]))
    finally:
        timing[0] = False
        sumo_world.World.step = real_step
        for owner, name, real in undo:
            setattr(owner, name, real)
        if cpus is not None:
            os.sched_setaffinity(0, cpus)  # the machine line counts this machine's CPUs, not the pin
    ingest.stdin.write(f"{out.summary().published}\n")
    ingest.stdin.flush()
    stats = last_json(ingest)
    steps = round(args.seconds / STEP_S)
    return {"wall_s": wall, "cpu_s": cpu, "pinned": pinned, "settled_after_s": stats["settle_wait_s"],
            "events": events, "published": out.summary().published, "stored": stats["stored"],
            "ingest_cpu_s": stats["cpu_s"], "queries": sim.books.queries - mark["queries"],
            "engine_asks": sim.books.engine_asks - mark["engine_asks"],
            "sumo_s": stepping[0] - mark["sumo"], "sumo_cpu_s": stepping[1] - mark["sumo_cpu"],
            "generator_s": generating, "put_s": putting, "put_cpu_s": put_cpu, "thread_cpu_s": thread_cpu, "ran_s": ran,
            "waited_s": waited, "steps": steps, "vehicles_mean": states / steps,
            "potential_violations": sim.summary.potential_violations,
            "parts_cpu_ms_per_step": {k: round(1e3 * v / steps, 2) for k, v in spent.items()},
            "parts_calls_per_step": {k: round(v / steps, 1) for k, v in calls.items()},
            "ingest": {k: v for k, v in stats.items() if k not in ("cpu_s", "settle_wait_s")}}


def _said(run: dict) -> str:
    return (f"{run['steps_per_s']:,.1f} steps/s with {run['vehicles_mean']:,.0f} vehicles on average "
            f"({run['steps_per_s'] * STEP_S:.2f} x real time; {run['steps_per_cpu_s']:,.1f} steps per CPU second, "
            f"{1e3 / run['steps_per_thread_cpu_s']:.2f} ms of thread CPU a step)")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--vehicles", type=int, default=200 if quick() else 1120,
                    help="vehicles set off (1,120: about 1,000 on the grid through the window, as some leave)")
    ap.add_argument("--seconds", type=float, default=20.0 if quick() else 60.0, help="world seconds simulated")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--warmup", type=float, default=10.0 if quick() else 60.0,
                    help="world seconds, not timed, in which the vehicles enter the network")
    ap.add_argument("--depart-within", type=float, default=None,
                    help="share of the run over which vehicles set off (default: the warm-up)")
    ap.add_argument("--no-parts", dest="parts", action="store_false",
                    help="leave the parts' clocks out (two thread-CPU reads a call: what they cost is in the figures)")
    ap.add_argument("--note", default="", help="said in the recorded notes (e.g. another commit's figures beside it)")
    ap.add_argument("--part", choices=["sumo-alone", "sumo-same", "serve"], help=argparse.SUPPRESS)
    ap.add_argument("part_args", nargs="*", help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.depart_within is None:
        args.depart_within = args.warmup / (args.warmup + args.seconds)
    net = grid_net()
    steps = round(args.seconds / STEP_S)
    if args.part == "sumo-alone":
        print(json.dumps(sumo_alone(net, args.vehicles, steps, args.seed)))
        return
    if args.part == "serve":
        print(json.dumps(serve(Path(args.part_args[0]), args.part_args[1])))
        return
    monitors = net.with_name("grid10-lefthand.monitors.json")
    if args.part == "sumo-same":
        pin(0)
        print(json.dumps(sumo_same(net, monitors, args)))
        return
    monitors.write_text(json.dumps({"monitors": MONITORS}), encoding="utf-8")
    sizes = ["--vehicles", str(args.vehicles), "--seconds", str(args.seconds), "--seed", str(args.seed)]
    same_args = (*sizes, "--warmup", str(args.warmup), "--depart-within", str(args.depart_within))
    before = last_json(child("sumo-same", *same_args))
    print(f"SUMO alone with the simulation's traffic, before the simulation: {_said(before)}", flush=True)
    old_got = last_json(child("sumo-alone", *sizes))
    old_rate, old_vehicles, old_cpu = old_got["steps_per_s"], old_got["vehicles_mean"], old_got["steps_per_cpu_s"]
    print(f"SUMO alone with sumo_step.Traffic (the earlier reference: other routes, N kept on the grid): "
          f"{old_rate:,.1f} steps/s with {old_vehicles:,.0f} vehicles ({old_cpu:,.1f} steps per CPU second)",
          flush=True)
    speeds, loads = [calibration_elsewhere()], [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory(dir=os.environ.get("GAPS_BENCH_DIR", "/tmp")) as folder:
        got = simulation(net, monitors, args, Path(folder))
    speeds.append(calibration_elsewhere())
    loads.append(os.getloadavg()[0])
    after = last_json(child("sumo-same", *same_args))
    print(f"SUMO alone with the simulation's traffic, after the simulation: {_said(after)}", flush=True)
    # the reference: the two runs about the simulation, each figure their mean (the machine's load
    # changes over minutes; the runs on either side of the simulation bracket what it met)
    same = {k: (before[k] + after[k]) / 2 for k in ("steps_per_s", "steps_per_cpu_s", "steps_per_thread_cpu_s",
                                                    "vehicles_mean")}
    alone, alone_vehicles = same["steps_per_s"], same["vehicles_mean"]
    alone_cpu, alone_thread = same["steps_per_cpu_s"], same["steps_per_thread_cpu_s"]
    print(f"SUMO alone with the simulation's traffic (the reference, the mean of the two): {_said(same)}")
    got["calibration_ms"] = [round(x, 2) for x in speeds]
    got["load_average"] = [round(x, 2) for x in loads]
    got["sumo_same"] = {"before": before, "after": after}
    sim_rate = steps / got["wall_s"]
    print(f"simulation ({got['pinned']}): {args.seconds:g} s of world time in {got['wall_s']:.1f} s "
          f"({args.seconds / got['wall_s']:.2f} x real time; CPU {got['cpu_s']:.1f} s = {args.seconds / got['cpu_s']:.2f} x), {got['vehicles_mean']:,.0f} "
          f"vehicles on the network on average; {got['events']:,} events ({got['events'] / got['wall_s']:,.0f}/s), "
          f"{got['queries']:,} rulebook queries ({got['queries'] / got['wall_s']:,.0f}/s; {got['engine_asks']:,} proofs "
          f"worked out by the engine, the other questions with proofs answered by their shape); SUMO's step "
          f"{got['sumo_s']:.1f} s = {got['sumo_s'] / got['wall_s']:.0%} of the time")
    print(phases(got))
    print(f"thread CPU a step in parts of it (of {1e3 * got['thread_cpu_s'] / steps:.1f} ms): "
          + "; ".join(f"{k} {v:.2f} ms ({got['parts_calls_per_step'][k]:g} calls)"
                      for k, v in got["parts_cpu_ms_per_step"].items()))
    print(f"ingest (another process, another core): stored {got['stored']:,} of {got['published']:,} published, "
          f"all settled {got['settled_after_s']:.1f} s after the simulation ended; CPU {got['ingest_cpu_s']:.1f} s")
    print(f"ratio to SUMO alone: {sim_rate / alone:.2f} (simulation steps/s over SUMO-alone steps/s); by CPU time "
          f"{steps / got['cpu_s'] / alone_cpu:.2f} (steps per CPU second of each process: what the neighbours' load "
          f"leaves out)")
    ingest_rate = got["stored"] / got["ingest_cpu_s"]
    per_step = got["events"] / steps
    ingest_cap = ingest_rate / per_step / alone_cpu
    print(f"the ingest's cost: {ingest_rate:,.0f} events per CPU second of its process over the whole run; at "
          f"{per_step:,.0f} events a step it could take {ingest_rate / per_step:,.1f} steps per CPU second, "
          f"{ingest_cap:.2f} of SUMO alone's: the most the ratio by CPU time can reach with the ingest on a core "
          f"of its own")
    print(f"machine: {machine()}; load average {loads[0]:.2f} before the simulation, {loads[1]:.2f} after; "
          f"calibration {speeds[0]:.2f} ms before, {speeds[1]:.2f} ms after ({QUIET_MS})")
    if got["stored"] != got["published"]:
        raise SystemExit(f"bench/sim.py: {got['published'] - got['stored']:,} published events were not stored; "
                         f"the ingest's totals: {got['ingest']}")
    thread_ratio = steps / got["thread_cpu_s"] / alone_thread
    print(f"by the main thread's CPU: {1e3 * got['thread_cpu_s'] / steps:.1f} ms a step against SUMO alone's "
          f"{1e3 / alone_thread:.2f} ms: {thread_ratio:.2f}; to the earlier reference (sumo_step.Traffic) by CPU "
          f"time {steps / got['cpu_s'] / old_cpu:.2f}")
    parts = got["parts_cpu_ms_per_step"]
    sumo_part = parts.get("libsumo.simulationStep", 0.0) + parts.get("vehicles' subscription results", 0.0)
    if sumo_part:
        print(f"SUMO's part inside the simulation (simulationStep and the vehicles' subscription results): "
              f"{sumo_part:.2f} ms of thread CPU a step, {sumo_part * alone_thread / 1e3:.2f} times SUMO alone's whole "
              f"step on the same traffic: with no Python and no puts at all the ratio by thread CPU would be "
              f"{1e3 / alone_thread / sumo_part:.2f}")
    figures = [
        Figure("SUMO alone with the simulation's traffic", alone, "steps/s",
               note=f"the same departures, routes and seed, no agents, no publishing: {alone_vehicles:,.0f} vehicles "
                    f"on average; {alone_cpu:,.1f} steps per CPU second, {1e3 / alone_thread:.2f} ms of thread CPU "
                    f"a step"),
        Figure("SUMO alone with sumo_step.Traffic (the earlier reference)", old_rate, "steps/s",
               note=f"other routes, {old_vehicles:,.0f} vehicles kept on the grid; {old_cpu:,.1f} steps per CPU "
                    f"second; the simulation by CPU time to it {steps / got['cpu_s'] / old_cpu:.2f} x"),
        Figure("the simulation, publishing into an ingest", sim_rate, "steps/s",
               peer="SUMO alone with the simulation's traffic",
               note=f"{got['vehicles_mean']:,.0f} vehicles on average"),
        Figure("real-time factor of the simulation", args.seconds / got["wall_s"], "x real time",
               target=">= 1 at 1,000 vehicles, one core"),
        Figure("real-time factor by the simulation's CPU time", args.seconds / got["cpu_s"], "x real time",
               note="world seconds per CPU second of its process: what a core of its own would give"),
        Figure("the simulation by CPU time, to SUMO alone by CPU time", steps / got["cpu_s"] / alone_cpu, "x",
               target=">= 0.5 (issue 40)",
               note=f"steps per CPU second of each process (SUMO alone with the simulation's traffic "
                    f"{alone_cpu:,.1f}): the ratio without the neighbours' load"),
        *([Figure("SUMO's part inside the simulation, to SUMO alone's whole step", sumo_part * alone_thread / 1e3,
                  "x", note=f"simulationStep and the vehicles' subscription results, {sumo_part:.2f} ms of thread "
                            f"CPU a step: the ratio by thread CPU with no Python and no puts at all would be "
                            f"{1e3 / alone_thread / sumo_part:.2f}")] if sumo_part else []),
        Figure("the simulation's main thread to SUMO alone's, by thread CPU", thread_ratio, "x",
               note=f"{1e3 * got['thread_cpu_s'] / steps:.1f} ms a step against {1e3 / alone_thread:.2f} ms "
                    f"(Zenoh's threads left out)"),
        Figure("events published", got["events"] / got["wall_s"], "events/s"),
        Figure("the ingest's events per CPU second", ingest_rate, "events/CPU-s",
               note=f"stored over its process's CPU, the whole run; at {per_step:,.0f} events a step, "
                    f"{ingest_cap:.2f} x SUMO alone's steps per CPU second: the ingest's cap on the ratio by CPU"),
        Figure("rulebook queries", got["queries"] / got["wall_s"], "queries/s"),
        Figure("SUMO's share of the simulation's time", 100 * got["sumo_s"] / got["wall_s"], "%"),
        Figure("the simulation's own work (agents, monitors, events)",
               100 * (got["generator_s"] - got["sumo_s"]) / got["wall_s"], "% of the time"),
        Figure("the outlets' put (canonical JSON, Zenoh, the producer's cache)", 100 * got["put_s"] / got["wall_s"],
               "% of the time", note=f"its CPU {1e6 * got['put_cpu_s'] / got['events']:.0f} us an event"),
        Figure("the main thread waiting for the CPU", 100 * got["waited_s"] / got["wall_s"], "% of the time",
               note=f"Zenoh's threads, on the same core, used {got['cpu_s'] - got['thread_cpu_s']:.1f} s of CPU; "
                    f"the rest is the machine's other processes"),
    ]
    record("sim", "The whole simulation, publishing into a running ingest", figures,
           notes=f"grid10-lefthand, {args.vehicles:,} vehicles set off within {args.depart_within:.0%} of "
                 f"{args.seconds:g} s, seed {args.seed}, two monitors; the simulation on one core, the ingest "
                 f"in another process on the other (store not durable); SUMO alone in child processes, with the "
                 f"simulation's traffic and with sumo_step.Traffic; "
                 f"calibration {speeds[0]:.2f} / {speeds[1]:.2f} ms before / after the simulation ({QUIET_MS}), "
                 f"load average {loads[0]:.2f} / {loads[1]:.2f}" + (f"; {args.note}" if args.note else ""),
           details={k: v for k, v in got.items()})


if __name__ == "__main__":
    main()
