"""What the benchmarks ran on, printed beside every figure: shared machines vary."""
from __future__ import annotations

import json
import os
import platform
import sqlite3
import statistics
import time
from pathlib import Path


def machine() -> str:
    model = "unknown CPU"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    return (f"{cores} CPUs (nproc), {model}; Python {platform.python_version()}, "
            f"SQLite {sqlite3.sqlite_version}, {platform.system()} {platform.release()}")


QUIET_MS = "2.4-2.5 ms when this machine is quiet"


def calibration() -> float:
    """Median ms to parse a fixed 300 KB JSON document: the speed of this machine at this moment.
    A shared virtual machine's speed drifts by a factor of two or more from minute to minute;
    printed beside each round, this tells a slow round from a slow store."""
    doc = json.dumps([{"src": f"vehicle/{i}", "seq": i, "t": 1_732_184_100_000_000_000 + i, "body": {"x": i / 3, "facts": ["a", "b"]}}
                      for i in range(3000)])
    times = []
    for _ in range(20):
        started = time.perf_counter()
        json.loads(doc)
        times.append((time.perf_counter() - started) * 1000)
    return statistics.median(times)


def calibration_elsewhere() -> float:
    """calibration() in a fresh process: in a process holding a large heap (a benchmark's own
    results) the collector slows the parse down and the figure would blame the machine."""
    import subprocess
    import sys
    code = "import sys; sys.path.insert(0, sys.argv[1]); from machine import calibration; print(calibration())"
    out = subprocess.run([sys.executable, "-c", code, str(Path(__file__).parent)], capture_output=True,
                         text=True, check=True).stdout
    return float(out)
