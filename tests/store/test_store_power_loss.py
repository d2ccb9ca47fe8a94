"""Power loss between write and commit, simulated: a child writing the store is killed with SIGKILL
after its transaction's pages reached the WAL and before its COMMIT (tests/helpers/pause_before_commit.py).
Reopened, the store verifies and holds exactly what was committed before: a prefix of the chain,
none of the written-but-uncommitted batch; appending again stores the rest (issue 15, fault injection)."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from store import Store
from store.errors import DiskFull
from tests.helpers.store_testkit import event

ROOT = Path(__file__).parents[2]
EVENTS = 6_000


def write_jsonl(path: Path) -> list[dict]:
    evs = [event(seq, src="vehicle/173") for seq in range(EVENTS)]
    path.write_text("".join(json.dumps(ev) + "\n" for ev in evs))
    return evs


def paused_import(tmp_path: Path, source: Path, db: Path, at: int) -> tuple[subprocess.Popen, dict]:
    """`gaps import` in a child stopped before the COMMIT of its `at`th append."""
    marker = tmp_path / "paused.json"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "GAPS_PAUSE_AT": str(at), "GAPS_PAUSE_MARKER": str(marker)}
    child = subprocess.Popen([sys.executable, "-m", "tests.helpers.pause_before_commit", "import", str(source),
                              "--db", str(db)], cwd=ROOT, env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    deadline = time.monotonic() + 60
    while not marker.exists():
        assert child.poll() is None, child.stderr.read()
        assert time.monotonic() < deadline, "the child never reached the pause"
        time.sleep(0.05)
    time.sleep(0.05)  # the marker is written whole before the pause; let the write finish
    return child, json.loads(marker.read_text())


def test_a_kill_between_write_and_commit_leaves_the_committed_prefix(tmp_path: Path) -> None:
    source, db = tmp_path / "run.jsonl", tmp_path / "gaps.db"
    evs = write_jsonl(source)
    child, paused = paused_import(tmp_path, source, db, at=2)
    assert paused["wal_now"] > paused["wal_at_begin"], paused  # the batch's pages are in the WAL, uncommitted
    with Store.open_read_only(db) as reader:
        committed = reader.count()
    child.send_signal(signal.SIGKILL)
    child.wait()
    assert 0 < committed < EVENTS

    with Store(db) as store:              # what the next writer sees: the WAL's uncommitted frames ignored
        report = store.verify()
        stored = [(ev["src"], ev["seq"]) for ev in store.events(evs[0]["run"])]
    assert report.ok, report.problem
    assert stored == [(ev["src"], ev["seq"]) for ev in evs[:committed]]

    with Store(db) as store:              # and it goes on from the committed head
        again = store.append(evs)
        assert (again.stored, again.duplicates) == (EVENTS - committed, committed)
        assert store.verify().ok and store.count() == EVENTS


def test_a_full_disk_during_an_append_leaves_the_store_whole_and_appendable(tmp_path: Path) -> None:
    evs = [event(seq, src="vehicle/173") for seq in range(3_000)]
    with Store(tmp_path / "gaps.db") as store:
        store.append(evs[:100])
        pages = store.connection.execute("PRAGMA page_count").fetchone()[0]
        store.connection.execute(f"PRAGMA max_page_count = {pages}")   # SQLite's own full disk
        with pytest.raises(DiskFull, match="full"):      # the store's own error: free space, try again
            store.append(evs[100:])
        assert store.count() == 100 and store.verify().ok
        store.connection.execute("PRAGMA max_page_count = 1073741823")  # room again
        assert store.append(evs[100:]).stored == 2_900
        assert store.verify().ok and store.chain_head(evs[0]["run"])[0] == 3_000
