"""Regression on a Dask cluster started as its users start it (docs/regress.md "On a Dask
cluster"), one worker killed mid-job: the same result as one process, to the byte (a benchmark of
reliability, not a test; tests/reasoner/test_regress_threads.py runs the threads part in seconds).

    .venv/bin/python bench/dask_kill.py [--trials 10] [--runs 12] [--workers 2]

A `dask scheduler` on loopback and `--workers` plain `dask worker ADDRESS` processes, each with its
default threads (one per CPU: two here) and its nanny, as the docs' commands start them. A store
of `--runs` small runs (tests/reasoner/regress_runs: four crossings each, a verdict and a decision
flip under validators.le without its amber exception) is judged once by `gaps regress --json` in
one process, then, per trial, by `gaps regress --scheduler ADDRESS --json`: while the job runs,
one worker process that is running a task is sent SIGKILL (as an out-of-memory kill would), its
nanny starts another, and the command must still print the one process's bytes with exit 1
("changed"). Printed per trial: exit code, seconds, whether a worker was killed mid-task, and
whether the output is the same to the byte.
"""
from __future__ import annotations

import argparse
import os
import signal
import socket
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(Path(__file__).resolve().parent))

from results import Figure, quick, record  # noqa: E402
from tests.reasoner import regress_runs as R  # noqa: E402

BIN = Path(sys.executable).parent


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def env() -> dict:
    return {**os.environ, "PYTHONPATH": str(ROOT), "PYTHONFAULTHANDLER": "1"}


def start_cluster(workers: int, folder: Path) -> tuple[str, list[subprocess.Popen]]:
    """`dask scheduler` and `workers` x `dask worker ADDRESS`, as docs/regress.md says."""
    port = free_port()
    address = f"tcp://127.0.0.1:{port}"
    procs = [subprocess.Popen([str(BIN / "dask"), "scheduler", "--host", "127.0.0.1", "--port", str(port),
                               "--dashboard-address", "127.0.0.1:0"], env=env(),
                              stdout=subprocess.DEVNULL, stderr=open(folder / "scheduler.log", "w"))]
    time.sleep(2)
    for n in range(workers):
        procs.append(subprocess.Popen([str(BIN / "dask"), "worker", address], env=env(), stdout=subprocess.DEVNULL,
                                      stderr=open(folder / f"worker-{n}.log", "w")))
    from distributed import Client
    with Client(address, timeout=60) as client:
        client.wait_for_workers(workers, timeout=120)
        threads = client.nthreads()
    print(f"cluster at {address}: {len(threads)} workers, threads {sorted(threads.values())}", flush=True)
    return address, procs


def kill_one_busy(address: str, started: threading.Event, done: threading.Event, killed: list) -> None:
    """SIGKILL the process of the first worker seen running a task of the job."""
    from distributed import Client
    with Client(address, timeout=60) as client:
        started.set()
        while not done.is_set():
            busy = {w: keys for w, keys in client.processing().items()
                    if any(str(k).startswith("regress-") and "job" not in str(k) for k in keys)}
            if busy:
                worker = sorted(busy)[0]
                pid = client.run(os.getpid, workers=[worker]).get(worker)
                if pid:
                    os.kill(pid, signal.SIGKILL)
                    killed.append((worker, pid))
                    return
            time.sleep(0.05)


def regress(args: list[str], out: Path) -> tuple[int, float, bytes, str]:
    started = time.perf_counter()
    done = subprocess.run([str(BIN / "gaps"), "regress", *args, "--json"], env=env(), capture_output=True,
                          cwd=ROOT, timeout=900)
    out.write_bytes(done.stdout)
    return done.returncode, time.perf_counter() - started, done.stdout, done.stderr.decode(errors="replace")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--trials", type=int, default=3 if quick() else 10)
    parser.add_argument("--runs", type=int, default=6 if quick() else 12)
    parser.add_argument("--workers", type=int, default=2)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="gaps-dask-kill-") as tmp:
        folder = Path(tmp)
        db = R.build_store(folder / "gaps.db", tuple(f"run-{n:02d}" for n in range(args.runs)))
        rules = R.edited(folder / "rules", "validators.le", cut=(R.AMBER_TOO_CLOSE,))
        common = ["--rules", str(rules), "--all", "--db", str(db)]
        code, seconds, alone, err = regress(common, folder / "alone.json")
        print(f"one process: exit {code}, {seconds:.1f} s, {len(alone)} bytes", flush=True)
        assert code == 1, err
        address, procs = start_cluster(args.workers, folder)
        rows, same, times = [], 0, []
        try:
            for n in range(args.trials):
                started, done, killed = threading.Event(), threading.Event(), []
                killer = threading.Thread(target=kill_one_busy, args=(address, started, done, killed))
                killer.start()
                started.wait(60)
                code, seconds, out, err = regress([*common, "--scheduler", address], folder / f"trial-{n}.json")
                done.set()
                killer.join()
                alike = out == alone and code == 1
                same += alike
                times.append(seconds)
                tail = "" if alike else f"; stderr: {err.strip().splitlines()[-1:] if err.strip() else ''}"
                print(f"trial {n + 1}: exit {code}, {seconds:.1f} s, killed {killed[0][1] if killed else 'none'} "
                      f"mid-task, same bytes as one process: {alike}{tail}", flush=True)
                rows.append({"exit": code, "seconds": round(seconds, 2), "killed": bool(killed), "same": alike})
        finally:
            for proc in reversed(procs):
                proc.send_signal(signal.SIGTERM)
            for proc in procs:
                try:
                    proc.wait(30)
                except subprocess.TimeoutExpired:
                    proc.kill()
        for log in sorted(folder.glob("worker-*.log")):         # a worker that crashed says where
            text = log.read_text(errors="replace")
            for at in [i for i in range(len(text)) if text.startswith("Fatal Python error", i)][:3]:
                print(f"{log.name}: {text[at:at + 3000]}", flush=True)
        killed_all = sum(r["killed"] for r in rows)
        print(f"same as one process to the byte: {same} of {args.trials} trials "
              f"({killed_all} with a worker killed mid-task)", flush=True)
        times.sort()
        record("dask_kill", f"gaps regress on a scheduler and {args.workers} default `dask worker`s, one killed "
               "mid-job", [Figure("trials the same as one process to the byte", same, "trials",
                                  target=f"{args.trials} of {args.trials}"),
                           Figure("trials with a worker killed mid-task", killed_all, "trials"),
                           Figure("regression on the cluster", times[len(times) // 2], "s", tuple(times))],
               notes=f"{args.runs} runs, {args.workers} workers of their default threads",
               details={"trials": rows})


if __name__ == "__main__":
    main()
