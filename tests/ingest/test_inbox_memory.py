"""A quiet ingest gives back the memory of a drained burst (issue 40).

Zenoh's FIFO channel, the inbox's queue, grows to hold what waited and never shrinks: 80,000
samples waiting whole left some 24 MB resident in the process for ever after the writer had taken
them all (main before the inbox's renewal, 2026-12-07: 48 MB idle, 73 MB after). A quiet inbox now
renews its subscription, and the old channel goes (ingest/inbox.py). Measured in a child process of
its own (tests/helpers/drained_burst.py), its batches small so that what the interpreter keeps of
them stays small beside the queue; the bound leaves room for a busy machine's noise.
"""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from ingest.idle_memory import _trim
from tests.helpers.serve_testkit import ROOT, child_env

RUNS, PER_RUN, BATCH = 800, 100, 500
LEFT_MB = 10.0   # what may stay; the FIFO channel kept about 24 MB, the renewal about 1


@pytest.mark.skipif(_trim is None or not Path("/proc/self/status").exists(), reason="glibc and /proc needed")
def test_a_drained_burst_leaves_no_queue_behind(tmp_path: Path) -> None:
    done = subprocess.run([sys.executable, "-m", "tests.helpers.drained_burst", str(RUNS), str(PER_RUN), str(BATCH),
                           str(tmp_path / "burst.db")], cwd=ROOT, env=child_env(), capture_output=True, text=True,
                          timeout=300)
    assert done.returncode == 0, done.stderr[-3000:]
    found = json.loads(done.stdout.strip().splitlines()[-1])
    assert (found["stored"], found["rejected"], found["failed"]) == (found["received"], 0, 0)
    assert found["burst"] == RUNS * PER_RUN
    left = found["after_mb"] - found["idle_mb"]
    assert left < LEFT_MB, f"{left:.1f} MB resident after the burst's drain ({found})"
