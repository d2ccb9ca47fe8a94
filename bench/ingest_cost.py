"""What one event costs the ingest's writer thread, stage by stage, on one core (a benchmark, not a test).

    .venv/bin/python bench/ingest_cost.py [--events 100000] [--repeat 5] [--stream RUN.mcap]

bench/ingest_throughput.py gives the end-to-end rate and the ingest's CPU per event, split into
its writer thread and Zenoh's threads; this splits the writer's share into what it does to each
sample, each stage timed alone in thread CPU time over the same small events (bench/ingest_throughput.py's),
as the writer does it: in batches of 10,000, FULL durability, snapshots kept, with the collector
paced as the writer paces it (ingest/gc_pacing.py). The sum says what rate one core allows the
writer, before Zenoh's threads take their share (measured end to end, beside it). Medians of
--repeat rounds, each on a fresh store; CPU time, not wall time, because the machine is shared.

  receive  Zenoh's FIFO channel to a (key, payload, is_put, encoding) tuple (ingest/inbox.py),
           the samples put by another session in this process beforehand
  screen   parse, validate, canonical check, key check, a batch in one loop (ingest/screen.py's screen_all)
  track    the seqs followed, for gaps and for the caches (GapTracker.observe_all)
  chain    placing, chaining and checkpointing a batch's events in Python (store/batch.py)
  sqlite   the rows inserted and committed, fsync included (executemany + COMMIT)

``--stream FILE`` takes the events of a recorded run instead (an MCAP or JSONL file, e.g.
tests/golden/golden-sim.mcap, the simulation's own stream with its nine-property entity.states
and its vehicle.traces' proofs), repeated with seqs and times moved on until --events are made;
signed events are left out (a moved one would no longer match its signature).
"""
from __future__ import annotations

import argparse
import itertools
import socket
import statistics
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import zenoh
from zenoh import ext

sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from ingest.gap_tracker import GapTracker  # noqa: E402
from ingest.gc_pacing import collections_between_batches  # noqa: E402
from ingest.inbox import received  # noqa: E402
from ingest.screen import screen_all  # noqa: E402
from store import Store, canonical_json
from store.cache import enable_snapshots
from store.wire import key_for, session_config  # noqa: E402
from store.transfer import import_file  # noqa: E402
from store.batch import Batch  # noqa: E402

sys.path.insert(0, str(Path(__file__).resolve().parent))
from ingest_throughput import events  # noqa: E402  (bench/ingest_throughput.py, beside this file)
from results import Figure, quick, record  # noqa: E402

BATCH = 10_000
STAGES = ("receive", "screen", "track", "chain", "sqlite")


def cpu(step: Callable[[], object]) -> float:
    """Thread CPU seconds of one call."""
    started = time.thread_time()
    step()
    return time.thread_time() - started


def receive_cost(payloads: list[tuple[str, bytes]]) -> float:
    """Seconds of writer CPU to take every sample from an advanced subscriber's channel."""
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        endpoint = f"tcp/127.0.0.1:{sock.getsockname()[1]}"
    with zenoh.open(session_config(listen=[endpoint])) as ingest, \
            zenoh.open(session_config(connect=[endpoint])) as producer:
        channel = ext.declare_advanced_subscriber(ingest, "gaps/**", zenoh.handlers.FifoChannel(len(payloads) + 1))
        publishers: dict[str, zenoh.Publisher] = {}
        time.sleep(0.5)
        for key, payload in payloads:
            if key not in publishers:
                publishers[key] = producer.declare_publisher(
                    key, congestion_control=zenoh.CongestionControl.BLOCK, reliability=zenoh.Reliability.RELIABLE)
            publishers[key].put(payload)
        deadline = time.monotonic() + 60
        taken: list = []
        spent = 0.0
        while len(taken) < len(payloads) and time.monotonic() < deadline:
            started = time.thread_time()
            while (sample := channel.try_recv()) is not None:
                taken.append(received(sample))
            spent += time.thread_time() - started
            time.sleep(0.01)
        assert len(taken) == len(payloads), (len(taken), len(payloads))
        return spent


def writer_costs(samples: list[tuple[str, bytes]], db: Path) -> dict[str, float]:
    """Seconds of CPU per stage after receiving, batch by batch, as the writer runs them."""
    spent = dict.fromkeys(STAGES[1:], 0.0)
    tracker = GapTracker()
    with Store(db, durable=True) as store, collections_between_batches() as between_batches:
        enable_snapshots(store)
        for i in range(0, len(samples), BATCH):
            chunk = [(key, payload, True, "application/json") for key, payload in samples[i:i + BATCH]]
            screened: list = []
            spent["screen"] += cpu(lambda: screened.extend(screen_all(chunk, _unscreenable)))
            spent["track"] += cpu(lambda: tracker.observe_all([s.identity for s in screened]))
            spent["chain"] += cpu(lambda: _placed(store, [s.candidate for s in screened]))
            spent["sqlite"] += cpu(lambda: store.append_candidates([s.candidate for s in screened]))
            between_batches()
    spent["sqlite"] -= spent["chain"]   # append_candidates places too: what is left is SQLite's
    return spent


def _unscreenable(key: str, payload: bytes, exc: Exception) -> None:
    raise AssertionError(f"screening {key} raised {exc!r}")


def _placed(store: Store, candidates: list) -> None:
    """What append_candidates does in Python before SQLite, on a throwaway Batch."""
    batch = Batch(store._heads, store.checkpoint_every, time.time_ns(), store.checkpoint_key)
    batch.offer_candidates(candidates)
    batch.finish()
    store._heads.forget()   # the throwaway batch moved the cached heads on; the real append re-reads them


def recorded(path: Path, n: int) -> list[dict]:
    """n events from a recorded run's unsigned ones, in the store's order, the run repeated with
    each source's seqs and every time moved past the run's last until there are n."""
    with tempfile.TemporaryDirectory() as tmp, Store(Path(tmp) / "stream.db") as store:
        import_file(store, path)
        run = store.runs()[0].run
        found = [e for e in store.events(run) if "sig" not in e]
    span = max(e["t"] for e in found) - min(e["t"] for e in found) + 1
    step = max(e["seq"] for e in found) + 1
    made: list[dict] = []
    for lap in itertools.count():
        for e in found:
            if len(made) == n:
                return made
            made.append({**e, "seq": e["seq"] + lap * step, "t": e["t"] + lap * span})
    return made


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=20_000 if quick() else 100_000)
    parser.add_argument("--repeat", type=int, default=3 if quick() else 5)
    parser.add_argument("--stream", type=Path, default=None, help="a recorded run's events instead of small ones")
    args = parser.parse_args()
    made = events(args.events) if args.stream is None else recorded(args.stream, args.events)
    samples = [(key_for(e), canonical_json(e)) for e in made]
    rounds: dict[str, list[float]] = {stage: [] for stage in STAGES}
    for _ in range(args.repeat):
        rounds["receive"].append(receive_cost(samples) / args.events * 1e6)
        with tempfile.TemporaryDirectory() as tmp:
            for stage, seconds in writer_costs(samples, Path(tmp) / "cost.db").items():
                rounds[stage].append(seconds / args.events * 1e6)
    medians = {stage: statistics.median(values) for stage, values in rounds.items()}
    total = sum(medians.values())
    for stage in STAGES:
        print(f"{stage:8s} {medians[stage]:6.2f} us/event   (rounds: {', '.join(f'{v:.2f}' for v in rounds[stage])})")
    print(f"{'writer':8s} {total:6.2f} us/event: one core allows the writer {1e6 / total:,.0f} events/s")
    what = "small events (bench/ingest_throughput.py's)" if args.stream is None else f"events of {args.stream.name}"
    if args.stream is not None:
        return  # the recorded figures are the small events'; a stream's are printed only
    record("ingest_cost", "The ingest writer's CPU per event, stage by stage (one core)",
           [*(Figure(stage, medians[stage], "us/event", tuple(rounds[stage])) for stage in STAGES),
            Figure("writer, all stages", total, "us/event"),
            Figure("one core allows the writer", 1e6 / total, "events/s")],
           notes=f"{args.events:,} {what}, batches of {BATCH:,}, FULL "
                 f"durability, thread CPU time, medians of {args.repeat} rounds")


if __name__ == "__main__":
    main()
