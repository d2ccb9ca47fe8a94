"""Regression of many runs at once, on Dask (`gaps regress --workers N | --scheduler ADDRESS`).

    regress_store("fleet.db", rules=["new/"], runs=None, cluster=Cluster(workers=4))
    regress_recordings(["a.mcap", "b.mcap"], rules=["new/"], cluster=Cluster(scheduler="tcp://host:8786"))

The unit of work is a Task: one run of a store (the store's path and the run's name) or one
recording file (every run in it). A worker opens what its task names itself, judges it with its
own Prolog engine (janus is one per process, so a worker is a process with one thread) and sends
back plain data, a RunPart per run; the rulebooks travel as their texts (regress_books.BookText),
so a worker needs the project installed and the store or recordings at the same path, nothing
else. A run is never split across tasks: its incidents are matched, and its decisions asked, as a
whole, and the investigation keeps per-run state (the rulesets, the chain's status) that a split
would compute again in every part.

A worker may run tasks on several threads at once (a plain `dask worker` has one a CPU): each
thread asks its own Prolog engine (engine.py attaches one to every thread that asks) and opens
its own store and investigations (`_open` is per thread), so two tasks in one process share only
the rulebooks loaded once into the process's Prolog.

The cluster is Dask's own: a LocalCluster of `workers` processes by default, a running scheduler
with `scheduler`. A worker that dies has its task given to another by the scheduler (it tolerates
`allowed-failures`, 3 by default, deaths per task before calling it lost); a task that raises
(an unknown run, a recording that is not one) is a mistake said once, not retried. The parts are
put together in task order (regress.assemble), so the result is the one a single process gives.
"""
from __future__ import annotations

import logging
import threading
from contextlib import contextmanager
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Callable, Iterator, Sequence

from store import Store

from ..engine import get_engine
from .regression import Progress, Regression, Regressor, RunPart, assemble, chosen_runs
from .books import BookText, GivenBooks, RegressError, load_texts, read_given
from .recording import check_recording, judged_recording


@dataclass(frozen=True)
class Cluster:
    """Where tasks run: `workers` local processes, or the cluster a scheduler address leads to."""

    workers: int = 1
    scheduler: str | None = None

    @property
    def in_process(self) -> bool:
        return self.scheduler is None and self.workers <= 1


@dataclass(frozen=True)
class Job:
    """The two sides of the regression, as every task needs them."""

    rules: tuple[BookText, ...]
    baseline: tuple[BookText, ...] | None

    @classmethod
    def read(cls, rules: Sequence[str], baseline: Sequence[str] | None) -> Job:
        return cls(read_given(rules), read_given(baseline) if baseline else None)

    def books(self) -> tuple[GivenBooks, GivenBooks | None]:
        """The rulebooks loaded into this process's engine (checked: each used by a stage)."""
        engine = get_engine()
        new = load_texts(engine, self.rules, "--rules")
        return new, load_texts(engine, self.baseline, "--baseline") if self.baseline else None


@dataclass(frozen=True)
class Task:
    """One store run, or one recording file's runs, to judge."""

    source: str                          # an absolute path: a store file or a recording
    recording: bool
    run: str | None = None               # a store's run (a recording's are all judged)

    @property
    def label(self) -> str:
        return Path(self.source).name if self.recording else str(self.run)


CONNECT_TIMEOUT_S = 10                                # a scheduler that does not answer is a mistake said
WORKERS_UP_S = 120                                    # a local cluster's workers must be up by then
Judge = Callable[[Task, Job], list[RunPart]]


class ClusterLost(RegressError):
    """The cluster could not finish the job: a task every worker that took it died on, or the
    scheduler gone or forgetting the job. No judgement, so neither "nothing changed" (0) nor
    "changed" (1), nor a mistake of the user's (2)."""

    exit_code = 5


class _Open(threading.local):
    """This thread's store and its two investigations, kept open across the thread's tasks."""

    regressors: dict[tuple[str, Job], Regressor]

    def __init__(self) -> None:
        self.regressors = {}


_open = _Open()


def judge(task: Task, job: Job) -> list[RunPart]:
    """A task's runs judged under both sides: what a worker runs."""
    new, old = job.books()
    if task.recording:
        def parts(store: Store, problems: tuple[str, ...]) -> list[RunPart]:
            regressor = Regressor(store, get_engine(), new, old)
            return [_noting(regressor.part(run), problems) for run in store.run_names()]
        return judged_recording(task.source, parts)
    return [_store_regressor(task.source, job, new, old).part(str(task.run))]


def _store_regressor(path: str, job: Job, new: GivenBooks, old: GivenBooks | None) -> Regressor:
    """One read-only store and its two investigations per process, reused by the tasks of the
    same job (its runs' rulesets and chain checks are kept per run, so nothing is judged twice)."""
    key, mine = (path, job), _open.regressors
    if key not in mine:
        for regressor in mine.values():
            regressor.store.close()
        mine.clear()
        mine[key] = Regressor(Store.open_read_only(path), get_engine(), new, old)
    return mine[key]


def _noting(part: RunPart, problems: tuple[str, ...]) -> RunPart:
    if not problems:
        return part
    return replace(part, result=replace(part.result, problems=(*problems, *part.result.problems)))


def regress_store(db: str | Path, rules: Sequence[str], baseline: Sequence[str] | None = None,
                  runs: Sequence[str] | None = None, *, cluster: Cluster = Cluster(),
                  progress: Progress | None = None, judge_task: Judge = judge) -> Regression:
    """regress.regress over a store's runs (None: all), one task per run."""
    job = Job.read(rules, baseline)
    new, old = job.books()                       # a mistake in the rulebooks is said before any work
    path = str(Path(db).resolve())
    with Store.open_read_only(path) as store:
        chosen = chosen_runs(store, runs)
    tasks = [Task(path, False, run) for run in chosen]
    return assemble(new, old, run_tasks(tasks, job, cluster, progress, judge_task))


def regress_recordings(files: Sequence[str | Path], rules: Sequence[str], baseline: Sequence[str] | None = None,
                       *, cluster: Cluster = Cluster(), progress: Progress | None = None,
                       judge_task: Judge = judge) -> Regression:
    """Every run of each recording (MCAP or JSONL), one task per file, in the order given."""
    job = Job.read(rules, baseline)
    new, old = job.books()
    tasks = [Task(str(check_recording(f).resolve()), True) for f in files]
    return assemble(new, old, run_tasks(tasks, job, cluster, progress, judge_task))


def run_tasks(tasks: Sequence[Task], job: Job, cluster: Cluster, progress: Progress | None = None,
              judge_task: Judge = judge) -> list[RunPart]:
    """Every task's parts, in task order: here, or on the cluster."""
    if cluster.in_process:
        out = []
        for n, task in enumerate(tasks):
            out.extend(judge_task(task, job))
            if progress is not None:
                progress(task.label, n + 1, len(tasks))
        return out
    with _client(cluster) as client:
        # The job is a task of its own, not scattered data: data scattered to workers that all
        # die is lost for good and every task needing it cancelled ("already forgotten"); a
        # task's result is computed again on a live worker.
        shared = client.submit(_the_job, job, key=f"regress-job-{id(job):x}", pure=False)
        client.replicate([shared])      # on every worker: the runs' tasks then go where there is room,
        #                                 not all to the worker that made it (Dask places by locality)
        futures = [client.submit(judge_task, task, shared, key=f"regress-{n}-{task.label}", pure=False)
                   for n, task in enumerate(tasks)]
        labels = {f.key: t.label for f, t in zip(futures, tasks)}
        from distributed import KilledWorker, as_completed
        from distributed.client import FutureCancelledError
        try:
            for n, future in enumerate(as_completed(futures)):
                future.result()                  # a task's mistake is said now, the rest cancelled
                if progress is not None:
                    progress(labels[future.key], n + 1, len(tasks))
            return [part for future in futures for part in future.result()]
        except KilledWorker as exc:
            raise ClusterLost(f"{_lost(exc, labels)}: every worker that took it died (the scheduler's "
                              "allowed-failures); the run may be too big for a worker's memory") from None
        except (FutureCancelledError, OSError, TimeoutError) as exc:
            raise ClusterLost(f"the Dask cluster could not finish the regression ({type(exc).__name__}: "
                              f"{exc}); the scheduler or its workers were lost") from None


def _the_job(job: Job) -> Job:
    return job


def _lost(exc: Exception, labels: dict) -> str:
    key = getattr(exc, "task", None) or (exc.args[0] if exc.args else "")
    return f"the task judging {labels[key]}" if key in labels else f"a task ({exc})"


@contextmanager
def _client(cluster: Cluster) -> Iterator:
    """A Dask client on the scheduler given, or on a LocalCluster of one-thread worker processes
    started for this regression and stopped after it."""
    from distributed import Client, LocalCluster
    if cluster.scheduler is not None:
        try:
            client = Client(cluster.scheduler, timeout=CONNECT_TIMEOUT_S)
        except (OSError, TimeoutError, ValueError) as exc:
            raise RegressError(f"cannot reach the Dask scheduler at {cluster.scheduler}: {exc}") from None
        with client:
            yield client
        return
    with LocalCluster(n_workers=cluster.workers, threads_per_worker=1, processes=True, dashboard_address=None,
                      silence_logs=logging.ERROR) as local, Client(local) as client:
        # every worker up before the first task: one that came up late found the runs all taken by
        # the first (seen on a loaded machine: three runs, one worker)
        client.wait_for_workers(cluster.workers, timeout=WORKERS_UP_S)
        yield client
