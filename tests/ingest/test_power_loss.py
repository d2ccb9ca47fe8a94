"""`gaps serve` killed with SIGKILL between a batch's write and its COMMIT (the pause of
tests/helpers/pause_before_commit.py) while a producer goes on, then restarted: the store verifies,
holds what was committed, and the batch that never committed, with everything sent meanwhile, comes
back from the producer's cache; nothing sent is unaccounted (issue 15, fault injection)."""
from __future__ import annotations

import json
import signal
import sys
import time
from pathlib import Path

import pytest

from store import Store
from tests.helpers.ingest_testkit import RUN, free_endpoint
from tests.helpers.script_module import load_script
from tests.helpers.serve_testkit import ServeProcess, child_env

BENCH = Path(__file__).parents[2] / "bench" / "kill9.py"
PAUSING = [sys.executable, "-m", "tests.helpers.pause_before_commit", "serve"]
SOURCES = 5


@pytest.fixture(scope="module")
def kill9():
    return load_script(BENCH, "bench_kill9_power")


def wait_for(marker: Path, child: ServeProcess, timeout: float = 30.0) -> dict:
    deadline = time.monotonic() + timeout
    while not marker.exists():
        assert child.proc.poll() is None, child.lines[-20:]
        assert time.monotonic() < deadline, "the serve never reached the pause"
        time.sleep(0.02)
    time.sleep(0.05)
    return json.loads(marker.read_text())


def test_a_serve_killed_between_write_and_commit_loses_nothing(kill9, tmp_path: Path) -> None:
    db, marker, endpoint = tmp_path / "gaps.db", tmp_path / "paused.json", free_endpoint()
    producer = kill9.Producer(endpoint, SOURCES, rate=400)
    first = ServeProcess(db, free_endpoint(), "--connect", endpoint, command=PAUSING,
                         env=child_env(GAPS_PAUSE_AT="4", GAPS_PAUSE_MARKER=str(marker)))
    second = None
    try:
        first.wait_for_log("serve.ready")
        producer.start()
        wait_for(marker, first)
        with Store.open_read_only(db) as reader:
            committed = {(e["src"], e["seq"]) for e in reader.events(RUN)}
        first.proc.send_signal(signal.SIGKILL)
        first.proc.wait()
        time.sleep(0.3)                      # down a while, the producer going on
        second = ServeProcess(db, free_endpoint(), "--connect", endpoint)
        second.wait_for_log("serve.ready")
        ready_at = time.monotonic()
        time.sleep(0.5)
        producer.finish()
        code, _ = second.stop()
    finally:
        first.kill()
        if second is not None:
            second.kill()
    assert code == 0
    sent = {(f"vehicle/{i % SOURCES}", i // SOURCES) for i in range(len(producer.put_at))}
    with Store.open_read_only(db) as store:
        assert store.verify().ok
        stored = {(e["src"], e["seq"]) for e in store.events(RUN)}
        listed = {(g["src"], s) for g in store.gaps(RUN) for a, b in g["missing"] for s in range(a, b + 1)}
    assert committed and committed <= stored
    assert sent - stored - listed == set()       # none unaccounted
    sent_before = {(f"vehicle/{i % SOURCES}", i // SOURCES) for i, at in enumerate(producer.put_at) if at < ready_at}
    recovered = (sent_before - committed) & stored   # sent before the restart, not committed: only a cache had them
    assert recovered and len(recovered) == len(sent_before - committed - listed)
