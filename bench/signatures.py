"""What requiring signatures costs the ingest (a benchmark, not a test).

    .venv/bin/python bench/signatures.py [--events 30000]

In one run: the same signed events published from a child process (signed there before the
clock starts, so that the publisher is not what is measured) into an ingest that stores them as
they come, and into one that checks every signature (`gaps serve --require-signatures`); and
one Ed25519 check alone, as this machine does it. Events/s is from the first sample received to
the last event stored, durable (FULL), as bench/ingest_throughput.py counts it.
"""
from __future__ import annotations

import argparse
import multiprocessing as mp
import os
import sys
import tempfile
import time
from pathlib import Path

from ingest import IngestService
from sim_replay.publisher import EventPublisher, zenoh_config
from store import KeyFolder, Signer, Store, TrustedKeys, canonical_json

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ingest_throughput import RUN, VEHICLES, endpoint, events  # noqa: E402  (beside this file)


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
    parser.add_argument("--events", type=int, default=30_000)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(dir=os.environ.get("TMPDIR")) as keys:
        folder = KeyFolder(keys)
        for i in range(VEHICLES):
            folder.create(f"vehicle/{i}")
        trusted = TrustedKeys.load(folder.write_public_keys())
        size = len(canonical_json(Signer(folder).sign(next(events(1)))))
        print(f"{args.events:,} signed events ({size} bytes each, {VEHICLES} sources), publisher in a child process; "
              f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} CPUs")
        print(f"one signature check: {check_us(keys, trusted):.0f} us")
        plain, _ = ingest_rate(args.events, keys, None)
        print(f"ingest, signatures stored unchecked: {plain:,.0f} events/s")
        required, _ = ingest_rate(args.events, keys, trusted)
        print(f"ingest, --require-signatures:        {required:,.0f} events/s ({required / plain:.2f} x)")
        print(f"load average after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
