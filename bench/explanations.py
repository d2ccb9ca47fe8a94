"""Explaining the incidents of a long run: what one explanation costs once the run is judged.

    .venv/bin/python bench/explanations.py [--explain 20] [--dir /tmp/gaps-bench] [--json]

Before issue 11 every explanation re-hashed the whole run to say whether its chain verified
(8.3 s for one incident of a 355,000-event run). Now an investigation checks each run's chain
once and every explanation cites that. Measured on the simulated run of bench/sim_runs.py (the
working copy bench/incidents.py judged; recorded if missing), through the public API, read-only:

    judge     case.incidents(run): every incident judged (the investigation loads once)
    chain     the run's hash chain recomputed: what each explanation used to pay on top
    first     the first explanation (pays the chain check)
    each      every further explanation, median over --explain incidents spread over the run

Peer: "each" is compared with "chain", measured in the same run.
"""
from __future__ import annotations

import argparse
import json
import statistics
import time
from pathlib import Path

from machine import machine  # bench/machine.py, beside this file
from results import Figure, quick, record  # bench/results.py, beside this file
from sim_runs import RUN, work_file  # bench/sim_runs.py, beside this file


def seconds(call) -> tuple[float, object]:
    started = time.perf_counter()
    out = call()
    return time.perf_counter() - started, out


def measure(path: Path, count: int) -> dict:
    import explain
    import reasoner
    from reasoner.chain_status import chain_status

    with reasoner.open(path) as case:
        judge_s, found = seconds(lambda: case.incidents(RUN))
        chain_s, status = seconds(lambda: chain_status(case.store, RUN))
        step = max(1, len(found) // count)
        chosen = found[::step][:count]
        first_s, _ = seconds(lambda: explain.explanation(case, chosen[0]))
        each = [seconds(lambda inc=inc: explain.explanation(case, inc))[0] for inc in chosen[1:]]
        events = case.store.count(RUN)
    return {"events": events, "incidents": len(found), "judge_s": judge_s, "chain_s": chain_s,
            "chain_verified": status.verified, "first_s": first_s, "each_s": each, "explained": len(chosen)}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", type=Path, default=Path("/tmp/gaps-bench"))
    parser.add_argument("--explain", type=int, default=10 if quick() else 20)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)
    result = measure(work_file(args.dir, fresh=False), args.explain)
    result["machine"] = machine()
    each = statistics.median(result["each_s"])
    record("explanations", "Explaining the incidents of a simulated run", [
        Figure("every incident judged (case.incidents)", result["judge_s"], "s"),
        Figure("the run's hash chain recomputed (once per investigation)", result["chain_s"], "s"),
        Figure("the first explanation (includes the chain check)", result["first_s"], "s"),
        Figure("each further explanation", each, "s", tuple(result["each_s"]),
               peer="the run's hash chain recomputed (once per investigation)",
               note="before issue 11 each explanation also recomputed the chain")],
        notes=f"{RUN}: {result['events']:,} events, {result['incidents']} incidents, "
              f"{result['explained']} explained (spread over the run)")
    if args.json:
        print(json.dumps(result, indent=2))
        return
    print(f"machine: {result['machine']}")
    print(f"{RUN}: {result['events']:,} events, {result['incidents']} incidents")
    print(f"judged every incident in {result['judge_s']:.2f} s; chain recomputed in {result['chain_s']:.2f} s "
          f"(verified: {result['chain_verified']})")
    print(f"first explanation {result['first_s']:.2f} s; each further one median {each * 1000:.0f} ms "
          f"over {len(result['each_s'])} (max {max(result['each_s']) * 1000:.0f} ms); "
          f"a chain check per explanation would add {result['chain_s']:.2f} s to each")


if __name__ == "__main__":
    main()
