"""What letting one run go costs while other runs are held: the gap tracker's and the store's
part (a benchmark, not a test).

    .venv/bin/python bench/run_release.py [--baseline CHECKOUT]

A fleet's run that ends (its run.end stored) or goes quiet (ingest/writer.py's RUN_QUIET_S) is let
go by the ingest's gap tracker and by the store's append cache (store/heads.py). Each used to walk
every source it held to find the run's, so with runs that never end piling up each release cost
more; now each keeps its sources by run. Printed and recorded: microseconds a run let go, with
100, 1,000 and 5,000 runs of 35 sources held. `--baseline` measures another checkout (e.g. a copy
of main) the same way, each in a process of its own.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from results import Figure, record  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
HELD = (100, 1000, 5000)
SOURCES = 35
RELEASED = 100


def measure(code: Path) -> dict[int, tuple[float, float]]:
    """Per number of runs held: (gap tracker, store) seconds to let one run go, with `code`'s modules."""
    sys.path.insert(0, str(code))
    from ingest.gap_tracker import GapTracker
    from store import Store
    from tests.helpers.store_testkit import event

    out = {}
    for held in HELD:
        tracker = GapTracker()
        tracker.observe_all([(f"r{n}", f"vehicle/{v}", 0) for n in range(held) for v in range(SOURCES)])
        started = time.perf_counter()
        for n in range(RELEASED):
            tracker.release([f"r{n}"])
        tracked = (time.perf_counter() - started) / RELEASED
        with tempfile.TemporaryDirectory(prefix="gaps-run-release-") as tmp:
            with Store(os.path.join(tmp, "release.db"), durable=False) as store:
                store.append([event(0, run=f"r{n}", src=f"vehicle/{v}", kind="entity.state")
                              for n in range(held) for v in range(SOURCES)])
                started = time.perf_counter()
                for n in range(RELEASED):
                    store._heads.release(f"r{n}")
                stored = (time.perf_counter() - started) / RELEASED
        out[held] = (tracked, stored)
    return out


def measured_in_its_own_process(code: Path) -> dict[int, tuple[float, float]]:
    done = subprocess.run([sys.executable, __file__, "--measure", str(code)], check=True, capture_output=True,
                          text=True)
    return {int(k): tuple(v) for k, v in json.loads(done.stdout).items()}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--baseline", type=Path, default=None, help="another checkout, measured as `before`")
    parser.add_argument("--measure", type=Path, default=None, help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.measure is not None:
        print(json.dumps(measure(args.measure)))
        return
    figures = []
    for code, label in [(ROOT, "")] + ([(args.baseline, ", before")] if args.baseline else []):
        for held, (tracked, stored) in measured_in_its_own_process(code).items():
            print(f"{held:5,} runs of {SOURCES} sources held{label}: letting one go costs the gap tracker "
                  f"{tracked * 1e6:9,.1f} us, the store {stored * 1e6:9,.1f} us", flush=True)
            figures += [Figure(f"{held} runs held: gap tracker{label}", tracked * 1e6, "us a run let go"),
                        Figure(f"{held} runs held: store{label}", stored * 1e6, "us a run let go")]
    record("run_release", f"letting one run go with runs of {SOURCES} sources held", figures)


if __name__ == "__main__":
    main()
