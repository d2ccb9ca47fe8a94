"""Export and import rates of `gaps export` / `gaps import` for MCAP and JSONL (a benchmark, not a test).

    .venv/bin/python bench/transfer.py [--events 200000] [--repeat 3]

A generated junction run (100 road users moving at 10 Hz, with perceptions, decisions and signal
changes) is stored once; then each format is exported and imported `--repeat` times into fresh
stores, and the median time of each step is reported as events per second, with the bytes per
event of each file and the machine it ran on. Imports are timed with FULL durability (the
default) and with --fast (synchronous=NORMAL).
"""
from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Callable, Iterator

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from store import Store  # noqa: E402
from store.transfer import export_run, import_file  # noqa: E402
from machine import machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file

RUN = "bench-transfer"
T0 = 1_732_184_100_000_000_000
TICK = 100_000_000  # 10 Hz
VEHICLES = 100
MAP = {"roads": [{"id": "r1", "from": [-500.0, 0.0], "to": [500.0, 0.0]},
                 {"id": "r2", "from": [0.0, -500.0], "to": [0.0, 500.0]}],
       "junctions": [{"id": "j1", "x": 0.0, "y": 0.0, "control": "lights"}], "monitors": []}


def generated_run(n: int) -> Iterator[dict]:
    """At least n events: per tick every road user's state; every 10 ticks a perception and a
    decision per vehicle; a signal change every 50 ticks."""
    seqs: dict[str, int] = {}

    def ev(src: str, t: int, kind: str, body: dict) -> dict:
        seqs[src] = seqs.get(src, -1) + 1
        return {"v": 1, "run": RUN, "src": src, "seq": seqs[src], "t": t, "kind": kind, "body": body}

    count = 0
    yield ev("sim/world", T0, "run.start", {"map": MAP, "seed": 1})
    for i in range(VEHICLES):
        yield ev(f"vehicle/{i}", T0, "entity.spawn", {"type": "car", "driver": "autonomous", "automation_level": 4})
    count += 1 + VEHICLES
    tick = 0
    while count < n:
        t = T0 + tick * TICK
        if tick % 50 == 0:
            colour = ("green", "amber", "red", "red_amber")[(tick // 50) % 4]
            yield ev("signal/j1-west", t, "signal.state", {"junction": "j1", "approach": "west", "colour": colour})
            count += 1
        for i in range(VEHICLES):
            src = f"vehicle/{i}"
            x = -400.0 + ((tick * 1.2 + i * 7) % 800)
            yield ev(src, t, "entity.state", {"x": x, "y": (i % 4) * 3.5 - 5.25, "heading_deg": 0.0,
                                              "speed_mps": 12.0, "road": "r1", "junction": None})
            count += 1
            if tick % 10 == i % 10:
                light = "red" if (tick // 50) % 4 == 2 else "green"
                yield ev(src, t, "vehicle.perception", {"facts": [f"{i} is of type car", f"{i} has {light} light"]})
                yield ev(src, t, "vehicle.decision", {"goal": f"{i} can enter the junction",
                                                      "action": "enter the junction",
                                                      "permitted": light == "green", "proceeds": light == "green"})
                count += 2
        tick += 1


def fill(path: Path, n: int) -> int:
    with Store(path, durable=False) as store:
        batch: list[dict] = []
        for event in generated_run(n):
            batch.append(event)
            if len(batch) == 5000:
                store.append(batch)
                batch = []
        store.append(batch)
        return store.count(RUN)


def timed(step: Callable[[int], None], repeat: int) -> tuple[float, float]:
    """Median wall and median CPU seconds of `repeat` runs of step(i). CPU time is the steadier
    figure on a shared machine; wall time includes waiting for the disk (fsync) and other work."""
    walls, cpus = [], []
    for i in range(repeat):
        wall, cpu = time.perf_counter(), time.process_time()
        step(i)
        walls.append(time.perf_counter() - wall)
        cpus.append(time.process_time() - cpu)
    return statistics.median(walls), statistics.median(cpus)




def bench_format(source: Path, folder: Path, fmt: str, events: int, repeat: int, scene: bool = True) -> dict:
    name = f"{fmt}{'' if scene else '-no-scene'}"
    out = folder / f"run-{name}.{fmt}"
    with Store(source) as store:
        export_s = timed(lambda i: export_run(store, RUN, out, scene=scene), repeat)
    size = out.stat().st_size
    results = {"export_s": export_s, "bytes": size}
    for durable in (True, False):
        def load(i: int) -> None:
            with Store(folder / f"import-{name}-{durable}-{i}.db", durable=durable) as target:
                report = import_file(target, out)
            assert report.stored == events and report.rejected == 0, report.to_json()
            if report.chains:
                assert report.chains[0].match is True, report.chains
        results[f"import_{'full' if durable else 'fast'}_s"] = timed(load, repeat)
    return results


def rate(events: int, seconds: tuple[float, float]) -> str:
    wall, cpu = seconds
    return f"{events / wall:,.0f} ({events / cpu:,.0f})"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=20_000 if quick() else 200_000)
    parser.add_argument("--repeat", type=int, default=1 if quick() else 3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="gaps-bench-transfer-") as tmp:
        folder = Path(tmp)
        source = folder / "source.db"
        start = time.perf_counter()
        events = fill(source, args.events)
        print(f"machine: {machine()}")
        print(f"run {RUN}: {events:,} events stored in {time.perf_counter() - start:.1f} s; "
              f"median of {args.repeat} runs per step\n")
        print("events/s as wall (CPU) time:")
        print(f"{'file':<16}{'export':>20}{'import FULL':>20}{'import --fast':>20}{'bytes/event':>13}{'file MB':>9}")
        figures = []
        for label, fmt, scene in (("mcap", "mcap", True), ("mcap --no-scene", "mcap", False), ("jsonl", "jsonl", True)):
            r = bench_format(source, folder, fmt, events, args.repeat, scene)
            rates = "".join(f"{rate(events, r[key]):>20}" for key in ("export_s", "import_full_s", "import_fast_s"))
            print(f"{label:<16}{rates}{r['bytes'] / events:>13.1f}{r['bytes'] / 1e6:>9.1f}")
            figures += figures_of(label, events, r)
        print("\nmcap: zstd chunks of 1 MiB, events plus run/checkpoint metadata plus the Foxglove scene and log "
              "channels (all counted in the bytes); --no-scene: events and metadata only; jsonl: canonical "
              "lines, uncompressed. Rates are events of the run per second.")
    record("transfer", "Export and import (gaps export / gaps import)", figures,
           notes=f"a generated junction run of {events:,} events; median of {args.repeat} runs per step; "
                 "rates by wall clock")


def figures_of(label: str, events: int, r: dict) -> list[Figure]:
    """One format's figures, each CPU rate beside its wall-clock rate."""
    out = []
    for key, step in (("export_s", "export"), ("import_full_s", "import (durable)"), ("import_fast_s", "import --fast")):
        wall, cpu = r[key]
        out.append(Figure(f"{label}: {step}", events / wall, "events/s", note=f"{events / cpu:,.0f} per CPU second"))
    out.append(Figure(f"{label}: file size", r["bytes"] / events, "bytes/event"))
    return out


if __name__ == "__main__":
    main()
