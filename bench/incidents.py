"""All incidents of a one-hour, 200-vehicle run, recomputed: how many times faster than real time.

    .venv/bin/python bench/incidents.py [--repeats 3] [--dir /tmp/gaps-bench] [--no-cold] [--json]

Issue 6's target: all incidents of a one-hour, 200-vehicle run recomputed at >= 500x real time,
i.e. in at most 7.2 s. The run is sim_replay.synthetic's (seed 7: 10.6 million events, 316
potential violations seeded with their ground truth). It is generated once into a store file
under --dir (several minutes: the append is about 10 µs an event) with its ground truth beside
it as JSON, and kept as a pristine log: the cold measurement runs on a fresh copy of it, so that
"cold" always includes whatever the reasoner builds on first use (state snapshots, indexes).

    cold   Investigation(store).incidents(run) on the fresh copy, the first call in this process
    warm   the same on the copy again, each repeat with a fresh Store and Investigation (median)

Then the incidents are compared with the generator's ground truth (by the monitor's potential
violation they rest on: "monitor/m3:17"): verdict, perception-fault finding, who is liable.
The copy (with whatever the reasoner wrote into it) is kept for bench/scene.py.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import shutil
import statistics
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

from machine import QUIET_MS, calibration_elsewhere, machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file
from reasoner.bundled import RULES_DIR
from sim_replay.synthetic import GENERATOR, synthetic_run
from store import Store

RUN = "synthetic-1h"
VEHICLES, SECONDS, SEED = (100, 300, 7) if quick() else (200, 3600, 7)  # quick: about 440,000 events
BATCH = 10_000
TARGET = 500.0  # x real time


def rulebooks_tag() -> str:
    """The bundled rulebooks' digest, short: the run records them and its ground truth is asked of
    them, so a file generated under other rulebooks is another run, not this one."""
    digest = hashlib.sha256()
    for path in sorted(RULES_DIR.glob("*.le")):
        digest.update(path.name.encode() + b"\0" + path.read_bytes())
    return digest.hexdigest()[:10]


def base_file(directory: Path) -> Path:
    """The pristine store file of the run (and its ground truth), generated if missing."""
    path = directory / f"incidents-{RUN}-g{GENERATOR}-r{rulebooks_tag()}-v{VEHICLES}-s{SECONDS}-seed{SEED}.db"
    truth_path = path.with_suffix(".truth.json")
    if path.exists() and truth_path.exists():
        return path
    partial = path.with_suffix(".partial")
    for leftover in directory.glob(partial.name + "*"):
        leftover.unlink()
    truth: list[dict[str, Any]] = []
    started = time.perf_counter()
    appending = 0.0
    n = 0
    print(f"generating {RUN}: {VEHICLES} vehicles, {SECONDS} s, seed {SEED} into {partial}", flush=True)
    with Store(partial, durable=False) as store:
        batch: list[dict[str, Any]] = []
        for ev in synthetic_run(VEHICLES, SECONDS, SEED, RUN, truth=truth):
            batch.append(ev)
            if len(batch) == BATCH:
                a = time.perf_counter()
                report = store.append(batch, origin="bench")
                appending += time.perf_counter() - a
                if report.rejected:
                    raise SystemExit(f"the store refused generated events: {report.rejected[:3]}")
                n += len(batch)
                batch.clear()
                if n % 500_000 == 0:
                    el = time.perf_counter() - started
                    print(f"  {n:>11,} events  {el:6.0f} s  ({n / el:,.0f}/s; append {appending:.0f} s)", flush=True)
        store.append(batch, origin="bench")
        n += len(batch)
        assert store.count(RUN) == n
    if partial.with_name(partial.name + "-wal").exists():
        raise SystemExit(f"{partial} was not checkpointed on close; not renaming it")
    elapsed = time.perf_counter() - started
    truth_path.write_text(json.dumps(truth))
    partial.rename(path)
    print(f"generated {n:,} events in {elapsed:.0f} s: {(elapsed - appending) / n * 1e6:.1f} µs/event generating, "
          f"{appending / n * 1e6:.1f} µs/event appending; {path.stat().st_size / 1e9:.1f} GB", flush=True)
    return path


def work_file(directory: Path, fresh: bool) -> Path:
    """A copy of the pristine file that the reasoner may write into (snapshots, indexes)."""
    base = base_file(directory)
    work = base.with_name(base.stem + ".work.db")
    if fresh or not work.exists():
        for old in directory.glob(work.name + "*"):
            old.unlink()
        started = time.perf_counter()
        shutil.copyfile(base, work.with_suffix(".copying"))
        work.with_suffix(".copying").rename(work)
        print(f"copied the pristine file in {time.perf_counter() - started:.0f} s", flush=True)
    return work


def truth_of(directory: Path) -> list[dict[str, Any]]:
    return json.loads(base_file(directory).with_suffix(".truth.json").read_text())


def incidents_once(path: Path) -> tuple[list[dict[str, Any]], float, float]:
    """Wall and CPU seconds of one Investigation(store).incidents(run), fresh objects."""
    from reasoner.investigation import Investigation

    with Store(path, durable=False) as store:
        started, cpu = time.perf_counter(), time.process_time()
        found = Investigation(store).incidents(RUN)
        return found, time.perf_counter() - started, time.process_time() - cpu


def compare(found: list[dict[str, Any]], truth: list[dict[str, Any]]) -> dict[str, Any]:
    """How the incidents found match the ground truth, by the recorded potential violation."""
    by_id = {inc.id: inc for inc in found}
    matched = verdicts = faults = liable = 0
    wrong: list[str] = []
    for expected in truth:
        inc = by_id.get(expected["id"])
        if inc is None:
            wrong.append(f"{expected['id']} ({expected['cause']}): not found")
            continue
        matched += 1
        kinds = {f.kind for f in inc.findings}
        ok_verdict = inc.verdict == expected["verdict"]
        ok_fault = ("perception fault" in kinds) == ("perception fault" in expected["findings"])
        ok_liable = inc.liable == expected["liable"]
        verdicts += ok_verdict
        faults += ok_fault
        liable += ok_liable
        if not (ok_verdict and ok_fault and ok_liable):
            wrong.append(f"{expected['id']} ({expected['cause']}): verdict {inc.verdict} "
                         f"(expected {expected['verdict']}), liable {inc.liable} (expected "
                         f"{expected['liable']}), findings {sorted(k for k in kinds if k)}")
    extra = [inc for inc in found if inc.id not in {t["id"] for t in truth}]
    return {"expected": len(truth), "found": len(found), "matched": matched, "verdict_agrees": verdicts,
            "perception_fault_agrees": faults, "liable_agrees": liable, "not_in_truth": len(extra),
            "not_in_truth_examples": [{k: i.get(k) for k in ("id", "t", "vehicle", "action", "verdict")}
                                      for i in extra[:5]],
            "disagreements": wrong}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", type=Path, default=Path("/tmp/gaps-bench"))
    parser.add_argument("--repeats", type=int, default=2 if quick() else 3)
    parser.add_argument("--no-cold", action="store_true", help="reuse the working copy (no cold figure)")
    parser.add_argument("--build-only", action="store_true", help="generate the store file and stop")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)
    if args.build_only:
        base_file(args.dir)
        return
    path = work_file(args.dir, fresh=not args.no_cold)
    truth = truth_of(args.dir)
    with Store(path, durable=False) as store:
        span = next(r for r in store.runs() if r.run == RUN)
    duration = (span.last_t - span.first_t) / 1e9
    load = [os.getloadavg()[0]]
    cold = None
    if not args.no_cold:
        found, wall, cpu = incidents_once(path)
        cold = {"wall_s": wall, "cpu_s": cpu}
        print(f"cold: {wall:.2f} s wall, {cpu:.2f} s CPU ({duration / wall:,.0f}x real time)", flush=True)
    warm_wall, warm_cpu, speeds = [], [], []
    for i in range(args.repeats):
        load.append(os.getloadavg()[0])
        speed = calibration_elsewhere()
        found, wall, cpu = incidents_once(path)
        warm_wall.append(wall)
        warm_cpu.append(cpu)
        speeds.append(speed)
        print(f"warm {i + 1}: {wall:.2f} s wall, {cpu:.2f} s CPU (calibration before: {speed:.2f} ms, "
              f"{QUIET_MS})", flush=True)
    load.append(os.getloadavg()[0])
    median = statistics.median(warm_wall)
    verdicts = Counter(inc.verdict for inc in found)
    kinds = Counter(f.kind for inc in found for f in inc.findings)
    result = {
        "run": RUN, "events": span.events, "run_seconds": duration, "machine": machine(),
        "load_average": [round(x, 2) for x in load], "calibration_ms": [round(x, 2) for x in speeds],
        "cold": cold and {**cold, "x_real_time": duration / cold["wall_s"]},
        "warm": {"wall_s": warm_wall, "cpu_s": warm_cpu, "median_wall_s": median,
                 "x_real_time": duration / median, "x_real_time_cpu": duration / statistics.median(warm_cpu)},
        "target_x_real_time": TARGET, "incidents": len(found), "by_verdict": dict(verdicts),
        "findings": dict(kinds), "truth": compare(found, truth),
    }
    record_result(result, args.repeats)
    if args.json:
        print(json.dumps(result, indent=2))
        return
    print(f"machine: {result['machine']}")
    print(f"load average during the bench: {', '.join(f'{x:.2f}' for x in load)}")
    print(f"run {RUN}: {span.events:,} events over {duration:,.0f} s")
    print(f"incidents: {len(found)}  by verdict: {dict(verdicts)}  findings: {dict(kinds)}")
    if cold:
        print(f"cold: {cold['wall_s']:.2f} s  = {duration / cold['wall_s']:,.0f}x real time")
    print(f"warm: median {median:.2f} s of {args.repeats} (CPU median {statistics.median(warm_cpu):.2f} s) "
          f"= {duration / median:,.0f}x real time; target {TARGET:.0f}x (<= {duration / TARGET:.1f} s): "
          f"{'met' if duration / median >= TARGET else 'NOT met'}")
    t = result["truth"]
    print(f"ground truth: {t['matched']} of {t['expected']} seeded incidents found; verdict agrees on "
          f"{t['verdict_agrees']}, perception-fault finding on {t['perception_fault_agrees']}, liable on "
          f"{t['liable_agrees']}; {t['not_in_truth']} incidents not in the ground truth")
    for line in t["disagreements"][:15]:
        print(f"  {line}")
    if len(t["disagreements"]) > 15:
        print(f"  ... and {len(t['disagreements']) - 15} more")


def record_result(result: dict[str, Any], repeats: int) -> None:
    """The warm and cold figures into bench/results.json, with the agreement with the ground truth."""
    duration, warm, cold, t = result["run_seconds"], result["warm"], result["cold"], result["truth"]
    figures = [Figure("all incidents recomputed, warm (fresh Store and Investigation each)", warm["median_wall_s"], "s",
                      tuple(warm["wall_s"]), note=f"CPU {statistics.median(warm['cpu_s']):.2f} s"),
               Figure("the same as a speed", warm["x_real_time"], "× real time",
                      tuple(duration / w for w in warm["wall_s"]), target=f"≥ {TARGET:.0f}× real time")]
    if cold:
        figures.append(Figure("the same, cold (first call on a fresh copy of the file)", cold["wall_s"], "s",
                              note=f"{cold['x_real_time']:,.0f}× real time"))
    record("incidents", "All incidents of a synthetic run recomputed", figures,
           machine_extra=f"load average during the bench {', '.join(map(str, result['load_average']))}",
           notes=f"sim_replay.synthetic, {VEHICLES} vehicles for {SECONDS} s, seed {SEED}: {result['events']:,} events, "
                 f"{result['incidents']} incidents; median of {repeats} warm runs; ground truth: {t['matched']} of "
                 f"{t['expected']} found, verdict agrees on {t['verdict_agrees']}, perception fault on "
                 f"{t['perception_fault_agrees']}, liable on {t['liable_agrees']}, {t['not_in_truth']} not in it",
           details={"by_verdict": result["by_verdict"], "findings": result["findings"]})


if __name__ == "__main__":
    sys.exit(main())
