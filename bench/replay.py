"""`gaps replay --speed max` into a running `gaps serve`: events per second, sent and stored.

    .venv/bin/python bench/replay.py [--dir /tmp/gaps-bench] [--repeats 3] [--json]

Issue 16's target: replay at max speed >= 50,000 events/s into a running ingest. A `gaps serve`
child listens on a loopback port with a fresh store; the run (the same as bench/regress.py's: the
one-hour town run, BENCH_QUICK=1 the golden run) is replayed from its store onto Zenoh, RELIABLE
with BLOCK, so a slow ingest slows the replay and nothing is dropped.

    sent    events / the replay's wall time (publishing, paced by the ingest's back-pressure)
    stored  events / the time from the replay's start until the ingest's store holds them all
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

from results import Figure, record  # bench/results.py, beside this file
from regress import inputs  # bench/regress.py, beside this file

TARGET = 50_000.0
ROOT = Path(__file__).resolve().parents[1]


def once(db: Path, run: str, directory: Path) -> dict[str, float]:
    sys.path.insert(0, str(ROOT))
    from sim_replay.replay import replay
    from store import Store
    from tests.helpers.ingest_testkit import free_endpoint
    from tests.helpers.serve_testkit import ServeProcess

    endpoint = free_endpoint()
    with tempfile.TemporaryDirectory(prefix="gaps-bench-replay-", dir=directory) as tmp:
        live = Path(tmp) / "live.db"
        serve = ServeProcess(live, endpoint)
        try:
            serve.wait_for_log("serve.ready")
            with Store.open_read_only(db) as store:
                total = store.count(run)
                started = time.perf_counter()
                replay(store, [run], connect=[endpoint], speed=None)
                sent = time.perf_counter() - started
            stored = _until_stored(live, run, total, started)
            code, _ = serve.stop()
        finally:
            serve.proc.kill() if serve.proc.poll() is None else None
    if code != 0:
        raise SystemExit(f"gaps serve ended with {code}: {serve.lines[-5:]}")
    return {"events": total, "sent_s": sent, "stored_s": stored}


def _until_stored(live: Path, run: str, total: int, started: float, timeout_s: float = 600.0) -> float:
    """Seconds from `started` until the live store holds `total` events of the run."""
    from store import Store
    deadline = time.monotonic() + timeout_s
    while time.monotonic() < deadline:
        try:
            with Store.open_read_only(live) as store:
                if run in store.run_names() and store.count(run) >= total:
                    return time.perf_counter() - started
        except Exception:                      # the ingest is still creating its file
            pass
        time.sleep(0.05)
    raise SystemExit(f"the ingest did not store {total} events within {timeout_s} s")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dir", type=Path, default=Path("/tmp/gaps-bench"))
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    args.dir.mkdir(parents=True, exist_ok=True)
    db, _, run = inputs(args.dir)
    rounds, load = [], [os.getloadavg()[0]]
    for i in range(args.repeats):
        r = once(db, run, args.dir)
        rounds.append(r)
        load.append(os.getloadavg()[0])
        print(f"round {i + 1}: {r['events']:,} events sent in {r['sent_s']:.2f} s ({r['events'] / r['sent_s']:,.0f}/s), "
              f"all stored after {r['stored_s']:.2f} s ({r['events'] / r['stored_s']:,.0f}/s)", flush=True)
    n = rounds[0]["events"]
    sent = [n / r["sent_s"] for r in rounds]
    stored = [n / r["stored_s"] for r in rounds]
    print(f"replay at max speed into gaps serve: median {statistics.median(sent):,.0f} events/s sent, "
          f"{statistics.median(stored):,.0f} events/s stored (target {TARGET:,.0f}/s); load average "
          f"{', '.join(f'{x:.2f}' for x in load)}")
    record("replay", "Replay at max speed into a running ingest", [
        Figure("events sent per second (replay at max speed)", statistics.median(sent), "events/s", tuple(sent),
               target=f"≥ {TARGET:,.0f} events/s"),
        Figure("events stored per second by the receiving gaps serve", statistics.median(stored), "events/s",
               tuple(stored), target=f"≥ {TARGET:,.0f} events/s")],
        notes=f"run {run}, {n:,} events, replayed from a store into `gaps serve` on loopback; median of {len(rounds)}",
        machine_extra=f"load average during the bench {', '.join(f'{x:.2f}' for x in load)}")
    if args.json:
        print(json.dumps(rounds, indent=2))


if __name__ == "__main__":
    sys.exit(main())
