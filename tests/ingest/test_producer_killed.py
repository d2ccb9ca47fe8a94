"""A producer killed with SIGKILL before the ingest has asked its cache for what it missed: what
only that cache held is gone, and must be a recorded gap (its source and seq range, `gaps runs
--gaps`), never silently lost; the liveliness record shows the producer disappearing.

The ordering is made, not waited for: the ingest's recovery is held back (CacheRecovery.step does
nothing until the test lets it) until the producer is dead."""
from __future__ import annotations

import json
import subprocess
import sys
import textwrap
import threading
import time
from collections.abc import Iterator
from pathlib import Path

import pytest

from ingest import IngestService
from ingest.cache_recovery import CacheRecovery
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.ingest_testkit import RUN, free_endpoint
from tests.helpers.serve_testkit import ROOT, child_env

SRC = "vehicle/7"
WAIT_S = 15.0

PRODUCER = textwrap.dedent("""
    import sys
    from sim_replay.publisher import EventPublisher, zenoh_config
    from tests.helpers.ingest_testkit import make_event
    publisher = EventPublisher(config=zenoh_config(listen=[sys.argv[1]]))
    print("ready", flush=True)
    for line in sys.stdin:          # "match" or "publish FIRST LAST"
        word, *args = line.split()
        if word == "match":
            ok = publisher.wait_until_matched(make_event("vehicle/7", 0, "entity.state"), 10)
            print("matched" if ok else "no ingest", flush=True)
        else:
            first, last = map(int, args)
            publisher.publish_all([make_event("vehicle/7", seq, "entity.state") for seq in range(first, last + 1)])
            print("published", flush=True)
""")


class Producer:
    """The producer child process, told what to do one line at a time."""

    def __init__(self, endpoint: str) -> None:
        self.process = subprocess.Popen([sys.executable, "-c", PRODUCER, endpoint], cwd=ROOT, env=child_env(),
                                        stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        assert self._answer() == "ready"

    def ask(self, line: str) -> str:
        self.process.stdin.write(line + "\n")
        self.process.stdin.flush()
        return self._answer()

    def _answer(self) -> str:
        return self.process.stdout.readline().strip()

    def kill(self) -> None:
        self.process.kill()
        self.process.wait()


class HeldRecovery:
    """CacheRecovery.step does nothing until ``let_go``: the ingest has found the cache and seen
    the hole, but has asked nothing yet. ``seen`` holds the recoveries that were held."""

    def __init__(self, monkeypatch: pytest.MonkeyPatch) -> None:
        self.released = threading.Event()
        self.seen: list[CacheRecovery] = []
        step = CacheRecovery.step

        def held(recovery: CacheRecovery) -> None:
            if recovery not in self.seen:
                self.seen.append(recovery)
            if self.released.is_set():
                step(recovery)

        monkeypatch.setattr(CacheRecovery, "step", held)

    def let_go(self) -> None:
        self.released.set()


@pytest.fixture
def held_recovery(monkeypatch: pytest.MonkeyPatch) -> Iterator[HeldRecovery]:
    held = HeldRecovery(monkeypatch)
    yield held
    held.let_go()


def _liveliness(db: Path) -> list[tuple[bool, int | None]]:
    with Store.open_read_only(db) as store:
        return [(c.alive, c.last_seq) for c in store.liveliness_changes(RUN, SRC)]


def _wait(check, timeout: float = WAIT_S):
    deadline = time.monotonic() + timeout
    while not (found := check()) and time.monotonic() < deadline:
        time.sleep(0.05)
    return found


def test_what_only_a_killed_producers_cache_held_is_a_listed_gap(db_path: Path, held_recovery: HeldRecovery) -> None:
    endpoint = free_endpoint()
    producer = Producer(endpoint)
    try:
        with IngestService(db_path, connect=[endpoint]) as first:
            assert producer.ask("match") == "matched"
            assert producer.ask("publish 0 99") == "published"
            assert first.wait_until_stored(100, WAIT_S), first.stats()
        assert producer.ask("publish 100 199") == "published"      # no ingest: only the cache has them
        second = IngestService(db_path, connect=[endpoint])
        try:
            assert producer.ask("match") == "matched"
            assert producer.ask("publish 200 209") == "published"
            assert second.wait_until_stored(10, WAIT_S), second.stats()
            assert second.gaps() == [{"run": RUN, "src": SRC, "missing": [[100, 199]], "highest": 209}]
            producer.kill()                                      # before the ingest asked its cache
            assert _wait(lambda: _liveliness(db_path)[-1:] == [(False, 209)]), _liveliness(db_path)
            recovery = held_recovery.seen[-1]                    # the second ingest's
            assert not recovery.idle                             # the cache found and the hole, not asked
            held_recovery.let_go()                               # now it asks a cache that is gone
            assert _wait(lambda: recovery.idle), "asking a dead producer's cache never ended"
        finally:
            started = time.monotonic()
            second.stop()
            assert time.monotonic() - started < 5.0              # a dead cache does not hold the stop
        assert second.stats()["recovered"] == 0
    finally:
        producer.kill()
    with Store.open_read_only(db_path) as store:
        assert [e["seq"] for e in store.events(RUN)] == [*range(100), *range(200, 210)]
        assert store.gaps() == [{"run": RUN, "src": SRC, "missing": [[100, 199]], "highest": 209}]
        assert store.verify(RUN).ok
    changes = _liveliness(db_path)
    assert changes[0] == (True, None) and changes[-1] == (False, 209), changes
    assert [alive for alive, _ in changes] == [True, True, False], changes   # each ingest saw it appear
    listed = json.loads(gaps("runs", "--gaps", "--live", "--json", "--no-verify", db=db_path).stdout)
    assert listed["gaps"] == [{"run": RUN, "src": SRC, "missing": [[100, 199]], "highest": 209}]
    assert [(life["src"], life["alive"], life["last_seq"]) for life in listed["liveliness"]] == [(SRC, False, 209)]
