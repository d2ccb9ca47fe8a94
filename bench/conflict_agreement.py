"""The reasoner's "forced / endangered / gave way" held against SUMO's own account (issue 35).

    nice -n 10 .venv/bin/python bench/conflict_agreement.py [--minutes 10] [--seeds 11,12] [--maps paper,town]
                                                           [--keep DIR | --judge DIR] [--json] [--cost]

Each run is the simulation's (sim_replay.simulation, faults on at the rates `gaps sim --faults`
takes) with SUMO's own account kept in its ground truth (sim_replay/sumo_account.py: its SSM
device, and for every braking vehicle the constraint SUMO's car-following model says it braked
for). The events are appended to a store in a temporary directory and judged by the reasoner
through its public API (`reasoner.open(db).incidents(run)`, what `gaps incidents --json` prints).
Each Stop, Give Way and emergency-red incident (its act found in the truth by the tests' own
matching, tests/helpers/sim_truth_table.compare) is compared by tests/helpers/conflict_agreement.py:

    agreeing          the reasoner's forced or endangered road users are the ones SUMO says
                      gave way to the vehicle or were in its path
    false accusation  the reasoner names U, SUMO does not: U braked for something else (its
                      stated cause is listed), or not hard, or not at all
    miss              SUMO names U, the reasoner does not
    unraised          (per run) an act a monitor saw with no incident at all, to which SUMO says
                      someone gave way

and every act of the truth (of any class) that more than one incident judged with different
verdicts or rules: one act, one verdict (issue 35's "same act, opposite verdicts").

The reasoner's output is read only to be compared; nothing of it goes into the account.
`--cost` also times the simulation with and without SUMO's account: the demo's (three each, in
turn) and the first paper run's (once each).
"""
from __future__ import annotations

import argparse
import json
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from results import Figure, quick, record  # noqa: E402  bench/results.py, beside this file
from sim_replay.sim_config import FaultRates, SimConfig  # noqa: E402
from store import Store  # noqa: E402
from tests.helpers.conflict_agreement import Row, compare, split_verdicts, stated_cause, sumo_gave_way  # noqa: E402

FAULTS = FaultRates(misperceived_light=0.15, missed_road_user=0.05, speed_error=0.02, lost_event=0.001,
                    recorder_stops=0.1)
VEHICLES_PER_MIN = {"paper": 20, "town": 48}     # the paper's map backs up beyond ~20 a minute (docs/simulation.md)
BATCH = 10_000


def config(map_name: str, seed: int, minutes: float) -> SimConfig:
    return SimConfig(run=f"agree-{map_name}-{seed}", seed=seed, map=map_name,
                     vehicles=round(VEHICLES_PER_MIN[map_name] * minutes), duration_s=minutes * 60.0,
                     depart_within=1.0 if map_name == "town" else 0.7, faults=FAULTS)


# --- one run ------------------------------------------------------------------------------------

def simulate(cfg: SimConfig, db: Path) -> tuple[dict[str, Any], dict[str, float]]:
    """Simulate with SUMO's account into a store; the truth and what each step took."""
    from sim_replay.simulation import Simulation

    took: dict[str, float] = {"append_s": 0.0}
    started = time.perf_counter()
    sim = Simulation(cfg, account=True)
    with Store(db, durable=False) as store:
        batch: list[dict[str, Any]] = []
        for event in sim.events():
            batch.append(event)
            if len(batch) == BATCH:
                took["append_s"] += _append(store, batch)
        took["append_s"] += _append(store, batch)
    took["simulate_s"] = time.perf_counter() - started - took["append_s"]
    took["events"] = sim.summary.events
    return sim.truth.to_json(), took


def _append(store: Store, batch: list[dict[str, Any]]) -> float:
    started = time.perf_counter()
    report = store.append(list(batch))
    batch.clear()
    if report.rejected:
        raise SystemExit(f"the store refused simulated events: {report.rejected[:3]}")
    return time.perf_counter() - started


def kept(where: Path, run: str) -> tuple[dict[str, Any], dict[str, float], Path]:
    """A run an earlier `--keep DIR` kept: its truth and store, judged again as they are (read only)."""
    db, truth = where / f"{run}.db", where / f"{run}.truth.json"
    if not db.exists() or not truth.exists():
        raise SystemExit(f"{where}: no kept store and truth for {run} (run the bench with --keep {where} first)")
    return json.loads(truth.read_text(encoding="utf-8")), {"simulate_s": 0.0, "append_s": 0.0, "events": 0}, db


def judged(db: Path, run: str) -> tuple[list[Any], float]:
    """The run's incidents as `gaps incidents --json` gets them (reasoner.api)."""
    import reasoner

    started = time.perf_counter()
    with reasoner.open(db) as case:
        found = case.incidents(run)
    return found, time.perf_counter() - started


# --- printing -----------------------------------------------------------------------------------

def describe(row: Row) -> list[str]:
    a, i = row.act, row.incident
    where = f"{a['junction']}/{a['approach']} {a['line']}" + (f" {a['light']}" if a["light"] not in (None, "none") else "")
    out = [f"  {i.id} vehicle {i.vehicle} at {a['t_s']:.1f}s {where} ({'stood at the line' if a['stopped_at_line'] else 'did not stand'}"
           f"{', on a call' if a['on_call'] else ''}): {i.verdict} {i.rule or ''}"]
    for u in row.false:
        out.append(f"    false accusation: reasoner says {i.vehicle} forced/endangered {u}; SUMO: {u} "
                   f"{stated_cause(row.truth, u, a)}")
    for u in row.not_proven:
        s, d = row.sumo[u], next(x for x in row.incident.second_limb if x.user == u)
        out.append(f"    not proven: SUMO says {u} braked for {i.vehicle} ({s['cause']}), held over a second "
                   f"{max(s.get('held_mps2') or 0.0, s.get('road_user_held_mps2') or 0.0):.2f} m/s²; the reasoner "
                   f"measured {d.decel_mps2:.2f} ± {d.decel_uncertainty_mps2:.2f} m/s²: in doubt")
    for u in row.missed:
        s = row.sumo[u]
        if "decel_mps2" in s:
            ssm = ", ".join(f"{k} {v['value']:g} ({v['type']})" for k, v in s.get("ssm", {}).items()) or "no SSM conflict"
            held = f" (held over a second {s['held_mps2']:.1f})" if s.get("held_mps2") is not None else ""
            out.append(f"    miss: SUMO says {u} braked for {i.vehicle} ({s['cause']}) at {s['decel_mps2']:.1f} m/s²{held} "
                       f"from {s['t_s']:.1f}s, {s.get('from_mps') or s['speed_mps']:.1f} -> {s['min_speed_mps']:.1f} m/s; "
                       f"{ssm}")
        else:
            near = f"{s['nearest_m']:.1f} m from it at the nearest" if s.get("nearest_m") is not None \
                else "stepping in after it had passed"
            gap = f", PET {s['pet_s']:.1f} s" if s.get("pet_s") is not None else ""
            out.append(f"    miss: SUMO has pedestrian {u} in its path on {s['crossing']}, {near}{gap}")
    return out


def table(name: str, rows: list[Row], unraised: int) -> dict[str, int]:
    counts = {"incidents": len(rows), "agreeing": sum(r.agrees for r in rows), "unraised": unraised,
              "false_accusations": sum(len(r.false) for r in rows), "misses": sum(len(r.missed) for r in rows),
              "incidents_with_false": sum(bool(r.false) for r in rows),
              "incidents_with_miss": sum(bool(r.missed) for r in rows),
              "not_proven": sum(len(r.not_proven) for r in rows)}
    print(f"{name:<22} {counts['incidents']:>9} {counts['agreeing']:>9} {counts['false_accusations']:>7} "
          f"({counts['incidents_with_false']:>3} inc) {counts['misses']:>6} ({counts['incidents_with_miss']:>3} inc) "
          f"{counts['not_proven']:>10} {unraised:>8}")
    return counts


HEADER = (f"{'run':<22} {'incidents':>9} {'agreeing':>9} {'false accusations':>17} {'misses':>12} "
          f"{'not proven':>10} {'unraised':>8}")


def cost(cfg: SimConfig, repeats: int) -> dict[str, list[float]]:
    """A run's simulation with and without SUMO's account, alternately: wall and CPU seconds."""
    from sim_replay.simulation import Simulation

    out: dict[str, list[float]] = {"without": [], "with": [], "without_cpu": [], "with_cpu": []}
    for _ in range(repeats):
        for label, on in (("without", False), ("with", True)):
            started, cpu = time.perf_counter(), time.process_time()
            for _event in Simulation(cfg, account=on).events():
                pass
            out[label].append(round(time.perf_counter() - started, 2))
            out[label + "_cpu"].append(round(time.process_time() - cpu, 2))
    return out


def _record(args: argparse.Namespace, results: dict[str, Any]) -> None:
    total = results["total"]
    figures = [Figure("Stop, Give Way and emergency-red incidents compared", total["incidents"], "incidents"),
               Figure("agreeing with SUMO's account", total["agreeing"], "incidents", peer=(
                   "Stop, Give Way and emergency-red incidents compared" if total["incidents"] else "")),
               Figure("false accusations (reasoner: forced or endangered; SUMO: not for it)",
                      total["false_accusations"], "road users"),
               Figure("misses (SUMO: gave way to it or in its path; reasoner: not named)", total["misses"], "road users"),
               Figure("not proven (SUMO: gave way to it; reasoner: measured the same braking, in doubt within "
                      "its uncertainty)", total.get("not_proven", 0), "road users"),
               Figure("unraised (seen, no incident, SUMO: someone gave way to it)", total["unraised"], "acts"),
               Figure("wall time, all runs", results["wall_s"], "s")]
    for name, c in results.get("cost_s", {}).items():
        without, with_ = sorted(c["without"])[len(c["without"]) // 2], sorted(c["with"])[len(c["with"]) // 2]
        figures += [Figure(f"{name} simulation without SUMO's account", without, "s", tuple(c["without"])),
                    Figure(f"{name} simulation with SUMO's account", with_, "s", tuple(c["with"]),
                           peer=f"{name} simulation without SUMO's account")]
    runs = ", ".join(f"{r} ({v['config']['vehicles']} vehicles)" for r, v in results["runs"].items())
    record("conflict_agreement", "The reasoner's forced / endangered grounds against SUMO's own account", figures,
           notes=f"{args.minutes:g} world minutes per run, faults on: {runs}", details=results)


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--minutes", type=float, default=3.0 if quick() else 10.0,
                    help="world minutes per run (default 10; BENCH_QUICK=1: 3)")
    ap.add_argument("--seeds", default="11,12")
    ap.add_argument("--maps", default="paper,town")
    ap.add_argument("--keep", type=Path, help="keep each run's store and truth in this directory")
    ap.add_argument("--judge", type=Path, metavar="DIR",
                    help="judge the stores and truths an earlier --keep DIR kept, without simulating again")
    ap.add_argument("--json", action="store_true", help="print the figures as JSON at the end")
    ap.add_argument("--cost", action="store_true", help="also time the demo with and without SUMO's account")
    args = ap.parse_args(argv)
    started = time.perf_counter()
    results: dict[str, Any] = {"runs": {}}
    if args.cost:
        from sim_replay.demo import DEMO

        for name, cfg, repeats in (("demo", DEMO, 3), (f"paper {args.minutes:g} min", config("paper", 11, args.minutes), 1)):
            c = results.setdefault("cost_s", {})[name] = cost(cfg, repeats)
            print(f"{name} simulation ({cfg.duration_s:.0f} s world, {cfg.vehicles} vehicles): without SUMO's account "
                  f"{c['without']} s (CPU {c['without_cpu']}), with {c['with']} s (CPU {c['with_cpu']})", flush=True)
    per_run: list[tuple[str, list[Row], list[dict[str, Any]]]] = []
    split: dict[str, list[tuple[dict[str, Any], list[Any]]]] = {}
    with tempfile.TemporaryDirectory(prefix="gaps-agree-") as tmp:
        where = args.keep or Path(tmp)
        where.mkdir(parents=True, exist_ok=True)
        for map_name in args.maps.split(","):
            for seed in (int(s) for s in args.seeds.split(",")):
                cfg = config(map_name, seed, args.minutes)
                if args.judge:
                    truth, took, db = kept(args.judge, cfg.run)
                else:
                    db = where / f"{cfg.run}.db"
                    for old in where.glob(db.name + "*"):
                        old.unlink()
                    truth, took = simulate(cfg, db)
                    (where / f"{cfg.run}.truth.json").write_text(json.dumps(truth) + "\n", encoding="utf-8")
                incidents, took["judge_s"] = judged(db, cfg.run)
                rows, unraised = compare(truth, incidents)
                per_run.append((cfg.run, rows, unraised))
                split[cfg.run] = split_verdicts(truth, incidents)
                results["runs"][cfg.run] = {"config": {"map": map_name, "seed": seed, "vehicles": cfg.vehicles,
                                                       "world_s": cfg.duration_s},
                                            "took": {k: round(v, 1) for k, v in took.items()},
                                            "incidents_all": len(incidents), "yields": len(truth.get("yields", [])),
                                            "conflicts": len(truth.get("conflicts", []))}
                print(f"{cfg.run}: {cfg.vehicles} vehicles, {cfg.duration_s:.0f} s world; simulated in "
                      f"{took['simulate_s']:.0f} s ({took['events']:,} events, {len(truth.get('yields', []))} SUMO yields, "
                      f"{len(truth.get('conflicts', []))} SSM conflicts), stored in {took['append_s']:.0f} s, judged in "
                      f"{took['judge_s']:.0f} s: {len(incidents)} incidents, {len(rows)} Stop/Give Way/emergency-red",
                      flush=True)
    print()
    print(HEADER)
    for run, rows, unraised in per_run:
        results["runs"][run]["table"] = table(run, rows, len(unraised))
    results["total"] = table("total", [r for _, rows, _ in per_run for r in rows],
                             sum(len(u) for _, _, u in per_run))
    print()
    print("disagreements:")
    for run, rows, unraised in per_run:
        bad = [r for r in rows if not r.agrees]
        if bad or unraised:
            print(f" {run}")
            for r in bad:
                print("\n".join(describe(r)))
            for a in unraised:
                who = ", ".join(f"{u} ({s['cause']}{', %.1f m/s²' % s['decel_mps2'] if 'decel_mps2' in s else ''})"
                                for u, s in sorted(sumo_gave_way(a).items()))
                print(f"  unraised: vehicle {a['vehicle']} at {a['t_s']:.1f}s {a['junction']}/{a['approach']} {a['line']}"
                      f" seen by {','.join(a['seen_by'])}, no incident; SUMO: {who} gave way to it or was in its path")
    print()
    print("one act, different verdicts (every act of the truth judged by more than one incident):")
    for run, found in split.items():
        results["runs"][run]["split_verdicts"] = len(found)
        for a, incs in found:
            print(f"  {run} vehicle {a['vehicle']} {a['kind']} at {a['t_s']:.1f}s {a['junction'] or ''}: "
                  + "; ".join(f"{i.id} {i.verdict} {i.rule or ''}" for i in incs))
    print(f" {sum(len(f) for f in split.values())} acts")
    results["wall_s"] = round(time.perf_counter() - started, 1)
    print(f"\nwall time {results['wall_s']:.0f} s")
    if not args.judge:          # a re-judgement of kept runs is a check, not the bench's figures
        _record(args, results)
    if args.json:
        print(json.dumps(results, indent=1, default=str))
    return 0


if __name__ == "__main__":
    sys.exit(main())
