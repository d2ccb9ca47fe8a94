"""Fleet-shaped load into `gaps serve`: many short runs of many sources against the same events in
one run (a benchmark, not a test).

    .venv/bin/python bench/ingest_fleet.py [--runs 1000] [--events-per-run 76] [--repeat 3]
                                           [--more-runs 10000] [--baseline CHECKOUT]

A foreign producer (a plain Zenoh session in a child process, putting each event's canonical JSON
on its key, as a vendor's code would) publishes `--runs` runs of `--events-per-run` events each:
per run its `run.start` with its map (tests/helpers/foreign.py: a signalled crossroads, its roads
and a camera), then 34 vehicles' `entity.spawn` and `entity.state`, and its `run.end` (35 sources a run,
35,000 for 1,000 runs). Beside it, alternately, the same number of events as one run (the same shape: one
run.start, then the 34 vehicles' states over and over). `gaps serve` on loopback, a fresh store
each time; the rate is the events over the seconds from the first put to the serve's status line
counting them all stored (the time the serve stamped on that line, not when this bench read it).
Printed: both rates and their ratio (target >= 0.8), per repeat and the medians; then, with
`--more-runs`, `--more-runs` runs in one stream, the rate of each tenth of it (none may fall below
0.8 x the one run's). A tenth ends at the first status line counting a tenth more settled, and its
rate is the events those lines count between its start and its end over the seconds between them,
not a tenth's events: the writer commits 10,000 at a time, so the line that ends a tenth counts up
to a batch more than the tenth (charging each tenth a tenth's events took from the first tenth,
timed from the first put, the seconds of up to a batch beyond them, 2-9% of its rate here, and
moved every other tenth by up to 13% either way).
The first tenth is timed from the first put as the one run is: it pays, as the one run does, the
first batch's wait and commit before anything is counted, and the producer's start, which puts
some 150,000 events into Zenoh's channel in its first second (docs/serve.md, "The first tenth").
Then the serve's resident memory idle before the
producer, at its peak, and 5 s after the last run ended (target: within 10% of idle). With
`--baseline`, the many runs are measured with the other checkout's serve too, after this one's.
"""
from __future__ import annotations

import argparse
import json
import multiprocessing as mp
import os
import statistics
import sys
import tempfile
import time
from datetime import datetime
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from results import Figure, quick, record  # noqa: E402
from tests.helpers.foreign import T0, Foreign  # noqa: E402
from tests.helpers.ingest_testkit import free_endpoint  # noqa: E402
from tests.helpers.serve_testkit import ServeProcess  # noqa: E402

VEHICLES = 34
TENTHS_NOTE = (
    "A tenth's rate: the events settled between the serve's status lines that bound it over the seconds the "
    "serve stamped on them (a line counts whole batches of up to 10,000; charging each tenth exactly a tenth's "
    "events, as this bench did before 2026-12-08, took 2-9% from the first tenth). The first tenth is timed "
    "from the first put, as the one run is, and pays the producer's start: it puts some 150,000 events in its "
    "first second (Zenoh's channel holds 100,000), and it and the serve's Zenoh threads took 0.67 of a core "
    "in the first tenth against about 0.33 later; the writer's CPU per event was the same as later (0.16-0.19 s "
    "per 10,000) but it was off the CPU 0.46-0.83 s of the tenth against 0.07-0.6 s in later ones "
    "(2 shared cores; docs/serve.md, 'The first tenth').")
SECOND = 1_000_000_000


def fleet_run(n: int, per_run: int) -> list[dict]:
    """One short run: run.start (with its map), each vehicle's spawn, then states round-robin."""
    run = Foreign(run=f"fleet-{n:05d}")
    for v in range(VEHICLES):
        run.spawn(f"v{v}")
    k = 0
    while len(run.events) < per_run - 1:
        v = k % VEHICLES
        run.emit(f"vehicle/v{v}", T0 + (k + 1) * SECOND // 10, "entity.state",
                 {"x": float(k), "y": 1.75, "heading_deg": 0.0, "speed_mps": 10.0})
        k += 1
    run.emit("sim/camera-vendor", T0 + (k + 1) * SECOND // 10, "run.end", {"reason": "end of footage"})
    return run.events


def one_run(total: int) -> list[dict]:
    """The same number of events as one run of the same shape."""
    return fleet_run(0, total)


def payloads(events: list[dict]) -> list[tuple[str, bytes]]:
    from store.canonical import canonical_json
    return [(f"gaps/{e['run']}/{e['src']}/{e['kind']}", canonical_json(e)) for e in events]


def produce(endpoint: str, shape: str, runs: int, per_run: int, go, first_put, stored=None) -> None:
    """The producer's child process: builds its events, waits for `go`, puts them all, and keeps
    its session open until the serve has stored them (`stored`): samples still queued in the
    session when it closes are dropped, which on a slow serve left the bench waiting for ever."""
    import zenoh

    from sim_replay.publisher import zenoh_config
    if shape == "fleet":
        items = [p for n in range(runs) for p in payloads(fleet_run(n, per_run))]
    else:
        items = payloads(one_run(runs * per_run))
    session = zenoh.open(zenoh_config(connect=[endpoint]))
    try:
        go.wait()
        first_put.value = time.time()
        for key, payload in items:
            session.put(key, payload, encoding=zenoh.Encoding.APPLICATION_JSON,
                        congestion_control=zenoh.CongestionControl.BLOCK)
        if stored is None or not stored.wait(900):
            time.sleep(1.0)                  # let the last samples leave before the session closes
    finally:
        session.close()


def rss_mb(pid: int) -> float:
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) / 1024
    return 0.0


def serve_pid(serve: ServeProcess) -> int:
    return serve.proc.pid


def stored_at(serve: ServeProcess, total: int, timeout: float, tenths: list | None = None) -> float:
    """The time stamped on the first status line counting `total` settled; each tenth's too, as
    (its time, the events settled by then): the line that ends a tenth counts up to a batch more."""
    deadline = time.monotonic() + timeout
    seen = 0
    while time.monotonic() < deadline:
        for line in serve.lines[seen:]:
            seen += 1
            try:
                rec = json.loads(line)
            except ValueError:
                continue
            if rec.get("event") != "serve.status":
                continue
            stored = sum(rec.get(k, 0) for k in ("stored", "duplicates", "quarantined", "failed"))
            at = stamped(rec)
            if tenths is not None:
                while len(tenths) < 10 and stored >= total * (len(tenths) + 1) / 10:
                    tenths.append((at, stored))
            if stored >= total:
                return at
        time.sleep(0.05)
    raise TimeoutError(f"gaps serve did not store {total} events within {timeout} s: {serve.lines[-5:]}")


def stamped(rec: dict) -> float:
    """The wall time (as time.time) the serve wrote a log line: its reading, not this bench's
    polling, which came up to 0.05 s later."""
    return datetime.fromisoformat(rec["ts"].replace("Z", "+00:00")).timestamp()


def serve_command(code: Path | None) -> list[str]:
    """`gaps serve` of this checkout, or of another one (`--baseline CHECKOUT`: main, to compare)."""
    if code is None:
        return [sys.executable, "-m", "cli.main", "serve"]
    return [sys.executable, "-c", f"import sys; sys.path.insert(0, {str(code)!r}); sys.argv[0] = 'gaps'; "
            "from cli.main import main; main()", "serve"]


def one_pass(shape: str, runs: int, per_run: int, folder: Path, tenths: list | None = None,
             code: Path | None = None) -> dict:
    endpoint = free_endpoint()
    db = folder / f"{shape}-{time.monotonic_ns()}.db"
    serve = ServeProcess(db, endpoint, "--status-every", "0.1", command=serve_command(code))
    try:
        serve.wait_for_log("serve.ready", timeout=60)
        ctx = mp.get_context("spawn")
        go, first_put, stored = ctx.Event(), ctx.Value("d", 0.0), ctx.Event()
        producer = ctx.Process(target=produce, args=(endpoint, shape, runs, per_run, go, first_put, stored))
        producer.start()
        time.sleep(3.0)                                   # the producer built its events and linked
        idle = rss_mb(serve_pid(serve))
        go.set()
        total = runs * per_run
        peak = idle
        done_at = None
        started = time.monotonic()
        while done_at is None:
            if not producer.is_alive() and producer.exitcode:
                raise RuntimeError(f"the producer failed (exit {producer.exitcode})")
            peak = max(peak, rss_mb(serve_pid(serve)))
            try:
                done_at = stored_at(serve, total, 0.5, tenths)
            except TimeoutError:
                if time.monotonic() - started > 900:
                    raise
        seconds = done_at - first_put.value
        stored.set()
        producer.join(60)
        time.sleep(5.0)
        after = rss_mb(serve_pid(serve))
        return {"shape": shape, "events": total, "seconds": seconds, "rate": total / seconds,
                "rss_idle_mb": idle, "rss_peak_mb": peak, "rss_after_mb": after, "first_put": first_put.value}
    finally:
        serve.stop()


def many_runs(runs: int, per_run: int, folder: Path, code: Path | None) -> tuple[dict, list[float]]:
    """One pass of `runs` runs in one stream, and the rate of each tenth of it: the events settled
    between the status lines that bound it over the seconds between them (module docstring)."""
    tenths: list[tuple[float, int]] = []
    big = one_pass("fleet", runs, per_run, folder, tenths, code=code)
    starts = [(big["first_put"], 0), *tenths[:-1]]
    return big, [(settled - before) / (end - start) for (start, before), (end, settled) in zip(starts, tenths)]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=100 if quick() else 1000)
    parser.add_argument("--events-per-run", type=int, default=76)
    parser.add_argument("--repeat", type=int, default=1 if quick() else 3)
    parser.add_argument("--more-runs", type=int, default=1000 if quick() else 10_000)
    parser.add_argument("--baseline", type=Path, default=None,
                        help="another checkout (e.g. main's) whose serve is measured alternately, as `before`")
    parser.add_argument("--note", default="", help="said in the recorded notes (e.g. what the two serves are)")
    args = parser.parse_args()
    rows: dict[str, list[dict]] = {"one": [], "fleet": [], "one before": [], "fleet before": []}
    with tempfile.TemporaryDirectory(prefix="gaps-ingest-fleet-") as tmp:
        folder = Path(tmp)
        for n in range(args.repeat):
            for shape in ("one", "fleet") if n % 2 == 0 else ("fleet", "one"):
                for code, label in [(None, shape)] + ([(args.baseline, f"{shape} before")] if args.baseline else []):
                    row = one_pass(shape, args.runs, args.events_per_run, folder, code=code)
                    rows[label].append(row)
                    print(f"repeat {n + 1} {label:12}: {row['events']} events in {row['seconds']:.2f} s = "
                      f"{row['rate']:,.0f}/s; serve RSS idle {row['rss_idle_mb']:.0f} MB, peak "
                          f"{row['rss_peak_mb']:.0f} MB, after {row['rss_after_mb']:.0f} MB; load "
                          f"{os.getloadavg()[0]:.1f}", flush=True)
        one = statistics.median(r["rate"] for r in rows["one"])
        fleet = statistics.median(r["rate"] for r in rows["fleet"])
        ratios = [f["rate"] / o["rate"] for f, o in zip(rows["fleet"], rows["one"])]
        print(f"median: one run {one:,.0f}/s, {args.runs} runs {fleet:,.0f}/s = {fleet / one:.2f} x "
              f"(per repeat {', '.join(f'{r:.2f}' for r in ratios)}; target >= 0.8)", flush=True)
        figures = [Figure("one run", one, "events/s", tuple(r["rate"] for r in rows["one"])),
                   Figure(f"{args.runs} runs x {args.events_per_run}", fleet, "events/s",
                          tuple(r["rate"] for r in rows["fleet"]), target=">= 0.8 x one run", peer="one run")]
        if args.baseline:
            one_b = statistics.median(r["rate"] for r in rows["one before"])
            fleet_b = statistics.median(r["rate"] for r in rows["fleet before"])
            print(f"before ({args.baseline}), alternating with the above: one run {one_b:,.0f}/s, {args.runs} runs "
                  f"{fleet_b:,.0f}/s = {fleet_b / one_b:.2f} x", flush=True)
            figures += [Figure("one run, before", one_b, "events/s", tuple(r["rate"] for r in rows["one before"])),
                        Figure(f"{args.runs} runs x {args.events_per_run}, before", fleet_b, "events/s",
                               tuple(r["rate"] for r in rows["fleet before"]), peer="one run, before")]
        details = rows
        if args.more_runs:
            for code, label in [(None, "")] + ([(args.baseline, ", before")] if args.baseline else []):
                big, rates = many_runs(args.more_runs, args.events_per_run, folder, code)
                one = statistics.median(r["rate"] for r in rows["one" + (" before" if label else "")])
                print(f"{args.more_runs} runs{label}: {big['rate']:,.0f}/s overall; each tenth "
                      f"{', '.join(f'{r:,.0f}' for r in rates)}/s; lowest {min(rates) / one:.2f} x one run; serve "
                      f"RSS idle {big['rss_idle_mb']:.0f} MB, peak {big['rss_peak_mb']:.0f} MB, 5 s after "
                      f"{big['rss_after_mb']:.0f} MB ({big['rss_after_mb'] / big['rss_idle_mb']:.2f} x idle)", flush=True)
                peer = f"one run{label}"
                figures += [Figure(f"{args.more_runs} runs, overall{label}", big["rate"], "events/s", peer=peer),
                            Figure(f"{args.more_runs} runs, slowest tenth{label}", min(rates), "events/s", tuple(rates),
                                   target="" if label else ">= 0.8 x one run", peer=peer),
                            Figure(f"serve RSS after the runs / idle{label}", big["rss_after_mb"] / big["rss_idle_mb"],
                                   "x", target="" if label else "<= 1.1")]
                details["more" + label.replace(", ", " ")] = big | {"tenths": rates}
        record("ingest_fleet", f"{args.runs} runs x {args.events_per_run} events into gaps serve against one run",
               figures, notes=" ".join(filter(None, [args.note, TENTHS_NOTE if args.more_runs else ""])), details=details)


if __name__ == "__main__":
    main()
