"""Append throughput of the store against raw SQLite inserts, measured in one run (a benchmark, not a test).

    .venv/bin/python bench/append.py [--events 200000] [--batch 10000] [--repeat 5] [--json]

The producer is this Python process holding the events as dicts: the generated junction run of
bench/transfer.py (100 road users at 10 Hz: states, perceptions, decisions, signal changes).
With --small, minimal events instead (100 vehicles alternating a three-field state and a one-fact
perception, ~150 bytes), to show how the rate depends on event size.
The report ends with the CPU cost of the steps (a) does beyond (b), each timed alone.

(a) Store.append, in batches: full validation (envelope and JSON Schema of the body), canonical
    JSON, hash chain, Merkle frontier, checkpoints every 1000 events, synchronous=FULL, each batch
    committed before append returns. Also (a') the same with durable=False (synchronous=NORMAL).
(b) raw executemany of exactly the rows (a) stored into the same schema (a fresh store file, same
    pragmas, indexes and triggers), same batches and commits, synchronous=FULL: no validation, no
    JSON, no chain, no checkpoints. The floor a Python producer could reach with this schema.

Each is repeated on fresh files and the median taken. Rates are events per second of wall time,
with CPU time beside it (the steadier figure on a shared machine: wall time includes waiting for
fsync and for other processes). Bytes per event is the store file after a WAL checkpoint
(TRUNCATE) divided by the events, without VACUUM.
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
from typing import Callable

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from store import Store, canonical_json, validate_event  # noqa: E402
from store.chain import RunChain  # noqa: E402
from machine import QUIET_MS, calibration  # noqa: E402  (bench/machine.py, beside this file)
from results import Figure, quick, record  # noqa: E402  (bench/results.py, beside this file)
from transfer import generated_run, machine  # noqa: E402  (bench/transfer.py, beside this file)

INSERT = "INSERT INTO events (run, chain_pos, src, seq, t, kind, event, hash) VALUES (?, ?, ?, ?, ?, ?, ?, ?)"
Timing = tuple[float, float]  # wall seconds, CPU seconds


def small_events(n: int) -> list[dict]:
    """n minimal valid events: each of 100 vehicles alternates entity.state and vehicle.perception."""
    out = []
    for i in range(n):
        seq, vehicle = divmod(i, 100)
        if seq % 2:
            kind, body = "entity.state", {"x": float(seq), "y": 0.0, "speed_mps": 8.0}
        else:
            kind, body = "vehicle.perception", {"facts": [f"{vehicle} has red light"]}
        out.append({"v": 1, "run": "bench-small", "src": f"vehicle/{vehicle}", "seq": seq,
                    "t": 1_732_184_100_000_000_000 + i * 1_000_000, "kind": kind, "body": body})
    return out


def timed(step: Callable[[], None]) -> Timing:
    wall, cpu = time.perf_counter(), time.process_time()
    step()
    return time.perf_counter() - wall, time.process_time() - cpu


def batches(items: list, size: int) -> list[list]:
    return [items[i:i + size] for i in range(0, len(items), size)]


def store_append(path: Path, events: list[list[dict]], durable: bool) -> Timing:
    """(a): the store's own append, one call per batch."""
    with Store(path, durable=durable) as store:
        def run() -> None:
            for batch in events:
                report = store.append(batch)
                assert report.stored == len(batch) and not report.rejected, report.rejected[:3]
        return timed(run)


def raw_insert(path: Path, rows: list[list[tuple]]) -> Timing:
    """(b): the same rows, straight into a fresh store file of the same schema and pragmas."""
    with Store(path) as store:
        conn = store.connection

        def run() -> None:
            for batch in rows:
                conn.execute("BEGIN IMMEDIATE")
                conn.executemany(INSERT, batch)
                conn.execute("COMMIT")
        return timed(run)


def stored_rows(path: Path) -> list[tuple]:
    with Store(path) as store:
        return store.connection.execute(
            "SELECT run, chain_pos, src, seq, t, kind, event, hash FROM events ORDER BY run, chain_pos").fetchall()


def bytes_per_event(path: Path, events: int) -> float:
    with Store(path) as store:
        store.connection.execute("PRAGMA wal_checkpoint(TRUNCATE)")
    return path.stat().st_size / events


def median(timings: list[Timing]) -> Timing:
    return statistics.median(t[0] for t in timings), statistics.median(t[1] for t in timings)


def measure(n: int, batch: int, repeat: int, folder: Path, small: bool) -> dict:
    events = small_events(n) if small else list(generated_run(n))
    in_batches = batches(events, batch)
    full, normal, raw, sizes = [], [], [], {}
    for i in range(repeat):
        full.append(store_append(folder / f"full-{i}.db", in_batches, durable=True))
        normal.append(store_append(folder / f"normal-{i}.db", in_batches, durable=False))
        rows = batches(stored_rows(folder / f"full-{i}.db"), batch)
        raw.append(raw_insert(folder / f"raw-{i}.db", rows))
        if i == 0:
            with Store(folder / "full-0.db") as store:
                verify = timed(lambda: _assert_verified(store))
            sizes = {"store": bytes_per_event(folder / "full-0.db", len(events)),
                     "raw": bytes_per_event(folder / "raw-0.db", len(events))}
        for name in ("full", "normal", "raw"):
            (folder / f"{name}-{i}.db").unlink()
    size = sum(len(canonical_json(ev)) for ev in events) / len(events)
    return {"events": len(events), "event_bytes": size, "batch": batch, "repeat": repeat,
            "append_full": median(full), "append_normal": median(normal), "raw_full": median(raw),
            "runs": {"append_full": full, "append_normal": normal, "raw_full": raw},
            "verify": verify, "bytes_per_event": sizes, "cpu_us_per_event": breakdown(events, 3)}


def _assert_verified(store: Store) -> None:
    assert store.verify().ok


def breakdown(events: list[dict], repeat: int) -> dict[str, float]:
    """CPU µs per event of the steps of (a) that (b) does not do, each alone (best of `repeat`)."""
    texts = [canonical_json(ev) for ev in events]

    def chain() -> None:
        run = RunChain()
        for text in texts:
            run.extend(text)

    # Loops that drop each result, as append does: keeping 200,000 results alive would time the
    # allocator's page faults rather than the step.
    def check() -> None:
        for ev in events:
            validate_event(ev)

    def encode() -> None:
        for ev in events:
            canonical_json(ev)

    steps = {"envelope and JSON Schema checks": check,
             "canonical JSON": encode,
             "sha256 chain and Merkle frontier": chain}
    return {name: min(timed(step)[1] for _ in range(repeat)) / len(events) * 1e6 for name, step in steps.items()}


def report(r: dict, load: tuple[str, str]) -> str:
    n = r["events"]

    def rate(key: str) -> str:
        wall, cpu = r[key]
        return f"{n / wall:>10,.0f} /s  (CPU {n / cpu:>9,.0f} /s, {cpu / n * 1e6:5.2f} µs/event)"

    ours, raw = r["append_full"], r["raw_full"]
    lines = [
        f"machine: {machine()}",
        f"load average before / after: {load[0]} / {load[1]}",
        f"{n:,} events of {r['event_bytes']:.0f} bytes on average (canonical JSON) in batches of "
        f"{r['batch']:,}; median of {r['repeat']} runs on fresh files",
        "",
        f"(a)  Store.append, validation + chain + Merkle, FULL  {rate('append_full')}",
        f"(a') Store.append, the same, durable=False (NORMAL)   {rate('append_normal')}",
        f"(b)  raw executemany of the same rows, FULL           {rate('raw_full')}",
        f"ratio (a)/(b): {raw[0] / ours[0]:.2f} of the raw rate by wall time, {raw[1] / ours[1]:.2f} by CPU time",
        f"verify (recompute chain, Merkle, checkpoints): {n / r['verify'][0]:,.0f} events/s",
        f"bytes per event on disk: {r['bytes_per_event']['store']:.0f} (store), "
        f"{r['bytes_per_event']['raw']:.0f} (raw rows, no checkpoints)",
        f"CPU of (a) beyond (b): {(ours[1] - raw[1]) / n * 1e6:.2f} µs/event, of which, each step alone:",
        *(f"  {name}: {us:.2f} µs" for name, us in r["cpu_us_per_event"].items()),
    ]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=20_000 if quick() else 200_000)
    parser.add_argument("--batch", type=int, default=5_000 if quick() else 10_000)
    parser.add_argument("--repeat", type=int, default=3 if quick() else 5)
    parser.add_argument("--small", action="store_true", help="minimal events instead of the junction run")
    parser.add_argument("--json", action="store_true", help="print the figures as JSON")
    args = parser.parse_args()
    before = " ".join(f"{x:.2f}" for x in os.getloadavg()) + f" (calibration {calibration():.2f} ms)"
    with tempfile.TemporaryDirectory(prefix="gaps-bench-append-") as tmp:
        result = measure(args.events, args.batch, args.repeat, Path(tmp), args.small)
    after = " ".join(f"{x:.2f}" for x in os.getloadavg()) + f" (calibration {calibration():.2f} ms; {QUIET_MS})"
    if args.json:
        print(json.dumps({"machine": machine(), "load": [before, after], **result}, indent=2))
    else:
        print(report(result, (before, after)))
    record_result(result, (before, after), args.small)


def record_result(r: dict, load: tuple[str, str], small: bool) -> None:
    """The figures of report() into bench/results.json: (a), (a') and (b) with (b) as the peer."""
    n = r["events"]

    def figure(key: str, name: str, **extra: str) -> Figure:
        runs = tuple(n / wall for wall, _ in r["runs"][key])
        return Figure(name, n / r[key][0], "events/s", runs,
                      note=f"{n / r[key][1]:,.0f} per CPU second, {r[key][1] / n * 1e6:.2f} µs/event", **extra)

    raw = "raw executemany of the same rows, FULL"
    figures = [figure("append_full", "Store.append: validation, chain, Merkle, checkpoints, synchronous=FULL",
                      target="100,000/s", peer=raw),
               figure("append_normal", "the same with durable=False (synchronous=NORMAL)", peer=raw),
               figure("raw_full", raw),
               Figure("verify (chain, Merkle roots, checkpoints)", n / r["verify"][0], "events/s"),
               Figure("bytes per event on disk (after a WAL checkpoint, no VACUUM)",
                      r["bytes_per_event"]["store"], "bytes")]
    figures += [Figure(f"CPU beyond the raw insert: {name}", us, "µs/event") for name, us in r["cpu_us_per_event"].items()]
    kind = "minimal events (--small)" if small else "the generated junction run of bench/transfer.py"
    record("append", "Appending to the store, against raw SQLite inserts", figures,
           machine_extra=f"load average before / after {load[0]} / {load[1]}",
           notes=f"{n:,} events of {r['event_bytes']:.0f} bytes on average (canonical JSON), {kind}, in batches "
                 f"of {r['batch']:,}; median of {r['repeat']} runs on fresh files")


if __name__ == "__main__":
    main()
