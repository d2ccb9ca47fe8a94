"""kill -9 of `gaps serve` at random moments during a stream, then a restart (a benchmark of
reliability, not a test; tests/ingest/test_kill9.py runs two trials of the same code).

    .venv/bin/python bench/kill9.py [--trials 20] [--sources 10] [--rate 500] [--seed 1]

Each trial: a producer (EventPublisher, its cache of store.CACHE_S) listens and publishes `--rate`
events/s over `--sources` sources; `gaps serve` connects to it; at a random moment the serve is
killed with SIGKILL, stays down a random while, and is started again on the same store while the
producer goes on; the producer then stops and closes (its close waits for the serve to confirm),
and the serve is stopped. Counted per trial, from the store: sent; stored; of those, committed
before the kill, recovered (sent before the restarted serve was ready and not committed by the
first one: they can only have come from the caches) and received live after the restart; gap
(sent, not stored, and listed by the store's gaps); unaccounted (sent, neither stored nor listed:
a silent loss, which must be 0), and whether the store verifies.
"""
from __future__ import annotations

import argparse
import random
import signal
import sys
import tempfile
import threading
import time
from dataclasses import asdict, dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from results import Figure, quick, record  # noqa: E402  (bench/results.py, beside this file)
from sim_replay.publisher import EventPublisher, zenoh_config  # noqa: E402
from store import Store  # noqa: E402
from tests.helpers.ingest_testkit import free_endpoint, make_event  # noqa: E402
from tests.helpers.serve_testkit import ServeProcess, child_env  # noqa: E402

RUN = "test-run"   # make_event's run


@dataclass(frozen=True)
class Trial:
    """One trial's counts (events) and times (s)."""

    sent: int
    stored: int
    before_kill: int
    recovered: int
    live_after: int
    gap: int
    unaccounted: int
    verified: bool
    killed_after_s: float
    down_s: float


class Producer(threading.Thread):
    """Publishes entity.state events round-robin over `sources` at `rate` per second until stopped,
    noting when each was put."""

    def __init__(self, endpoint: str, sources: int, rate: float) -> None:
        super().__init__(daemon=True)
        self.sources, self.rate = sources, rate
        self.publisher = EventPublisher(config=zenoh_config(listen=[endpoint]))
        self.put_at: list[float] = []
        self._halt = threading.Event()

    def event(self, i: int) -> dict:
        return make_event(f"vehicle/{i % self.sources}", i // self.sources, "entity.state")

    def run(self) -> None:
        start = time.monotonic()
        i = 0
        while not self._halt.is_set():
            due = start + i / self.rate
            if (wait := due - time.monotonic()) > 0:
                time.sleep(wait)
            self.put_at.append(time.monotonic())
            self.publisher.publish(self.event(i))
            i += 1

    def finish(self) -> None:
        self._halt.set()
        self.join()
        self.publisher.close()


def _identities(db: Path) -> set[tuple[str, int]]:
    with Store.open_read_only(db) as store:
        return {(e["src"], e["seq"]) for e in store.events(RUN)}


def trial(workdir: Path, rng: random.Random, *, sources: int = 10, rate: float = 500.0,
          before_kill_s: tuple[float, float] = (0.5, 2.5), down_s: tuple[float, float] = (0.0, 2.0),
          after_s: float = 1.5) -> Trial:
    """One kill -9 and restart of `gaps serve` under a running producer (see the module's doc)."""
    db = workdir / "gaps.db"
    endpoint = free_endpoint()
    producer = Producer(endpoint, sources, rate)

    def serve() -> ServeProcess:
        proc = ServeProcess(db, free_endpoint(), "--connect", endpoint, env=child_env())
        proc.wait_for_log("serve.ready")
        return proc

    first = serve()
    producer.start()
    killed_after = rng.uniform(*before_kill_s)
    time.sleep(killed_after)
    first.proc.send_signal(signal.SIGKILL)
    first.proc.wait()
    killed_at = time.monotonic()
    committed = _identities(db)
    down = rng.uniform(*down_s)
    time.sleep(down)
    second = serve()
    ready_at = time.monotonic()
    time.sleep(after_s)
    producer.finish()
    second.stop()
    sent = {(f"vehicle/{i % sources}", i // sources): at for i, at in enumerate(producer.put_at)}
    stored = _identities(db)
    with Store.open_read_only(db) as store:
        verified = store.verify().ok
        listed = {(g["src"], seq) for g in store.gaps(RUN) for a, b in g["missing"] for seq in range(a, b + 1)}
    new = stored - committed
    recovered = sum(1 for ident in new if sent.get(ident, ready_at) < ready_at)
    return Trial(sent=len(sent), stored=len(stored & sent.keys()), before_kill=len(committed),
                 recovered=recovered, live_after=len(new) - recovered, gap=len((sent.keys() - stored) & listed),
                 unaccounted=len(sent.keys() - stored - listed), verified=verified,
                 killed_after_s=round(killed_after, 3), down_s=round(ready_at - killed_at, 3))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trials", type=int, default=3 if quick() else 20)
    parser.add_argument("--sources", type=int, default=10)
    parser.add_argument("--rate", type=float, default=500.0, help="events/s over all sources")
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    trials = []
    print("trial  sent  stored  before-kill  recovered  live-after  gap  unaccounted  verified  killed-at  down")
    for n in range(1, args.trials + 1):
        with tempfile.TemporaryDirectory() as tmp:
            t = trial(Path(tmp), rng, sources=args.sources, rate=args.rate)
        trials.append(t)
        print(f"{n:5}  {t.sent:4}  {t.stored:6}  {t.before_kill:11}  {t.recovered:9}  {t.live_after:10}  "
              f"{t.gap:3}  {t.unaccounted:11}  {str(t.verified):8}  {t.killed_after_s:8.2f}s  {t.down_s:.2f}s",
              flush=True)
    total = {k: sum(getattr(t, k) for t in trials) for k in ("sent", "stored", "recovered", "gap", "unaccounted")}
    ok = sum(t.verified and t.unaccounted == 0 for t in trials)
    print(f"{len(trials)} trials: sent {total['sent']}, stored {total['stored']} (recovered from caches "
          f"{total['recovered']}), listed as gaps {total['gap']}, unaccounted {total['unaccounted']}; "
          f"{ok}/{len(trials)} trials verified with nothing unaccounted")
    record("kill9", "kill -9 of gaps serve during a stream, then a restart",
           [Figure("trials with the store verified and every sent event stored or listed as a gap", ok, "trials"),
            Figure("events sent", total["sent"], "events"),
            Figure("recovered from the publishers' caches", total["recovered"], "events"),
            Figure("listed as gaps", total["gap"], "events"),
            Figure("unaccounted (silently lost)", total["unaccounted"], "events")],
           notes=f"{len(trials)} trials, {args.sources} sources at {args.rate:g} events/s in all, seed {args.seed}",
           details={"trials": [asdict(t) for t in trials]})


if __name__ == "__main__":
    main()
