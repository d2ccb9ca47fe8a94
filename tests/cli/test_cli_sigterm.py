"""SIGTERM (a CI job's timeout, `kill`) stops `gaps` as Ctrl-C does: it unwinds, so a regression
straight from a recording deletes the temporary store it imported the file into, and exits 143
saying why. Ended by the default action instead, the process left that store behind (388 MB
of the hour's recording after a few seconds, 7 GB once imported)."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).parents[2]
GOLDEN = ROOT / "tests" / "golden" / "golden-sim.mcap"


def _wait_for(found, seconds: float = 60.0):
    deadline = time.monotonic() + seconds
    while time.monotonic() < deadline:
        hit = found()
        if hit:
            return hit
        time.sleep(0.01)
    return None


def test_sigterm_deletes_the_temporary_store_and_exits_143(tmp_path):
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    env = {**os.environ, "PYTHONPATH": str(ROOT), "TMPDIR": str(tmp)}
    proc = subprocess.Popen([sys.executable, "-m", "cli.main", "regress", str(GOLDEN), "--rules",
                             str(ROOT / "reasoner" / "rules" / "validators.le")],
                            cwd=ROOT, env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        store = _wait_for(lambda: next(iter(tmp.glob("gaps-regress-*/recording.db")), None))
        assert store is not None, "the regression never began importing the recording"
        proc.send_signal(signal.SIGTERM)
        _, err = proc.communicate(timeout=120)
    finally:
        if proc.poll() is None:
            proc.kill()
    assert proc.returncode == 143, err
    assert "stopped by SIGTERM" in err and "Traceback" not in err
    assert list(tmp.iterdir()) == []
