"""Quick end-to-end throughput check of publisher → Zenoh → ingest → store (a benchmark, not a test).

    .venv/bin/python bench/ingest_throughput.py [--events 50000 | --seconds 60] [--repeat 3]
                                                 [--not-durable] [--same-process]

The publisher runs in a child process by default so that it does not share the GIL with the ingest; the
raw Zenoh rate (a subscriber that only counts) is measured the same way for comparison, alternately with
the ingest, ``--repeat`` times, and the medians are recorded. ``--seconds S`` publishes for S seconds
instead of a number of events: a sustained rate rather than a burst. Beside each rate: the load average,
the CPU the ingest's process spent (its writer thread and Zenoh's threads apart, from /proc) and its
resident memory (now and at its peak), because on a shared machine a rate alone says little.
"""
from __future__ import annotations

import argparse
import itertools
import multiprocessing as mp
import os
import socket
import statistics
import sys
import tempfile
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path


import zenoh

from ingest import IngestService, session_config
from ingest.service import BATCH_SIZE, MAX_PENDING
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store

sys.path.insert(0, str(Path(__file__).resolve().parent))
from results import Figure, quick, record  # noqa: E402  (bench/results.py, beside this file)

RUN = "bench"
VEHICLES = 100
CLK_TCK = os.sysconf("SC_CLK_TCK")


def endpoint() -> str:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return f"tcp/127.0.0.1:{sock.getsockname()[1]}"


def events(n: int | None) -> Iterator[dict]:
    """Small valid events, round-robin over VEHICLES sources, alternating two kinds (n None: no end)."""
    for i in itertools.count() if n is None else range(n):
        seq, ident = divmod(i, VEHICLES)
        if seq % 2:
            kind, body = "entity.state", {"x": float(seq), "y": 0.0, "speed_mps": 8.0}
        else:
            kind, body = "vehicle.perception", {"facts": [f"{ident} has red light"]}
        yield {"v": 1, "run": RUN, "src": f"vehicle/{ident}", "seq": seq, "t": 1_700_000_000_000_000_000 + i,
               "kind": kind, "body": body}


def publish(connect: str, n: int, seconds: float | None, sent) -> None:
    """Child process: connect, wait for the subscriber, publish n events (or for ``seconds``), say
    how many in ``sent``, linger until told to stop (closing early could drop the tail)."""
    with EventPublisher(config=zenoh_config(connect=[connect])) as publisher:
        for probe in events(2):
            if not publisher.wait_until_matched(probe, 10):
                raise SystemExit("no subscriber")
        t0 = time.perf_counter()
        if seconds is None:
            count = publisher.publish_all(events(n))
        else:
            count, stream = 0, events(None)
            while time.perf_counter() - t0 < seconds:
                count += publisher.publish_all(itertools.islice(stream, 1000))
        put_s = time.perf_counter() - t0
        sent.value = count
        print(f"  publisher: put {count:,} in {put_s:.2f} s ({count / put_s:,.0f}/s), "
              f"CPU {time.process_time():.1f} s", flush=True)
        time.sleep(600)


def start_publisher(connect: str, n: int, seconds: float | None, same_process: bool, sent):
    if same_process:
        thread = threading.Thread(target=publish, args=(connect, n, seconds, sent), daemon=True)
        thread.start()
        return None
    proc = mp.get_context("spawn").Process(target=publish, args=(connect, n, seconds, sent), daemon=True)
    proc.start()
    return proc


def wait_sent(sent, timeout: float) -> int:
    """How many the publisher put, once it has said (-1 until then)."""
    deadline = time.monotonic() + timeout
    while sent.value < 0 and time.monotonic() < deadline:
        time.sleep(0.01)
    return sent.value


def thread_cpu() -> dict[str, float]:
    """CPU seconds (user + system) of each thread of this process, summed by name: Python's name
    for a Python thread (the writer is "ingest-writer"), the kernel's for the others (Zenoh's)."""
    python_names = {t.native_id: t.name for t in threading.enumerate()}
    out: dict[str, float] = {}
    for task in Path("/proc/self/task").iterdir():
        try:
            stat = (task / "stat").read_text()
        except OSError:
            continue
        name = python_names.get(int(task.name)) or stat[stat.index("(") + 1:stat.rindex(")")]
        fields = stat[stat.rindex(")") + 2:].split()
        out[name] = out.get(name, 0.0) + (int(fields[11]) + int(fields[12])) / CLK_TCK
    return out


def memory_mb() -> tuple[float, float]:
    """(resident now, resident at its peak) of this process, in MB."""
    found = {}
    for line in Path("/proc/self/status").read_text().splitlines():
        name, _, value = line.partition(":")
        if name in ("VmRSS", "VmHWM"):
            found[name] = int(value.split()[0]) / 1024
    return found["VmRSS"], found["VmHWM"]


@dataclass(frozen=True)
class Round:
    """One ingest run: its rate, its load, and what the ingest's process spent on it."""
    rate: float
    events: int
    load: float
    cpu_s: float           # all threads of the ingest's process over the timed window
    writer_cpu_s: float    # the writer thread alone
    rss_mb: float
    peak_rss_mb: float
    stats: dict
    elapsed_s: float = 0.0  # the timed window: the writer's share of it says whether it is the bottleneck

    @property
    def writer_busy(self) -> float:
        """The writer thread's CPU over the window's wall time: near 1, the writer holds the rate back
        (one core's worth of Python); well below, something else does (the publisher, the machine)."""
        return self.writer_cpu_s / self.elapsed_s if self.elapsed_s else 0.0

    def line(self) -> str:
        us = 1e6 / self.events
        return (f"{self.rate:,.0f} events/s; load {self.load:.2f}; ingest CPU {self.cpu_s:.1f} s "
                f"({self.cpu_s * us:.1f} us/event, writer {self.writer_cpu_s * us:.1f}, others "
                f"{(self.cpu_s - self.writer_cpu_s) * us:.1f}; writer busy {self.writer_busy:.0%} of the window); "
                f"RSS {self.rss_mb:.0f} MB, peak {self.peak_rss_mb:.0f} MB; "
                f"{self.stats['batches']} batches")


def raw_rate(n: int, seconds: float | None, same_process: bool) -> float:
    """Samples/s of a subscriber that only counts: the ceiling the ingest is compared with."""
    ep = endpoint()
    count, times = [0], [0.0, 0.0]
    sent = mp.get_context("spawn").Value("q", -1)

    def on_sample(_: zenoh.Sample) -> None:
        now = time.perf_counter()
        if count[0] == 0:
            times[0] = now
        count[0] += 1
        times[1] = now

    with zenoh.open(session_config(listen=[ep])) as session:
        sub = session.declare_subscriber("gaps/**", on_sample)
        proc = start_publisher(ep, n, seconds, same_process, sent)
        total = wait_sent(sent, (seconds or 0) + 120)
        deadline = time.monotonic() + 120
        while count[0] < total and time.monotonic() < deadline:
            time.sleep(0.01)
        rate = (count[0] - 1) / (times[1] - times[0])
        sub.undeclare()
    if proc is not None:
        proc.kill()
    return rate


def ingest_rate(n: int, seconds: float | None, durable: bool, same_process: bool, batch_size: int,
                max_pending: int) -> Round:
    """Events/s committed to the store, from the first sample received to the last event stored."""
    ep = endpoint()
    sent = mp.get_context("spawn").Value("q", -1)
    with tempfile.TemporaryDirectory() as tmp:
        db = Path(tmp) / "bench.db"
        with IngestService(db, listen=[ep], durable=durable, batch_size=batch_size,
                           max_pending=max_pending) as ingest:
            proc = start_publisher(ep, n, seconds, same_process, sent)
            ingest.wait_for(lambda s: s["received"] >= 1, 60)
            t0, cpu0, load0 = time.perf_counter(), thread_cpu(), os.getloadavg()[0]
            total = wait_sent(sent, (seconds or 0) + 300)
            ok = ingest.wait_until_stored(total, 300)
            elapsed = time.perf_counter() - t0
            cpu1, (rss, peak), load1 = thread_cpu(), memory_mb(), os.getloadavg()[0]
            stats = ingest.stats()
        if proc is not None:
            proc.kill()
        with Store(db) as store:
            assert ok and store.count(RUN) == total, (ok, total, stats)
            assert store.verify(RUN).ok
    spent = {name: cpu1[name] - cpu0.get(name, 0.0) for name in cpu1}
    return Round(total / elapsed, total, max(load0, load1), sum(spent.values()), spent.get("ingest-writer", 0.0),
                 rss, peak, stats, elapsed)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--events", type=int, default=5_000 if quick() else 50_000)
    parser.add_argument("--seconds", type=float, default=None, help="publish for this long instead of --events")
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--not-durable", action="store_true")
    parser.add_argument("--same-process", action="store_true")
    parser.add_argument("--batch-size", type=int, default=BATCH_SIZE)
    parser.add_argument("--max-pending", type=int, default=MAX_PENDING, help="samples Zenoh may hold for the writer")
    args = parser.parse_args()
    where = "same process" if args.same_process else "publisher in a child process"
    size = f"{args.seconds:g} s of publishing" if args.seconds else f"{args.events:,} events"
    print(f"{size}, {where}, durable={not args.not_durable}, batch_size={args.batch_size}, "
          f"max_pending={args.max_pending}, {args.repeat} round(s)")
    raws, rounds = [], []
    for _ in range(args.repeat):
        raws.append(raw_rate(args.events, args.seconds, args.same_process))
        print(f"raw zenoh pub→sub: {raws[-1]:,.0f} samples/s", flush=True)
        rounds.append(ingest_rate(args.events, args.seconds, not args.not_durable, args.same_process, args.batch_size,
                                  args.max_pending))
        print(f"ingest → store:    {rounds[-1].line()}", flush=True)
    raw = statistics.median(raws)
    mid = sorted(rounds, key=lambda r: r.rate)[len(rounds) // 2]
    print(f"median: raw {raw:,.0f} samples/s, ingest {mid.rate:,.0f} events/s ({mid.rate / raw:.2f} × raw)")
    raw_name = "raw Zenoh pub→sub (a subscriber that only counts)"
    us = 1e6 / mid.events
    record("ingest_throughput", "Publisher → Zenoh → ingest → store, end to end",
           [Figure(raw_name, raw, "samples/s", tuple(raws)),
            Figure("ingest → store", mid.rate, "events/s", tuple(r.rate for r in rounds), peer=raw_name,
                   note=f"median round: ingest CPU {mid.cpu_s * us:.1f} us/event (writer thread "
                        f"{mid.writer_cpu_s * us:.1f}, busy {mid.writer_busy:.0%} of the window), RSS peak {mid.peak_rss_mb:.0f} MB, "
                        f"load {mid.load:.2f}, errors {mid.stats['errors']}")],
           notes=f"{size}, small events, {where}, durable={not args.not_durable}, "
                 f"batch_size={args.batch_size}, max_pending={args.max_pending}; {args.repeat} round(s), raw and ingest alternately, medians")


if __name__ == "__main__":
    main()
