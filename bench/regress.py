"""Regression (two rulebooks, diff) as a speed against real time, from a store and straight from
MCAP, and its scaling on a local Dask cluster.

    .venv/bin/python bench/regress.py [--dir /tmp/gaps-bench] [--repeats 3] [--copies 4] [--recording KEY] [--json]

Issue 16's targets: a one-hour, 200-vehicle run regressed at >= 1,000x real time from a store and
>= 100x straight from its MCAP file with nothing prepared; >= 0.8x linear per worker on a local Dask
cluster, against the single-process run in the same bench.

The run: the simulation's one-hour town run (bench/sim_runs.py), exported once to MCAP beside it;
BENCH_QUICK=1 takes the golden run instead (tests/golden/golden-sim.mcap: 90 s, 60 road users,
25,533 events), imported once into a store under --dir. The new rulebook is validators.le without
its amber exception (verdicts and decisions flip, so the diff and the reasons are computed); the
baseline is the rulebooks in force.

    store    regress.regress on the store, a fresh Store and Regressor each repeat (median)
    mcap     regress_cluster.regress_recordings on the file, nothing prepared: each in a cache home of
             its own (nothing kept of the file: store/kept_recording.py), so it imports the file
             into a temporary store and judges it
    again    the same file regressed again, `--repeats` times, in the last one's cache home: judged
             from what that one kept of it under its digest (a fleet's logs regressed under
             another rulebook)
    scaling  `--copies` copies of the run in one store (renamed runs), judged in this process, then
             on a LocalCluster of 1 and of 2 worker processes (started and warmed on another copy
             of the file first: the figure is the judging, not the cluster's start)
"""
from __future__ import annotations

import argparse
import json
import os
import shutil
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any, Callable

from machine import QUIET_MS, calibration_elsewhere  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file

ROOT = Path(__file__).resolve().parents[1]
GOLDEN = ROOT / "tests" / "golden" / "golden-sim.mcap"
AMBER = '% "or are so close to it that to stop might cause a collision"'
TARGETS = {"store": 1000.0, "mcap": 100.0, "linear": 0.8}


def new_rules(directory: Path) -> Path:
    """validators.le without the amber exception (the rule under the AMBER comment)."""
    from reasoner.bundled import bundled
    text = bundled("validators.le")
    start = text.index(AMBER)
    path = directory / "validators.le"
    path.write_text(text[:start] + text[text.index("\n\n", start) + 2:], encoding="utf-8")
    return path


def inputs(directory: Path) -> tuple[Path, Path, str]:
    """The store file, the MCAP file and the run's name (made once under `directory`)."""
    from store import Store
    from store.transfer import export_run, import_file
    if quick():
        db, mcap = directory / "regress-golden.db", GOLDEN
        if not db.exists():
            with Store(db.with_suffix(".partial"), durable=False) as store:
                import_file(store, GOLDEN)
            db.with_suffix(".partial").rename(db)
        with Store.open_read_only(db) as store:
            return db, mcap, store.run_names()[0]
    sys.path.insert(0, str(Path(__file__).parent))
    from sim_runs import RUN, recorded
    db = recorded(directory)
    mcap = db.with_suffix(".mcap")
    if not mcap.exists():
        with Store.open_read_only(db) as store:
            export_run(store, RUN, mcap.with_suffix(".partial.mcap"), scene=False)
        mcap.with_suffix(".partial.mcap").rename(mcap)
    return db, mcap, RUN


def copies(db: Path, run: str, n: int, directory: Path) -> Path:
    """A store holding the run n times, as run-1..run-n (each its own chain)."""
    from store import Store
    path = directory / f"regress-{db.stem}-x{n}.db"
    if path.exists():
        return path
    partial = path.with_suffix(".partial")
    partial.unlink(missing_ok=True)
    with Store.open_read_only(db) as source, Store(partial, durable=False) as target:
        events = [json.loads(row.event) for row in source.history(run)]
        for i in range(1, n + 1):
            target.append([{**e, "run": f"{run}-{i}"} for e in events])
    partial.rename(path)
    return path


def timed(fn: Callable[[], Any]) -> tuple[Any, float]:
    started = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - started


def timed_cpu(fn: Callable[[], Any]) -> tuple[Any, float, float]:
    """The result, wall seconds and this process's CPU seconds (a shared machine's wall clock
    counts the other tenants' work too)."""
    cpu = time.process_time()
    out, wall = timed(fn)
    return out, wall, time.process_time() - cpu


def measure(db: Path, mcap: Path, run: str, rules: str, repeats: int, mcap_repeats: int) -> dict[str, Any]:
    """`repeats` regressions from the store (the first may measure and keep what the run's chain
    had not kept yet), then `mcap_repeats` straight from the file with nothing kept of it, then
    `repeats` of it again from what the last of those kept, each with the machine's calibration
    (bench/machine.py) taken just before it."""
    from reasoner.regress import regress
    from reasoner.regress import regress_recordings
    from store import Store

    def from_store():
        with Store.open_read_only(db) as store:
            return regress(store, [rules], runs=[run])

    with Store.open_read_only(db) as store:
        span = next(r for r in store.runs() if r.run == run)
    seconds = (span.last_t - span.first_t) / 1e9
    out: dict[str, Any] = {"run": run, "events": span.events, "run_seconds": seconds, "store_s": [], "mcap_s": [],
                           "again_s": [], "store_cpu_s": [], "mcap_cpu_s": [], "again_cpu_s": [], "calibration_ms": [],
                           "load": [os.getloadavg()[0]]}
    with tempfile.TemporaryDirectory(prefix="gaps-bench-kept-") as homes:
        def from_mcap(i: int) -> Callable[[], Any]:
            def regressed():
                os.environ["XDG_CACHE_HOME"] = os.path.join(homes, str(i))     # nothing kept of the file there
                return regress_recordings([mcap], [rules])
            return regressed

        steps = [("store", from_store)] * repeats + [("mcap", from_mcap(i)) for i in range(mcap_repeats)]
        steps += [("again", from_mcap(mcap_repeats - 1))] * (repeats if mcap_repeats else 0)
        home = os.environ.get("XDG_CACHE_HOME")
        try:
            for what, fn in steps:
                _step(out, what, fn, seconds)
        finally:
            os.environ.pop("XDG_CACHE_HOME", None)
            if home is not None:
                os.environ["XDG_CACHE_HOME"] = home
    return out


def _step(out: dict[str, Any], what: str, fn: Callable[[], Any], seconds: float) -> None:
    """One timed regression, its calibration taken just before it."""
    out["calibration_ms"].append(calibration_elsewhere())
    result, wall, cpu = timed_cpu(fn)
    out[f"{what}_s"].append(wall)
    out[f"{what}_cpu_s"].append(cpu)
    out.setdefault("counts", result.counts())
    assert result.counts() == out["counts"], "every regression gives the same counts"
    out["load"].append(os.getloadavg()[0])
    print(f"{what} {len(out[f'{what}_s'])}: {wall:.2f} s wall ({seconds / wall:,.0f}x real time), {cpu:.2f} s CPU "
          f"({seconds / cpu:,.0f}x); calibration {out['calibration_ms'][-1]:.2f} ms ({QUIET_MS})", flush=True)


def scaling(db: Path, run: str, rules: str, n: int, directory: Path) -> dict[str, Any]:
    """The n copies judged in this process, then on 1 and 2 local workers (warmed first), twice each:
    warm, from the measurements a first untimed pass kept, and cold, on a copy of the store with
    no derived cache (every case measured: a fleet's newly logged runs, and work large enough per
    task that the cluster's own costs do not hide the scaling)."""
    import logging

    from distributed import LocalCluster
    from reasoner.regress import Cluster, regress_store

    many = copies(db, run, n, directory)
    out: dict[str, Any] = {"runs": n, "load": [os.getloadavg()[0]]}
    with tempfile.TemporaryDirectory(prefix="gaps-bench-warm-", dir=directory) as tmp:
        def cold_copy(name: str) -> Path:
            path = Path(tmp) / f"{name}.db"
            shutil.copyfile(many, path)     # the store file alone: its derived cache is not copied
            return path

        regress_store(many, [rules])    # measures each run once and keeps it (reasoner/case_memo.py): every
        #                                 warm pass below then judges from the same kept measurements
        _, out["process_s"] = timed(lambda: regress_store(many, [rules]))
        cold = cold_copy("cold-process")
        _, out["process_cold_s"] = timed(lambda: regress_store(cold, [rules]))
        print(f"{n} runs in this process: {out['process_s']:.2f} s warm, {out['process_cold_s']:.2f} s cold",
              flush=True)
        for workers in (1, 2):
            with LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                              silence_logs=logging.ERROR) as local:
                on = Cluster(scheduler=local.scheduler_address)
                regress_store(cold_copy(f"start-{workers}"), [rules], cluster=on)   # start every worker's engine
                _, wall = timed(lambda: regress_store(many, [rules], cluster=on))
                cold = cold_copy(f"cold-{workers}")
                _, cold_wall = timed(lambda: regress_store(cold, [rules], cluster=on))
            out[f"workers_{workers}_s"], out[f"workers_{workers}_cold_s"] = wall, cold_wall
            out["load"].append(os.getloadavg()[0])
            print(f"{n} runs on {workers} worker(s): {wall:.2f} s warm, {cold_wall:.2f} s cold", flush=True)
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", type=Path, default=Path("/tmp/gaps-bench"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--copies", type=int, default=4, help="runs in the scaling store (two per worker); "
                        "0: no scaling measured")
    parser.add_argument("--mcap-repeats", type=int, default=None,
                        help="regressions straight from MCAP (default: --repeats); each imports and measures "
                             "the whole run afresh, the hour's some twenty minutes")
    parser.add_argument("--recording", metavar="KEY", help="regress the hour recorded under this key in --dir (by an "
                        "earlier version of the simulation) instead of recording the one this code would record")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)
    sys.path.insert(0, str(Path(__file__).parent))
    import sim_runs
    sim_runs.RECORDING = args.recording
    db, mcap, run = inputs(args.dir)
    with tempfile.TemporaryDirectory(prefix="gaps-bench-rules-") as tmp:
        rules = str(new_rules(Path(tmp)))
        speed = measure(db, mcap, run, rules, args.repeats,
                        args.repeats if args.mcap_repeats is None else args.mcap_repeats)
        scale = scaling(db, run, rules, args.copies, args.dir) if args.copies else None
    result = {**speed, "scaling": scale}
    figures(result, mcap)
    if args.json:
        print(json.dumps(result, indent=2))


def figures(r: dict[str, Any], mcap: Path) -> None:
    seconds, s = r["run_seconds"], r["scaling"]
    load = [*r["load"], *(s["load"] if s else [])]
    lines = [f"run {r['run']}: {r['events']:,} events over {seconds:,.0f} s; judged: {r['counts']}"]
    found: list[Figure] = []
    for what, label, target in (("store", "regression from a store (two rulebooks, diff)", "store"),
                                ("mcap", "regression straight from MCAP, nothing prepared", "mcap"),
                                ("again", "the same MCAP file regressed again (kept by its digest)", None)):
        if r.get(f"{what}_s"):
            lines.append(_speed_line(r, what, seconds, target) + (
                f" ({mcap.stat().st_size / 1e6:.1f} MB)" if what == "mcap" else ""))
            found += _speed_figures(r, what, label, seconds, target)
    if s:
        for temper in ("warm", "cold"):
            lines += _scaling_lines(s, temper, found)
    lines.append(f"load average during the bench: {', '.join(f'{x:.2f}' for x in load)} "
                 f"(median {statistics.median(load):.2f}); calibration {_spread(r['calibration_ms'])} ms ({QUIET_MS})")
    for line in lines:
        print(line)
    record("regress", "Regression of a run under two rulebooks, from a store, from MCAP, on Dask", found,
           notes=f"run {r['run']}, {r['events']:,} events over {seconds:,.0f} s; new rulebook: validators.le without "
                 f"its amber exception, baseline in force; medians of {len(r['store_s'])} from the store (the first "
                 f"{r['store_s'][0]:.2f} s: it keeps the baseline and any measurement not kept yet) and "
                 + (f"{len(r['mcap_s'])} from MCAP with nothing kept of it and {len(r['again_s'])} of it again, "
                    "from what was kept" if r["mcap_s"] else "none from MCAP (not measured in this run)")
                 + f"; calibration {_spread(r['calibration_ms'])} ms ({QUIET_MS})"
                 + ("" if s else "; scaling not measured in this run"),
           machine_extra=f"load average during the bench {', '.join(f'{x:.2f}' for x in load)}",
           details={"counts": r["counts"], "scaling": s, "store_cpu_s": r["store_cpu_s"],
                    "mcap_cpu_s": r["mcap_cpu_s"], "again_cpu_s": r.get("again_cpu_s", []),
                    "calibration_ms": r["calibration_ms"]})


def _scaling_lines(s: dict[str, Any], temper: str, found: list[Figure]) -> list[str]:
    """The scaling figures of the warm or the cold passes (appended to `found`) and their line."""
    suffix = "" if temper == "warm" else "_cold"
    if f"workers_2{suffix}_s" not in s:
        return []
    one, two, alone = s[f"workers_1{suffix}_s"], s[f"workers_2{suffix}_s"], s[f"process{suffix}_s"]
    runs = f"{s['runs']} runs, {temper},"
    found += [Figure(f"{runs} in one process", alone, "s"),
              Figure(f"{runs} on 1 Dask worker", one, "s", peer=f"{runs} in one process"),
              Figure(f"{runs} on 2 Dask workers", two, "s", peer=f"{runs} in one process"),
              Figure(f"2 workers as a fraction of linear ({temper}, against one process)", alone / two / 2,
                     "× linear", target=f"≥ {TARGETS['linear']}× linear")]
    return [f"{s['runs']} runs, {temper}: this process {alone:.2f} s, 1 worker {one:.2f} s, 2 workers {two:.2f} s: "
            f"{alone / two / 2:.2f}x linear against this process, {one / two / 2:.2f}x against 1 worker "
            f"(target {TARGETS['linear']}x)"]


_SAID = {"store": "from the store", "mcap": "straight from MCAP", "again": "the same MCAP again, kept"}


def _speed_line(r: dict[str, Any], what: str, seconds: float, target: str | None) -> str:
    wall, cpu = statistics.median(r[f"{what}_s"]), statistics.median(r[f"{what}_cpu_s"])
    return (f"{_SAID[what]}: median {wall:.2f} s = {seconds / wall:,.0f}x real time, CPU {cpu:.2f} s = "
            f"{seconds / cpu:,.0f}x" + (f" (target {TARGETS[target]:,.0f}x)" if target else " (no target)"))


def _speed_figures(r: dict[str, Any], what: str, label: str, seconds: float, target: str | None) -> list[Figure]:
    walls, cpus = r[f"{what}_s"], r[f"{what}_cpu_s"]
    wall, cpu = statistics.median(walls), statistics.median(cpus)
    aim = f"≥ {TARGETS[target]:,.0f}× real time" if target else ""
    return [Figure(label, wall, "s", tuple(walls), note=f"CPU {cpu:.2f} s"),
            Figure("the same as a speed", seconds / wall, "× real time", tuple(seconds / x for x in walls),
                   target=aim, note=f"{seconds / cpu:,.0f}× by CPU")]


def _spread(values: list[float]) -> str:
    return f"{min(values):.1f}-{max(values):.1f}" if values else "not taken"


if __name__ == "__main__":
    sys.exit(main())
