"""A Dask worker's tasks on several threads of one process (a plain `dask worker` has one a CPU):
each thread judges with its own Prolog engine and its own store, and the result is the one a
single thread gives. Before engine.py attached an engine to every asking thread, `holds` from
any thread but the one that started Prolog killed the process with SIGSEGV (janus_swi's
apply_once attaches none), so each case runs in a child process and its exit is checked."""
from __future__ import annotations

import json
import logging
import os
import subprocess
import sys
from pathlib import Path

import pytest

from reasoner.regress.cluster import regress_store
from tests.reasoner import regress_runs as R

ROOT = Path(__file__).parents[2]
RUNS = ("run-a", "run-b", "run-c", "run-d")

FOUR_THREADS = """
import json, sys, threading
from reasoner.regress import assemble
from reasoner.regress.cluster import Job, Task, judge
job = Job.read([sys.argv[1]], None)
tasks = [Task(sys.argv[2], False, run) for run in sys.argv[3:]]
parts, ready = {}, threading.Barrier(len(tasks))
def go(n):
    ready.wait()                                   # every thread asks at the same moment
    parts[n] = judge(tasks[n], job)
threads = [threading.Thread(target=go, args=(n,)) for n in range(len(tasks))]
for t in threads: t.start()
for t in threads: t.join()
new, old = job.books()
print(json.dumps(assemble(new, old, [p for n in range(len(tasks)) for p in parts[n]]).to_json(), default=str))
"""

ONE_QUESTION_OFF_THE_MAIN_THREAD = """
import threading
from reasoner.bundled import RULES_DIR
from reasoner.engine import get_engine
from reasoner.le.document import parse_document
engine = get_engine()
book = engine.load((RULES_DIR / "paper.le").read_text(), "paper.le")
answers = []
t = threading.Thread(target=lambda: answers.append(engine.holds(book, book.document.rules[0].head, [])))
t.start(); t.join()
print(answers)
"""


def child(code: str, *args: object) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code, *map(str, args)], cwd=ROOT, capture_output=True, text=True,
                          env={**os.environ, "PYTHONPATH": str(ROOT), "PYTHONFAULTHANDLER": "1"}, timeout=300)


@pytest.fixture(scope="module")
def db(tmp_path_factory):
    return R.build_store(tmp_path_factory.mktemp("regress-threads") / "gaps.db", RUNS)


@pytest.fixture(scope="module")
def new(tmp_path_factory):
    return str(R.edited(tmp_path_factory.mktemp("rules"), "validators.le", cut=(R.AMBER_TOO_CLOSE,)))


def test_a_question_from_a_thread_that_did_not_start_prolog_is_answered():
    done = child(ONE_QUESTION_OFF_THE_MAIN_THREAD)
    assert done.returncode == 0, done.stderr[-2000:]
    assert done.stdout.strip() in ("[True]", "[False]")


def test_four_threads_judging_at_once_give_what_one_thread_gives(db, new):
    done = child(FOUR_THREADS, new, db, *RUNS)
    assert done.returncode == 0, done.stderr[-2000:]
    alone = json.loads(json.dumps(regress_store(db, [new]).to_json(), default=str))
    assert alone["changed"] and len(alone["runs"]) == 4
    assert json.loads(done.stdout) == alone


def test_a_cluster_that_cannot_finish_is_its_own_exit_code_not_a_judgement(db, new):
    """Every worker that takes the task dies (allowed-failures 0 here, 3 by default): exit 5,
    one line naming the run, neither 0 nor 1 (judgements) nor a traceback."""
    import dask
    from distributed import LocalCluster

    from reasoner.regress.cluster import Cluster, ClusterLost
    from tests.reasoner import regress_dying
    with dask.config.set({"distributed.scheduler.allowed-failures": 0}), \
            LocalCluster(n_workers=1, threads_per_worker=1, processes=True, dashboard_address=None,
                         silence_logs=logging.CRITICAL) as local:
        with pytest.raises(ClusterLost, match="the task judging run-a: every worker that took it died") as lost:
            regress_store(db, [new], runs=["run-a"], cluster=Cluster(scheduler=local.scheduler_address),
                          judge_task=regress_dying.die_always)
    assert lost.value.exit_code == 5
