"""Regression on a Dask cluster of two worker processes, and straight from recordings: the same
result as one process judging a store, a worker killed mid-task, a mistake said from a worker."""
from __future__ import annotations

import functools
import hashlib
import json
import logging
import os
import subprocess
import sys
from pathlib import Path

import pytest

from reasoner.regress import regress
from reasoner.regress.books import RegressError
from reasoner.regress.cluster import Cluster, regress_recordings, regress_store
from store import NoSuchRun, Store
from store.transfer import export_run, import_file

from tests.reasoner import regress_dying
from tests.reasoner import regress_runs as R

RUNS = ("run-a", "run-b", "run-c")
ROOT = Path(__file__).parents[2]


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    return R.build_store(tmp_path_factory.mktemp("regress-cluster") / "gaps.db", RUNS)


@pytest.fixture(scope="module")
def new(tmp_path_factory):
    """validators.le without the amber exception: a verdict and a decision flip in every run."""
    return str(R.edited(tmp_path_factory.mktemp("rules"), "validators.le", cut=(R.AMBER_TOO_CLOSE,)))


def fresh_json(*args: object) -> dict:
    """`gaps ARGS --json` in a process of its own: a rulebook is named by the path it was first
    loaded from in a process, so only a fresh process says what a user's command says."""
    done = subprocess.run([sys.executable, "-m", "cli.main", *map(str, args), "--json"], cwd=ROOT,
                          env={**os.environ, "PYTHONPATH": str(ROOT)}, capture_output=True, text=True, timeout=300)
    assert done.returncode in (0, 1), done.stderr
    return json.loads(done.stdout)


def same(result) -> dict:
    return json.loads(json.dumps(result.to_json(), default=str))


@pytest.fixture(scope="module")
def alone(db, new):
    """What one process, judging the store's runs one after another, says."""
    result = fresh_json("regress", "--rules", new, "--all", "--db", db)
    assert result["changed"] and len(result["runs"]) == 3
    return result


@pytest.fixture(scope="module")
def cluster():
    from distributed import Client, LocalCluster
    with LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as local:
        with Client(local) as client:       # both workers registered before the first test's tasks
            client.wait_for_workers(2, timeout=120)
        yield Cluster(scheduler=local.scheduler_address)


def test_two_workers_share_the_runs_and_give_what_one_process_gives(db, new, alone, cluster, tmp_path):
    seen, before = [], hashlib.sha256(db.read_bytes()).hexdigest()
    result = regress_store(db, [new], cluster=cluster, progress=lambda run, done, total: seen.append((done, total)),
                           judge_task=functools.partial(regress_dying.judge_noting_pid, str(tmp_path)))
    assert same(result) == alone
    assert hashlib.sha256(db.read_bytes()).hexdigest() == before          # the workers only read it
    assert sorted(seen) == [(1, 3), (2, 3), (3, 3)]
    pids = {p.name.rpartition(".")[2] for p in tmp_path.iterdir()}
    assert len(list(tmp_path.iterdir())) == 3 and len(pids) == 2 and str(os.getpid()) not in pids


def test_a_worker_killed_mid_task_has_its_run_judged_by_another(db, new, alone, cluster, tmp_path):
    marker = tmp_path / "died"
    result = regress_store(db, [new], cluster=cluster,
                           judge_task=functools.partial(regress_dying.die_once, str(marker)))
    assert same(result) == alone
    dead = int(marker.read_text())
    with pytest.raises(ProcessLookupError):
        os.kill(dead, 0)


def test_recordings_on_the_cluster_give_what_the_store_gives(db, new, alone, cluster, tmp_path):
    files = []
    with Store.open_read_only(db) as store:
        for run in RUNS:
            export_run(store, run, tmp_path / f"{run}.mcap")
            files.append(tmp_path / f"{run}.mcap")
    assert same(regress_recordings(files, [new], cluster=cluster)) == alone


def test_a_file_that_is_no_recording_is_said_from_the_worker(new, cluster, tmp_path):
    bad = tmp_path / "bad.mcap"
    bad.write_bytes(b"not an mcap file at all")
    with pytest.raises(RegressError, match="bad.mcap"):
        regress_recordings([bad], [new], cluster=cluster)


def test_an_unknown_run_is_said_before_any_work(db, new):
    with pytest.raises(NoSuchRun):
        regress_store(db, [new], runs=["nope"], cluster=Cluster(scheduler="tcp://127.0.0.1:9"))


def test_the_golden_recording_regressed_straight_gives_what_importing_it_gives(new, tmp_path):
    """About 15 s: the golden run (25,533 events) judged twice under both rulebooks, in this
    process (one engine: the rulebooks are named alike on both sides)."""
    recording = ROOT / "tests" / "golden" / "golden-sim.mcap"
    with Store(tmp_path / "imported.db") as store:
        import_file(store, recording)
        imported = regress(store, [new]).to_json()
    straight = regress_recordings([recording], [new]).to_json()
    assert imported["changed"] and imported["counts"]["verdict"] > 0 and straight == imported


def test_events_a_recording_refuses_are_said_as_a_problem_of_its_runs(db, new, tmp_path):
    recording = tmp_path / "run.jsonl"
    with Store.open_read_only(db) as store:
        export_run(store, RUNS[0], recording)
    with recording.open("a", encoding="utf-8") as out:
        out.write('{"v": 1, "run": "run-a", "src": "vehicle/5", "kind": "vehicle.decision"}\n')
    (result,) = regress_recordings([recording], [new]).runs
    assert result.problems == (f"{recording}: 1 event(s) refused on import, not judged (`gaps import` says why)",)
    assert len(result.incidents) == 3
