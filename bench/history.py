"""Histories over the simulated run of bench/incidents.py: what the verdicts pay for them, and
what every passage of every vehicle costs.

    .venv/bin/python bench/history.py [--repeats 3] [--dir /tmp/gaps-bench] [--no-whole] [--json]

On the store file bench/sim_runs.py records (its working copy; recorded if missing):

    judgement    Investigation(store).incidents(run), fresh objects, warm: every act's history,
                 derived facts, margin and the sweep of acts nobody recorded included (issue 12's
                 target: 500x real time or more)
    without      the same with the histories left out (Investigation._measured answering nothing:
                 the judgement before issue 12), measured in the same repeats, so that the
                 difference is the histories' cost on one machine at one time
    per act      for each recorded potential violation: history.passage(store, run, vehicle, t),
                 derived.facts(passage, t) and margins.margin(passage, action) alone, one run
                 context shared
    whole record every vehicle's passages over its whole record (history.passages(around=None)):
                 events read per second and as a multiple of real time

Events read are counted as the store hands them over (entity.state, observations, spawns).
Medians of --repeats runs; the machine is shared, so each repeat prints its calibration.
"""
from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path
from typing import Any

from incidents import TARGET, incidents_once  # bench/incidents.py, beside this file
from machine import QUIET_MS, calibration_elsewhere, machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file
from sim_runs import RUN, describe, work_file  # bench/sim_runs.py, beside this file
from store import Store


class Counted:
    """A read-only Store whose reads count the events they hand over."""

    def __init__(self, store: Store) -> None:
        self.store, self.read = store, 0

    def __getattr__(self, name: str) -> Any:
        return getattr(self.store, name)

    def source_events(self, *args: Any, **kwargs: Any) -> list[dict]:
        found = self.store.source_events(*args, **kwargs)
        self.read += len(found)
        return found

    def observations_of(self, *args: Any, **kwargs: Any) -> list[dict]:
        found = self.store.observations_of(*args, **kwargs)
        self.read += len(found)
        return found

    def events(self, *args: Any, **kwargs: Any):
        for event in self.store.events(*args, **kwargs):
            self.read += 1
            yield event


def per_act(path: Path) -> dict[str, Any]:
    """Every recorded potential violation's passage, facts and margin, timed."""
    from reasoner import derived, history, margins

    with Store.open_read_only(path) as opened:
        store = Counted(opened)
        acts = [(pv["body"]["vehicle"], pv["t"], pv["body"]["action"])
                for pv in opened.events(RUN, kinds=["monitor.potential_violation"])]
        started, cpu = time.perf_counter(), time.process_time()
        ctx = history.run_context(store, RUN)
        passages = facts = measured = crossings = 0
        for vehicle, t, action in acts:
            p = history.passage(store, RUN, vehicle, t, context=ctx)
            if p is None:
                continue
            passages += 1
            crossings += p.crossing is not None
            facts += len(derived.facts(p, t))
            measured += margins.margin(p, action) is not None
        wall, cpu = time.perf_counter() - started, time.process_time() - cpu
    return {"acts": len(acts), "passages": passages, "crossings": crossings, "facts": facts, "margins": measured,
            "events_read": store.read, "wall_s": wall, "cpu_s": cpu}


def without_histories(path: Path) -> float:
    """Wall seconds of the judgement with no history (for the difference only): every court,
    plain or kept, measures nothing."""
    from reasoner.judge.court import Court
    from reasoner.measurement import Measurement
    from reasoner.speedups.kept_court import KeptCourt

    saved = {court: court.measured for court in (Court, KeptCourt)}
    for court in saved:
        court.measured = lambda self, case, mscen, vscen: Measurement(present=False)  # type: ignore[method-assign]
    try:
        return incidents_once(path)[1]
    finally:
        for court, measured in saved.items():
            court.measured = measured  # type: ignore[method-assign]


def whole_record(path: Path) -> dict[str, Any]:
    """Every vehicle's passages over its whole record."""
    from reasoner import history

    with Store.open_read_only(path) as opened:
        store = Counted(opened)
        vehicles = [src.split("/", 1)[1] for src in opened.sources(RUN) if src.startswith("vehicle/")]
        started = time.perf_counter()
        ctx = history.run_context(store, RUN)
        passages = sum(len(history.passages(store, RUN, v, context=ctx)) for v in vehicles)
        wall = time.perf_counter() - started
    return {"vehicles": len(vehicles), "passages": passages, "events_read": store.read, "wall_s": wall}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", type=Path, default=Path("/tmp/gaps-bench"))
    parser.add_argument("--repeats", type=int, default=2 if quick() else 3)
    parser.add_argument("--no-whole", action="store_true", help="skip every vehicle's whole record")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)
    path = work_file(args.dir, fresh=False)
    with Store.open_read_only(path) as store:
        span = next(r for r in store.runs() if r.run == RUN)
    duration = (span.last_t - span.first_t) / 1e9
    judged, bare, acts, speeds = [], [], [], []
    for i in range(args.repeats):
        speeds.append(calibration_elsewhere())
        _, wall, _ = incidents_once(path)
        judged.append(wall)
        bare.append(without_histories(path))
        acts.append(per_act(path))
        print(f"repeat {i + 1}: judgement {wall:.2f} s, without histories {bare[-1]:.2f} s, histories of "
              f"{acts[-1]['acts']} acts alone {acts[-1]['wall_s']:.3f} s (calibration before: {speeds[-1]:.2f} ms, "
              f"{QUIET_MS})", flush=True)
    whole = None if args.no_whole else whole_record(path)
    judge = statistics.median(judged)
    without = statistics.median(bare)
    act = statistics.median(a["wall_s"] for a in acts)
    last = acts[-1]
    result = {
        "run": RUN, "events": span.events, "run_seconds": duration, "machine": machine(),
        "calibration_ms": [round(x, 2) for x in speeds],
        "judgement_s": judged, "without_s": bare, "per_act": acts, "judgement_median_s": judge,
        "without_median_s": without, "per_act_median_s": act, "per_act_ms": act / max(last["acts"], 1) * 1000,
        "judgement_x_real_time": duration / judge, "without_x_real_time": duration / without,
        "whole_record": whole,
    }
    record_result(result, args.repeats)
    if args.json:
        print(json.dumps(result, indent=2))
        return
    print(f"machine: {result['machine']}")
    print(f"run {RUN}: {span.events:,} events over {duration:,.0f} s; {last['acts']} recorded potential violations")
    print(f"judgement with histories: median {judge:.2f} s = {duration / judge:,.0f}x real time; target "
          f"{TARGET:.0f}x: {'met' if duration / judge >= TARGET else 'NOT met'}")
    print(f"judgement without histories: median {without:.2f} s = {duration / without:,.0f}x real time "
          f"(the histories' share: {judge - without:+.2f} s)")
    print(f"histories of the recorded acts alone: median {act:.3f} s ({result['per_act_ms']:.1f} ms an act; "
          f"{last['events_read']:,} events read, {last['events_read'] / act:,.0f} events/s; {last['crossings']} "
          f"crossings, {last['facts']} derived facts, {last['margins']} margins)")
    if whole:
        print(f"whole record: {whole['vehicles']} vehicles, {whole['passages']:,} passages in {whole['wall_s']:.1f} s; "
              f"{whole['events_read']:,} events read = {whole['events_read'] / whole['wall_s']:,.0f} events/s, "
              f"{duration / whole['wall_s']:,.0f}x real time")


def record_result(result: dict[str, Any], repeats: int) -> None:
    """The figures into bench/results.json."""
    duration, acts, whole = result["run_seconds"], result["per_act"], result["whole_record"]
    last = acts[-1]
    act = result["per_act_median_s"]
    figures = [
        Figure("all incidents judged with histories (Investigation.incidents, warm)", result["judgement_median_s"],
               "s", tuple(result["judgement_s"])),
        Figure("judgement with histories, as a speed", result["judgement_x_real_time"], "× real time",
               tuple(duration / j for j in result["judgement_s"]), target=f"≥ {TARGET:.0f}× real time"),
        Figure("the same judgement without histories", result["without_median_s"], "s", tuple(result["without_s"]),
               peer="all incidents judged with histories (Investigation.incidents, warm)",
               note=f"{result['without_x_real_time']:,.0f}× real time"),
        Figure("histories of every recorded act alone (passage, derived facts, margin)", act, "s",
               tuple(a["wall_s"] for a in acts),
               note=f"{result['per_act_ms']:.1f} ms an act; {last['events_read'] / act:,.0f} events read/s"),
    ]
    if whole:
        figures.append(Figure("every passage of every vehicle, whole record", whole["events_read"] / whole["wall_s"],
                              "events/s", note=f"{whole['passages']:,} passages of {whole['vehicles']} vehicles in "
                              f"{whole['wall_s']:.1f} s = {duration / whole['wall_s']:,.0f}× real time"))
    record("history", "Histories rebuilt over a simulated run", figures,
           notes=f"{describe()}: {result['events']:,} events, {last['acts']} recorded potential "
                 f"violations ({last['crossings']} with a stop-line crossing, {last['facts']} derived facts, "
                 f"{last['margins']} margins); median of {repeats} runs; calibration "
                 f"{', '.join(map(str, result['calibration_ms']))} ms ({QUIET_MS})",
           details={"per_act": acts[-1], "whole_record": whole})


if __name__ == "__main__":
    main()
