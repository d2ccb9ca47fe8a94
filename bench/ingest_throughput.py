"""Quick end-to-end throughput check of publisher → Zenoh → ingest → store (a benchmark, not a test).

    .venv/bin/python bench/ingest_throughput.py [--events 50000] [--not-durable] [--same-process]

The publisher runs in a child process by default so that it does not share the GIL with the ingest; the
raw Zenoh rate (a subscriber that only counts) is measured the same way for comparison.
"""
from __future__ import annotations

import argparse
import multiprocessing as mp
import socket
import sys
import tempfile
import threading
import time
from pathlib import Path


import zenoh

from ingest import IngestService, session_config
from ingest.service import BATCH_SIZE
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store

sys.path.insert(0, str(Path(__file__).resolve().parent))
from results import Figure, quick, record  # noqa: E402  (bench/results.py, beside this file)

RUN = "bench"
VEHICLES = 100


def endpoint() -> str:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{sock.getsockname()[1]}"


def events(n: int):
    """Small valid events, round-robin over VEHICLES sources, alternating two kinds."""
    for i in range(n):
        seq, ident = divmod(i, VEHICLES)
        if seq % 2:
            kind, body = "entity.state", {"x": float(seq), "y": 0.0, "speed_mps": 8.0}
        else:
            kind, body = "vehicle.perception", {"facts": [f"{ident} has red light"]}
        yield {"v": 1, "run": RUN, "src": f"vehicle/{ident}", "seq": seq, "t": 1_700_000_000_000_000_000 + i,
               "kind": kind, "body": body}


def publish(connect: str, n: int) -> None:
    """Child process: connect, wait for the subscriber, publish n events, linger until told to stop."""
    with EventPublisher(config=zenoh_config(connect=[connect])) as publisher:
        first = next(events(1))
        for probe in events(2):
            if not publisher.wait_until_matched(probe, 10):
                raise SystemExit("no subscriber")
        del first
        t0 = time.perf_counter()
        publisher.publish_all(events(n))
        print(f"  publisher: put {n} in {time.perf_counter() - t0:.2f} s", flush=True)
        time.sleep(30)  # closed by the parent once everything arrived; closing early could drop the tail


def start_publisher(connect: str, n: int, same_process: bool):
    if same_process:
        thread = threading.Thread(target=publish, args=(connect, n), daemon=True)
        thread.start()
        return None
    proc = mp.get_context("spawn").Process(target=publish, args=(connect, n), daemon=True)
    proc.start()
    return proc


def raw_rate(n: int, same_process: bool) -> float:
    """Samples/s of a subscriber that only counts: the ceiling the ingest is compared with."""
    ep = endpoint()
    done, count, t0 = threading.Event(), [0], [0.0]

    def on_sample(_: zenoh.Sample) -> None:
        if count[0] == 0:
            t0[0] = time.perf_counter()
        count[0] += 1
        if count[0] == n:
            done.set()

    with zenoh.open(session_config(listen=[ep])) as session:
        sub = session.declare_subscriber("gaps/**", on_sample)
        proc = start_publisher(ep, n, same_process)
        done.wait(120)
        rate = (count[0] - 1) / (time.perf_counter() - t0[0])
        sub.undeclare()
    if proc is not None:
        proc.kill()
    return rate


def ingest_rate(n: int, durable: bool, same_process: bool, batch_size: int) -> tuple[float, dict]:
    """Events/s committed to the store, from the first sample received to the last event stored."""
    ep = endpoint()
    with tempfile.TemporaryDirectory() as tmp:
        db = Path(tmp) / "bench.db"
        with IngestService(db, listen=[ep], durable=durable, batch_size=batch_size) as ingest:
            proc = start_publisher(ep, n, same_process)
            ingest.wait_for(lambda s: s["received"] >= 1, 60)
            t0 = time.perf_counter()
            ok = ingest.wait_until_stored(n, 300)
            elapsed = time.perf_counter() - t0
            stats = ingest.stats()
        if proc is not None:
            proc.kill()
        with Store(db) as store:
            assert ok and store.count(RUN) == n, (ok, stats)
            assert store.verify(RUN).ok
    return n / elapsed, stats


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=5_000 if quick() else 50_000)
    parser.add_argument("--not-durable", action="store_true")
    parser.add_argument("--same-process", action="store_true")
    parser.add_argument("--batch-size", type=int, default=BATCH_SIZE)
    args = parser.parse_args()
    where = "same process" if args.same_process else "publisher in a child process"
    print(f"{args.events} events, {where}, durable={not args.not_durable}, batch_size={args.batch_size}")
    raw = raw_rate(args.events, args.same_process)
    print(f"raw zenoh pub→sub: {raw:,.0f} samples/s")
    rate, stats = ingest_rate(args.events, not args.not_durable, args.same_process, args.batch_size)
    print(f"ingest → store:    {rate:,.0f} events/s ({rate / raw:.2f} × raw); {stats['batches']} batches, "
          f"mean {stats['stored'] / stats['batches']:.0f} per batch, errors {stats['errors']}")
    raw_name = "raw Zenoh pub→sub (a subscriber that only counts)"
    record("ingest_throughput", "Publisher → Zenoh → ingest → store, end to end",
           [Figure(raw_name, raw, "samples/s"),
            Figure("ingest → store", rate, "events/s", peer=raw_name,
                   note=f"{stats['batches']} batches, errors {stats['errors']}")],
           notes=f"{args.events:,} small events, {where}, durable={not args.not_durable}, "
                 f"batch_size={args.batch_size}; one run each")


if __name__ == "__main__":
    main()
