"""Task functions for the Dask tests, importable by the cluster's worker processes."""
from __future__ import annotations

import os
from pathlib import Path

from reasoner.regress.cluster import Job, Task, judge


def die_once(marker: str, task: Task, job: Job):
    """The first task any worker takes kills its process mid-task (as an out-of-memory kill
    would), writing its pid to `marker` first; every other task is judged."""
    try:
        fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
    except FileExistsError:
        return judge(task, job)
    os.write(fd, str(os.getpid()).encode())
    os.close(fd)
    os._exit(1)


def judge_noting_pid(folder: str, task: Task, job: Job):
    """judge, leaving a file named for the worker process that ran the task."""
    (Path(folder) / f"{task.label}.{os.getpid()}").touch()
    return judge(task, job)


def die_always(task: Task, job: Job):
    """Every worker that takes the task dies of it (a run too big for any worker's memory)."""
    os._exit(1)
