"""kill -9 of `gaps serve` at random moments during a stream, then a restart (a benchmark of
reliability, not a test; tests/ingest/test_kill9.py runs two trials of the same code).

    .venv/bin/python bench/kill9.py [--trials 20] [--sources 10] [--rate 500] [--seed 1] [--down 0 2]
                                    [--topology serve-connects|serve-listens]

Every documented topology, the same kill moments in each: `serve-connects` (the producer listens,
`gaps serve --connect` dials it), `serve-listens` (docs/serve.md's first: `gaps serve --listen`, the
producer connects to it and must find the restarted serve again by itself) and `via-router` (a Zenoh
router, here an eclipse-zenoh session in router mode in this process, the producer and
`gaps serve --mode client` its clients, as in docs/serve.md's slices and hardened deployment).

Each trial: a producer (EventPublisher, its cache of store.CACHE_S) publishes `--rate`
events/s over `--sources` sources; `gaps serve` is linked to it; at a random moment the serve is
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

import zenoh  # noqa: E402

from results import Figure, quick, record  # noqa: E402  (bench/results.py, beside this file)
from sim_replay.publisher import EventPublisher, zenoh_config  # noqa: E402
from store import Store  # noqa: E402
from tests.helpers.ingest_testkit import free_endpoint, make_event  # noqa: E402
from tests.helpers.serve_testkit import ServeProcess, child_env  # noqa: E402

RUN = "test-run"   # make_event's run
SERVE_CONNECTS = "serve-connects"   # the producer listens, the serve connects to it
SERVE_LISTENS = "serve-listens"     # docs/serve.md's: the serve listens, the producer connects
VIA_ROUTER = "via-router"           # both clients of a Zenoh router (docs/serve.md "Slices", "A hardened deployment")
TOPOLOGIES = (SERVE_CONNECTS, SERVE_LISTENS, VIA_ROUTER)


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

    def __init__(self, endpoint: str, sources: int, rate: float, topology: str = SERVE_CONNECTS) -> None:
        super().__init__(daemon=True)
        self.sources, self.rate = sources, rate
        where = ({"listen": [endpoint]} if topology == SERVE_CONNECTS else
                 {"connect": [endpoint], "mode": "client"} if topology == VIA_ROUTER else {"connect": [endpoint]})
        self.publisher = EventPublisher(config=zenoh_config(**where))
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
          after_s: float = 1.5, topology: str = SERVE_CONNECTS) -> Trial:
    """One kill -9 and restart of `gaps serve` under a running producer (see the module's doc)."""
    db = workdir / "gaps.db"
    endpoint = free_endpoint()
    router = zenoh.open(zenoh_config(listen=[endpoint], mode="router")) if topology == VIA_ROUTER else None

    def serve() -> ServeProcess:
        if topology == SERVE_LISTENS:
            proc = ServeProcess(db, endpoint, env=child_env())
        else:
            client = ("--mode", "client") if topology == VIA_ROUTER else ()
            proc = ServeProcess(db, None, "--connect", endpoint, *client, env=child_env())
        proc.wait_for_log("serve.ready")
        return proc

    if topology == SERVE_LISTENS:   # the listener opens first
        first = serve()
        producer = Producer(endpoint, sources, rate, topology)
    else:
        producer = Producer(endpoint, sources, rate, topology)
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
    if router is not None:
        router.close()
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
    parser.add_argument("--trials", type=int, default=3 if quick() else 20, help="trials per topology")
    parser.add_argument("--sources", type=int, default=10)
    parser.add_argument("--rate", type=float, default=500.0, help="events/s over all sources")
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--down", type=float, nargs=2, default=(0.0, 2.0), metavar=("MIN", "MAX"),
                        help="seconds the serve stays down, drawn between MIN and MAX (default 0 2)")
    parser.add_argument("--topology", choices=TOPOLOGIES, action="append",
                        help="run only this topology (repeatable; default all three)")
    args = parser.parse_args()
    by_topology = {}
    print("topology        trial  sent  stored  before-kill  recovered  live-after  gap  unaccounted  verified  "
          "killed-at  down")
    for topology in args.topology or TOPOLOGIES:
        rng = random.Random(args.seed)   # the same kill moments and downtimes in each topology
        trials = by_topology[topology] = []
        for n in range(1, args.trials + 1):
            with tempfile.TemporaryDirectory() as tmp:
                t = trial(Path(tmp), rng, sources=args.sources, rate=args.rate, down_s=tuple(args.down),
                          topology=topology)
            trials.append(t)
            print(f"{topology:14}  {n:5}  {t.sent:4}  {t.stored:6}  {t.before_kill:11}  {t.recovered:9}  "
                  f"{t.live_after:10}  {t.gap:3}  {t.unaccounted:11}  {str(t.verified):8}  {t.killed_after_s:8.2f}s  "
                  f"{t.down_s:.2f}s", flush=True)
    print()
    print("| topology | trials | published | stored | recovered from caches | listed as gaps | unaccounted | verified, nothing unaccounted |")
    print("|---|---|---|---|---|---|---|---|")
    figures = []
    for topology, trials in by_topology.items():
        total = {k: sum(getattr(t, k) for t in trials) for k in ("sent", "stored", "recovered", "gap", "unaccounted")}
        ok = sum(t.verified and t.unaccounted == 0 for t in trials)
        print(f"| {topology} | {len(trials)} | {total['sent']:,} | {total['stored']:,} | {total['recovered']:,} | "
              f"{total['gap']:,} | {total['unaccounted']:,} | {ok}/{len(trials)} |")
        figures += [Figure(f"{topology}: trials with the store verified and every sent event stored or listed as a "
                           "gap", ok, "trials"),
                    Figure(f"{topology}: events sent", total["sent"], "events"),
                    Figure(f"{topology}: events stored", total["stored"], "events"),
                    Figure(f"{topology}: recovered from the publishers' caches", total["recovered"], "events"),
                    Figure(f"{topology}: listed as gaps", total["gap"], "events"),
                    Figure(f"{topology}: unaccounted (silently lost)", total["unaccounted"], "events")]
    record("kill9", "kill -9 of gaps serve during a stream, then a restart, in every topology", figures,
           notes=f"{args.trials} trials a topology, {args.sources} sources at {args.rate:g} events/s in all, "
                 f"down {args.down[0]:g}-{args.down[1]:g} s, seed {args.seed}",
           details={topology: [asdict(t) for t in trials] for topology, trials in by_topology.items()})


if __name__ == "__main__":
    main()
