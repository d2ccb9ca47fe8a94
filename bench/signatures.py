"""What requiring signatures costs the ingest (a benchmark, not a test).

    .venv/bin/python bench/signatures.py [--events 30000] [--runs 3]

In one run: the same signed events published from a child process (signed there before the
clock starts, so that the publisher is not what is measured) into an ingest that stores them as
they come, and into one that checks every signature (`gaps serve --require-signatures`); and
one Ed25519 check alone, as this machine does it. Events/s is from the first sample received to
the last event stored, durable (FULL), as bench/ingest_throughput.py counts it; the two ingests
take turns, `--runs` times each, and the medians are recorded.
"""
from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

from ingest import IngestService
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store, canonical_json
from store.keys import KeyFolder, Signer, TrustedKeys

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ingest_throughput import RUN, VEHICLES, endpoint, events  # noqa: E402  (beside this file)
from results import Figure, quick, record  # noqa: E402


def publish(connect: str, n: int, keys: str) -> None:
    """Child process: sign n events, wait for the ingest, publish them, linger until killed."""
    signer = Signer(KeyFolder(keys))
    signed = [signer.sign(ev) for ev in events(n)]
    with EventPublisher(config=zenoh_config(connect=[connect])) as publisher:
        for probe in signed[:2]:
            if not publisher.wait_until_matched(probe, 10):
                raise SystemExit("no subscriber")
        publisher.publish_all(signed)
        time.sleep(60)


def ingest_rate(n: int, keys: str, trusted: TrustedKeys | None) -> tuple[float, dict]:
    ep = endpoint()
    with tempfile.TemporaryDirectory(dir=os.environ.get("TMPDIR")) as tmp:
        db = Path(tmp) / "bench.db"
        with IngestService(db, listen=[ep], trusted_keys=trusted) as ingest:
            proc = mp.get_context("spawn").Process(target=publish, args=(ep, n, keys), daemon=True)
            proc.start()
            ingest.wait_for(lambda s: s["received"] >= 1, 120)
            t0 = time.perf_counter()
            ok = ingest.wait_until_stored(n, 600)
            elapsed = time.perf_counter() - t0
            stats = ingest.stats()
        proc.kill()
        with Store(db) as store:
            assert ok and store.count(RUN) == n and stats["signature_refused"] == 0, (ok, stats)
    return n / elapsed, stats


def check_us(keys: str, trusted: TrustedKeys, n: int = 5000) -> float:
    """Microseconds for one TrustedKeys.reason of a signed event (canonical JSON, base64, Ed25519)."""
    signed = [Signer(KeyFolder(keys)).sign(ev) for ev in events(n)]
    t0 = time.perf_counter()
    for ev in signed:
        trusted.reason(ev)
    return (time.perf_counter() - t0) / n * 1e6


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=3_000 if quick() else 30_000)
    parser.add_argument("--runs", type=int, default=1 if quick() else 3)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(dir=os.environ.get("TMPDIR")) as keys:
        folder = KeyFolder(keys)
        for i in range(VEHICLES):
            folder.create(f"vehicle/{i}")
        trusted = TrustedKeys.load(folder.write_public_keys())
        size = len(canonical_json(Signer(folder).sign(next(events(1)))))
        print(f"{args.events:,} signed events ({size} bytes each, {VEHICLES} sources), publisher in a child process; "
              f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} CPUs")
        check = check_us(keys, trusted)
        print(f"one signature check: {check:.0f} us")
        plain, required = [], []
        for _ in range(args.runs):
            plain.append(ingest_rate(args.events, keys, None)[0])
            print(f"ingest, signatures stored unchecked: {plain[-1]:,.0f} events/s")
            required.append(ingest_rate(args.events, keys, trusted)[0])
            print(f"ingest, --require-signatures:        {required[-1]:,.0f} events/s")
        print(f"load average after: {os.getloadavg()[0]:.2f}")
    unchecked = "ingest of signed events, stored unchecked"
    record("signatures", "What --require-signatures costs the ingest",
           [Figure(unchecked, statistics.median(plain), "events/s", tuple(plain)),
            Figure("ingest with --require-signatures", statistics.median(required), "events/s", tuple(required),
                   peer=unchecked),
            Figure("one signature check (TrustedKeys.reason)", check, "us")],
           notes=f"{args.events:,} signed events of {VEHICLES} sources, publisher in a child process, durable; "
                 f"the two ingests in turn, {args.runs} run(s) each")


if __name__ == "__main__":
    main()
