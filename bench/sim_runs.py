"""The recorded run the benchmarks measure on: made by the simulation, stored once, kept under --dir.

The targets are stated on "a one-hour, 200-vehicle run" (DESIGN "Performance and reliability
targets"), so the run is the simulation's own (sim_replay.simulation): vehicles that ask the
rulebook, human drivers with habits, monitors that watch, faults injected, and its ground truth
(sim_replay.truth) beside it. The paper's map backs up well before 200 vehicles are on it at once,
so the run is on the bundled town (sim_replay/maps/town: twenty junctions with signals, a yellow
box, Stop and Give Way lines, 23 monitors). Vehicles set off all through the hour, 0.83 a second;
each is on the network about four minutes, so about 200 are on it at a time once it has filled
(ten minutes in). BENCH_QUICK=1 runs four minutes of the same (fewer on it: it is still filling).

    recorded(directory)   the pristine store file, generated if missing (with its ground truth)
    work_file(directory)  a copy of it the reasoner may write into (snapshots, indexes)
    truth(directory)      the ground truth, as sim_replay.truth writes it

A file is named by a digest of everything that decides its events: the config (seed included), the
bundled rulebooks, the simulation's source and its map's files, SUMO's version and this module's
GENERATOR; a change to any of them is another run, generated afresh. (The sentences the events
carry are reasoner.vocabulary's templates, which tests/reasoner/test_vocabulary.py holds to the
rulebooks' own.) A file is renamed into place only when complete, so an interrupted generation is
simply redone.
"""
from __future__ import annotations

import dataclasses
import hashlib
import json
import shutil
import time
from pathlib import Path
from typing import Any

from results import quick  # bench/results.py, beside this file
from reasoner.bundled import RULES_DIR
from sim_replay.maps import map_files
from sim_replay.sim_config import FaultRates, SimConfig
from store import Store

ROOT = Path(__file__).resolve().parents[1]
GENERATOR = 1          # bump when the way a run is recorded here changes
BATCH = 10_000

FULL = SimConfig(run="town-1h", seed=7, map="town", vehicles=3000, duration_s=3600.0, depart_within=1.0,
                 faults=FaultRates(misperceived_light=0.05, missed_road_user=0.02, speed_error=0.005,
                                   lost_event=0.0001, recorder_stops=0.05))
QUICK = dataclasses.replace(FULL, run="town-4m", vehicles=200, duration_s=240.0)
CONFIG = QUICK if quick() else FULL
RUN = CONFIG.run


def describe(config: SimConfig = CONFIG) -> str:
    """The run in a few words, for notes beside the figures."""
    return (f"the simulation on the {config.map} map, seed {config.seed}: {config.vehicles:,} vehicles setting off "
            f"over {config.duration_s:,.0f} s")


def key(config: SimConfig = CONFIG) -> str:
    """A digest of everything that decides the run's events (module docstring)."""
    import libsumo

    digest = hashlib.sha256()

    def add(label: str, data: bytes) -> None:
        digest.update(label.encode() + b"\0" + hashlib.sha256(data).digest())

    add("config", json.dumps(config.to_json(), sort_keys=True).encode())
    add("generator", str(GENERATOR).encode())
    add("sumo", repr(libsumo.getVersion()).encode())
    files = map_files(config.map)
    sources = [*sorted(RULES_DIR.glob("*.le")), *sorted((ROOT / "sim_replay").rglob("*.py")),
               *sorted(files.net.parent.iterdir())]
    for path in sources:
        if path.is_file():
            add(str(path.relative_to(ROOT)), path.read_bytes())
    return digest.hexdigest()[:12]


RECORDING: str | None = None
"""The key of a recording under the directory to use instead of the one this code would record
(`--recording`): judging an hour already recorded by an earlier version of the simulation, rather
than recording it again for 40 minutes because the simulation's code changed since."""


def recorded(directory: Path, config: SimConfig = CONFIG) -> Path:
    """The pristine store file of the run (its ground truth and `about` beside it), generated if missing."""
    path = directory / f"sim-{config.run}-{RECORDING or key(config)}.db"
    if path.exists() and truth_path(path).exists() and about_path(path).exists():
        return path
    if RECORDING:
        raise SystemExit(f"no recording {RECORDING} of {config.run} under {directory} (with its .truth.json and "
                         f".about.json): record it without --recording")
    partial = path.with_suffix(".partial")
    for leftover in directory.glob(partial.name + "*"):
        leftover.unlink()
    print(f"recording {config.run}: {describe(config)}, into {partial}", flush=True)
    made = _record(config, partial, truth_path(path))
    if partial.with_name(partial.name + "-wal").exists():
        raise SystemExit(f"{partial} was not checkpointed on close; not renaming it")
    made["bytes"] = partial.stat().st_size
    about_path(path).write_text(json.dumps(made, indent=1) + "\n", encoding="utf-8")
    partial.rename(path)
    s = made["simulation"]
    print(f"recorded {s['events']:,} events in {made['wall_s']:.0f} s ({s['world_s'] / made['wall_s']:.1f}x real time; "
          f"appending {made['append_s']:.0f} s of it): {made['vehicles_on_network']:.0f} vehicles on the network on "
          f"average ({s['vehicles']:,} in all), {s['acts']:,} acts in the ground truth, {s['potential_violations']:,} "
          f"potential violations, {s['rulebook_queries']:,} rulebook queries; {made['bytes'] / 1e9:.1f} GB", flush=True)
    return path


def _record(config: SimConfig, partial: Path, truth_file: Path) -> dict[str, Any]:
    """Simulate into the store file in batches, then write the ground truth; what it took and made."""
    from sim_replay.simulation import Simulation

    started = time.perf_counter()
    progress = _Progress(config.duration_s, started)
    simulation = Simulation(config, progress)
    appending = 0.0
    vehicle_states = 0
    with Store(partial, durable=False) as store:
        batch: list[dict[str, Any]] = []
        for event in simulation.events():
            batch.append(event)
            vehicle_states += event["kind"] == "entity.state" and event["src"].startswith("vehicle/")
            if len(batch) == BATCH:
                appending += _append(store, batch)
                progress.events += len(batch)
                batch.clear()
        appending += _append(store, batch)
        summary = simulation.summary
        assert summary is not None and store.count(config.run) == summary.events
    simulation.truth.write(truth_file)
    ticks = summary.world_s * config.rate_hz
    return {"run": config.run, "key": key(config), "config": config.to_json(), "simulation": summary.to_json(),
            "vehicles_on_network": vehicle_states / ticks if ticks else 0.0,
            "wall_s": round(time.perf_counter() - started, 1), "append_s": round(appending, 1)}


def _append(store: Store, batch: list[dict[str, Any]]) -> float:
    started = time.perf_counter()
    report = store.append(batch, origin="bench")
    if report.rejected:
        raise SystemExit(f"the store refused simulated events: {report.rejected[:3]}")
    return time.perf_counter() - started


class _Progress:
    """Prints a line each 5% of world time: a full-size run takes many minutes."""

    def __init__(self, world_s: float, started: float) -> None:
        self.world_s, self.started, self.events, self.next = world_s, started, 0, 0.05

    def __call__(self, done: float, total: float) -> None:
        if done / total + 1e-9 < self.next:
            return
        self.next = done / total + 0.05
        wall = time.perf_counter() - self.started
        print(f"  {done:6.0f} of {total:,.0f} world s  {self.events:>11,} events stored  {wall:6.0f} s "
              f"({done / wall:.1f}x real time)", flush=True)


def truth_path(store_file: Path) -> Path:
    return store_file.with_suffix(".truth.json")


def about_path(store_file: Path) -> Path:
    """How the run was made: its config and key, the simulation's summary, the vehicles on the
    network on average, and how long the recording took."""
    return store_file.with_suffix(".about.json")


def work_file(directory: Path, fresh: bool, config: SimConfig = CONFIG) -> Path:
    """A copy of the pristine file that the reasoner may write into (snapshots, indexes)."""
    base = recorded(directory, config)
    work = base.with_name(base.stem + ".work.db")
    if fresh or not work.exists():
        for old in directory.glob(work.name + "*"):
            old.unlink()
        started = time.perf_counter()
        shutil.copyfile(base, work.with_suffix(".copying"))
        work.with_suffix(".copying").rename(work)
        print(f"copied the pristine file in {time.perf_counter() - started:.0f} s", flush=True)
    return work


def truth(directory: Path, config: SimConfig = CONFIG) -> dict[str, Any]:
    return json.loads(truth_path(recorded(directory, config)).read_text(encoding="utf-8"))


def about(directory: Path, config: SimConfig = CONFIG) -> dict[str, Any]:
    return json.loads(about_path(recorded(directory, config)).read_text(encoding="utf-8"))

