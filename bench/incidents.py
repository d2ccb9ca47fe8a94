"""All incidents of a one-hour, 200-vehicle run, recomputed: how many times faster than real time.

    .venv/bin/python bench/incidents.py [--repeats 3] [--dir /tmp/gaps-bench] [--no-cold] [--recording KEY] [--json]

Issue 6's target: all incidents of a one-hour, 200-vehicle run recomputed at >= 500x real time,
i.e. in at most 7.2 s. The run is the simulation's (bench/sim_runs.py: the town map, about 200
vehicles on it through the hour, faults injected), recorded once into a store file under --dir with
its ground truth beside it, and kept as a pristine log: the cold measurement runs on a fresh copy
of it, so that "cold" always includes whatever the reasoner builds on first use (state snapshots,
indexes).

    cold       Investigation(store).incidents(run) on the fresh copy, the first call in this process:
               every case found and measured (histories, derived facts, states), then judged
    warm       the same on the copy again, each repeat with a fresh Store and Investigation (median):
               the cases and their measurements read from the sealed cache the cold call kept
               (reasoner/case_memo.py), every case judged again by the rulebooks
    remeasured one more call with Speedups.NONE: every case measured again as in the cold call (the
               presence index and other caches warm), the cost of the histories without their cache

Every call's incidents must be the cold call's, by a digest of their JSON (the bench says so).

Then the incidents are compared with the simulation's ground truth through the tests' own table
(tests/helpers/sim_truth_table.py): each act the simulation made happen gets the verdict the law
should give, and every disagreement is printed, with its explanation where it is a known one.
The copy (with whatever the reasoner wrote into it) is kept for bench/scene.py.
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import sys
import time
from collections import Counter
from pathlib import Path
from typing import Any

from machine import QUIET_MS, calibration_elsewhere, machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file
import sim_runs  # bench/sim_runs.py, beside this file
from sim_runs import RUN, about, describe, recorded, truth, work_file
from sim_replay.sim_events import T0
from store import Store

TARGET = 500.0  # x real time


def incidents_once(path: Path, kept: bool = True) -> tuple[list[Any], float, float]:
    """The incidents, and the wall and CPU seconds of one Investigation(store).incidents(run), fresh objects."""
    from reasoner.investigation import Investigation, Speedups

    with Store(path, durable=False) as store:
        started, cpu = time.perf_counter(), time.process_time()
        found = Investigation(store, speedups=Speedups.MEASUREMENTS if kept else Speedups.NONE).incidents(RUN)
        return found, time.perf_counter() - started, time.process_time() - cpu


def digest(found: list[Any]) -> str:
    text = json.dumps([inc.to_json() for inc in found], sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:12]


def compare(found: list[Any], ground: dict[str, Any]) -> dict[str, Any]:
    """The incidents beside the ground truth's acts, as the tests' table reads them: how many agree,
    every disagreement (known ones with their explanation), and the crossings after an injected
    misread light with how many of them became incidents with a perception-fault finding."""
    from tests.helpers.sim_truth_table import compare as lines_of

    lines = lines_of(ground, found, T0)
    acts = [line for line in lines if line.act is not None]
    expected = [line for line in acts if line.row.verdict is not None]
    wrong = [line for line in lines if not line.agrees]
    misread = [line for line in acts if (line.act.get("fault") or "").startswith("misperceived_light")]
    judged = [line for line in misread if line.incidents]
    return {"acts": len(acts), "expected_incidents": len(expected),
            "expected_and_found": sum(1 for line in expected if line.agrees and line.incidents),
            "expected_unseen": sum(1 for line in expected if line.agrees and not line.incidents),
            "no_incident_agrees": sum(1 for line in acts if line.row.verdict is None and line.agrees),
            "by_row": dict(Counter(line.row.name for line in acts)),
            "disagreements": len(wrong), "known": sum(1 for line in wrong if line.known),
            "lines": [f"{line.describe()} | {line.known or 'UNEXPLAINED'}" for line in wrong],
            "misread_lights": {"acts": len(misread), "incidents": len(judged), "perception_fault": sum(
                1 for line in judged if any(f.kind == "perception fault" for i in line.incidents for f in i.findings))}}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", type=Path, default=Path("/tmp/gaps-bench"))
    parser.add_argument("--repeats", type=int, default=2 if quick() else 3,
                        help="warm runs (0: the cold one only, which then gives the speed)")
    parser.add_argument("--no-cold", action="store_true", help="reuse the working copy (no cold figure)")
    parser.add_argument("--build-only", action="store_true", help="generate the store file and stop")
    parser.add_argument("--no-remeasured", action="store_true", help="skip the call that measures every case again")
    parser.add_argument("--recording", metavar="KEY", help="judge the recording of this key under --dir (made by an "
                        "earlier version of the simulation) instead of the one this code records")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    sim_runs.RECORDING = args.recording
    if args.no_cold and args.repeats < 1:
        parser.error("--no-cold needs at least one of --repeats")
    args.dir.mkdir(parents=True, exist_ok=True)
    if args.build_only:
        recorded(args.dir)
        return
    path = work_file(args.dir, fresh=not args.no_cold)
    ground, made = truth(args.dir), about(args.dir)
    with Store(path, durable=False) as store:
        span = next(r for r in store.runs() if r.run == RUN)
    duration = (span.last_t - span.first_t) / 1e9
    load = [os.getloadavg()[0]]
    cold = None
    if not args.no_cold:
        found, wall, cpu = incidents_once(path)
        cold = {"wall_s": wall, "cpu_s": cpu, "digest": digest(found)}
        print(f"cold: {wall:.2f} s wall, {cpu:.2f} s CPU ({duration / wall:,.0f}x real time)", flush=True)
    warm_wall, warm_cpu, speeds = [], [], []
    digests = {cold["digest"]} if cold else set()
    for i in range(args.repeats):
        load.append(os.getloadavg()[0])
        speed = calibration_elsewhere()
        found = None        # each call starts as a fresh process would, not holding the last one's incidents
        found, wall, cpu = incidents_once(path)
        warm_wall.append(wall)
        warm_cpu.append(cpu)
        speeds.append(speed)
        digests.add(this := digest(found))
        print(f"warm {i + 1}: {wall:.2f} s wall, {cpu:.2f} s CPU (calibration before: {speed:.2f} ms, "
              f"{QUIET_MS}), incidents {this}", flush=True)
    remeasured = None
    if not args.no_remeasured:
        again, wall, cpu = incidents_once(path, kept=False)
        remeasured = {"wall_s": wall, "cpu_s": cpu, "x_real_time": duration / wall}
        digests.add(this := digest(again))
        print(f"remeasured: {wall:.2f} s wall, {cpu:.2f} s CPU ({duration / wall:,.0f}x real time), "
              f"incidents {this}", flush=True)
    load.append(os.getloadavg()[0])
    median = statistics.median(warm_wall) if warm_wall else None
    verdicts = Counter(inc.verdict for inc in found)
    kinds = Counter(f.kind for inc in found for f in inc.findings)
    result = {
        "run": RUN, "events": span.events, "run_seconds": duration, "machine": machine(),
        "load_average": [round(x, 2) for x in load], "calibration_ms": [round(x, 2) for x in speeds],
        "cold": cold and {**cold, "x_real_time": duration / cold["wall_s"]},
        "warm": median and {"wall_s": warm_wall, "cpu_s": warm_cpu, "median_wall_s": median,
                            "x_real_time": duration / median, "x_real_time_cpu": duration / statistics.median(warm_cpu)},
        "remeasured": remeasured, "same_incidents_every_call": len(digests) == 1,
        "target_x_real_time": TARGET, "incidents": len(found), "by_verdict": dict(verdicts),
        "findings": dict(kinds), "truth": compare(found, ground), "recording": made,
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
    wall = median or cold["wall_s"]
    print(f"{'warm: median' if median else 'cold (no warm runs):'} {wall:.2f} s"
          f"{f' of {args.repeats} (CPU median {statistics.median(warm_cpu):.2f} s)' if median else ''} "
          f"= {duration / wall:,.0f}x real time; target {TARGET:.0f}x (<= {duration / TARGET:.1f} s): "
          f"{'met' if duration / wall >= TARGET else 'NOT met'}")
    if remeasured:
        print(f"remeasured (every case measured again, Speedups.NONE): {remeasured['wall_s']:.2f} s = "
              f"{remeasured['x_real_time']:,.0f}x real time")
    print(f"the same incidents from every call: {'yes' if len(digests) == 1 else 'NO: ' + ', '.join(sorted(digests))}")
    print_truth(result["truth"])


def print_truth(t: dict[str, Any]) -> None:
    misread = t["misread_lights"]
    print(f"ground truth: {t['acts']:,} acts; {t['expected_incidents']} should be incidents: {t['expected_and_found']} "
          f"found with the verdict and rule the table gives, {t['expected_unseen']} unseen by any monitor and not "
          f"found; {t['no_incident_agrees']:,} acts rightly without an incident; {t['disagreements']} disagreements "
          f"({t['known']} known)")
    print(f"  acts after an injected misread light that became incidents: {misread['incidents']} of {misread['acts']}, "
          f"{misread['perception_fault']} with a perception-fault finding")
    for row, n in sorted(t["by_row"].items(), key=lambda kv: -kv[1]):
        print(f"  {n:6,}  {row}")
    for line in t["lines"]:
        print(f"  DISAGREES {line}")


def record_result(result: dict[str, Any], repeats: int) -> None:
    """The warm and cold figures into bench/results.json, with the agreement with the ground truth."""
    duration, warm, cold, t = result["run_seconds"], result["warm"], result["cold"], result["truth"]
    figures = []
    if warm:
        figures += [Figure("all incidents recomputed, warm (fresh Store and Investigation each)", warm["median_wall_s"],
                           "s", tuple(warm["wall_s"]), note=f"CPU {statistics.median(warm['cpu_s']):.2f} s"),
                    Figure("the same as a speed", warm["x_real_time"], "× real time",
                           tuple(duration / w for w in warm["wall_s"]), target=f"≥ {TARGET:.0f}× real time")]
    if cold:
        figures.append(Figure("the same, cold (first call on a fresh copy of the file)", cold["wall_s"], "s",
                              note=f"{cold['x_real_time']:,.0f}× real time; CPU {cold['cpu_s']:.2f} s"))
    if result["remeasured"]:
        again = result["remeasured"]
        figures.append(Figure("the same, measuring every case again (kept=False; other caches warm)", again["wall_s"],
                              "s", note=f"{again['x_real_time']:,.0f}× real time; CPU {again['cpu_s']:.2f} s"))
    if not warm:
        figures.append(Figure("the cold call as a speed (no warm runs)", cold["x_real_time"], "× real time",
                              target=f"≥ {TARGET:.0f}× real time"))
    made = result["recording"]
    record("incidents", "All incidents of a simulated run recomputed", figures,
           machine_extra=f"load average during the bench {', '.join(map(str, result['load_average']))}",
           notes=f"{describe()} ({made['vehicles_on_network']:.0f} on the network on average), recording "
                 f"{made.get('key', '?')}{' (by an earlier version of the simulation)' if sim_runs.RECORDING else ''}, recorded into the "
                 f"store in {made['wall_s']:,.0f} s: {result['events']:,} events, {result['incidents']} incidents; "
                 f"median of {repeats} warm runs; the same incidents from every call: "
                 f"{'yes' if result['same_incidents_every_call'] else 'NO'}; ground truth: "
                 f"{t['acts']:,} acts, {t['expected_incidents']} of them incidents by the tests' table, "
                 f"{t['expected_and_found']} found with its verdict and rule, {t['expected_unseen']} unseen by any "
                 f"monitor; {t['disagreements']} disagreements ({t['known']} known)",
           details={"by_verdict": result["by_verdict"], "findings": result["findings"],
                    "recording": {k: made.get(k) for k in ("key", "wall_s", "append_s", "vehicles_on_network", "simulation")},
                    "truth_rows": t["by_row"], "misread_lights": t["misread_lights"], "disagreements": t["lines"]})


if __name__ == "__main__":
    sys.exit(main())
