"""Where every benchmark records its figures: bench/results.json, read by bench/performance_md.py.

A figure quoted without the machine, the date and the command that produced it cannot be checked or
compared, so each benchmark records all of them beside its figures, and docs/performance.md is
generated from this file rather than typed. `BENCH_QUICK=1` (or `make bench-quick`) runs reduced
sizes: those results are recorded under their own key, so that a quick run never overwrites a
full one. `BENCH_RESULTS=PATH` records elsewhere (tests do).
"""
from __future__ import annotations

import datetime as _dt
import json
import os
import platform
import shlex
import sqlite3
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

RESULTS = Path(__file__).resolve().parent / "results.json"
MEASURED = "measured"


def quick() -> bool:
    """True when the reduced sizes were asked for (`BENCH_QUICK=1`)."""
    return os.environ.get("BENCH_QUICK", "") not in ("", "0")


def results_path() -> Path:
    return Path(os.environ["BENCH_RESULTS"]) if os.environ.get("BENCH_RESULTS") else RESULTS


@dataclass(frozen=True)
class Machine:
    """What a figure was measured on: a shared virtual machine's speed is part of the figure."""
    cpu: str
    cores: int | None
    ram_gb: float | None
    os: str | None
    python: str | None
    extra: str = ""  # SQLite or SWI-Prolog version, load average: what else the bench saw

    def line(self) -> str:
        parts = [self.cpu]
        if self.cores is not None:
            parts.append(f"{self.cores} logical CPUs")
        if self.ram_gb is not None:
            parts.append(f"{self.ram_gb:.0f} GB RAM")
        if self.os:
            parts.append(self.os)
        if self.python:
            parts.append(f"Python {self.python}")
        if self.extra:
            parts.append(self.extra)
        return ", ".join(parts)

    def to_json(self) -> dict[str, Any]:
        return {"cpu": self.cpu, "cores": self.cores, "ram_gb": None if self.ram_gb is None else round(self.ram_gb, 1), "os": self.os,
                "python": self.python, "extra": self.extra, "line": self.line()}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Machine:
        return cls(data["cpu"], data.get("cores"), data.get("ram_gb"), data.get("os"), data.get("python"),
                   data.get("extra", ""))


def this_machine(extra: str = "") -> Machine:
    """The machine this process runs on, read from /proc where Linux offers it."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count()
    sqlite = f"SQLite {sqlite3.sqlite_version}"
    return Machine(_cpu_model(), cores, _ram_gb(), f"{platform.system()} {platform.release()}",
                   platform.python_version(), f"{sqlite}; {extra}" if extra else sqlite)


def _cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or "unknown CPU"


def _ram_gb() -> float | None:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemTotal:"):
                return int(line.split()[1]) / 1024 ** 2
    except (OSError, ValueError, IndexError):
        pass
    return None


def load_average() -> str:
    """The 1-minute load average, for the machine line: the machine is shared with other work."""
    return f"load average {os.getloadavg()[0]:.2f}" if hasattr(os, "getloadavg") else ""


@dataclass(frozen=True)
class Figure:
    """One measured quantity: its median over the runs, in its unit, and how it compares with its
    peer (the figure measured beside it as the reference, e.g. raw SQLite inserts) when there is one."""
    name: str
    median: float
    unit: str
    runs: tuple[float, ...] = ()
    target: str = ""
    peer: str = ""          # name of the figure in the same result this one is compared with
    ratio: float | None = None  # median / peer's median
    note: str = ""

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "median": _sig(self.median), "unit": self.unit,
                "runs": [_sig(r) for r in self.runs], "target": self.target, "peer": self.peer,
                "ratio": None if self.ratio is None else _sig(self.ratio), "note": self.note}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Figure:
        return cls(data["name"], data["median"], data["unit"], tuple(data.get("runs", ())), data.get("target", ""),
                   data.get("peer", ""), data.get("ratio"), data.get("note", ""))


def _sig(x: float) -> float:
    """Six significant digits: more than any of these measurements can support."""
    return float(f"{x:.6g}")


@dataclass(frozen=True)
class Result:
    """One run of one benchmark, as recorded in results.json."""
    benchmark: str  # the script's name without .py
    title: str
    figures: tuple[Figure, ...]
    machine: Machine
    date: str       # ISO 8601 date of the run
    command: str    # what produced it, to run it again
    quick: bool = False
    source: str = MEASURED  # or "README as of <commit>" for figures transcribed from an earlier run
    notes: str = ""
    details: dict[str, Any] = field(default_factory=dict)  # the script's own extra figures, as JSON

    @property
    def key(self) -> str:
        return f"{self.benchmark}-quick" if self.quick else self.benchmark

    def to_json(self) -> dict[str, Any]:
        return {"benchmark": self.benchmark, "title": self.title, "quick": self.quick, "source": self.source,
                "date": self.date, "command": self.command, "machine": self.machine.to_json(),
                "figures": [f.to_json() for f in self.figures], "notes": self.notes, "details": self.details}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Result:
        return cls(data["benchmark"], data["title"], tuple(Figure.from_json(f) for f in data["figures"]),
                   Machine.from_json(data["machine"]), data["date"], data["command"], data.get("quick", False),
                   data.get("source", MEASURED), data.get("notes", ""), data.get("details", {}))


def with_ratios(figures: list[Figure]) -> tuple[Figure, ...]:
    """Each figure's ratio to its named peer, computed here so that no script computes it its own way."""
    by_name = {f.name: f for f in figures}
    out = []
    for f in figures:
        peer = by_name.get(f.peer)
        if f.peer and peer is None:
            raise ValueError(f"figure {f.name!r} names peer {f.peer!r}, which is not among {sorted(by_name)}")
        ratio = f.median / peer.median if peer and peer.median else f.ratio
        out.append(Figure(f.name, f.median, f.unit, f.runs, f.target, f.peer, ratio, f.note))
    return tuple(out)


def command_line() -> str:
    """How this benchmark was started, as one would type it again."""
    script = Path(sys.argv[0])
    try:
        script = script.resolve().relative_to(Path(__file__).resolve().parents[1])
    except ValueError:
        pass
    prefix = "BENCH_QUICK=1 " if quick() else ""
    return prefix + shlex.join(["python", str(script), *sys.argv[1:]])


def read(path: Path | None = None) -> dict[str, Result]:
    path = path or results_path()
    if not path.exists():
        return {}
    data = json.loads(path.read_text(encoding="utf-8"))
    return {key: Result.from_json(entry) for key, entry in data["results"].items()}


def write(results: dict[str, Result], path: Path | None = None) -> None:
    path = path or results_path()
    data = {"about": "written by bench/results.py; docs/performance.md is generated from it "
                     "(python bench/performance_md.py)",
            "results": {key: results[key].to_json() for key in sorted(results)}}
    path.write_text(json.dumps(data, indent=2, ensure_ascii=False) + "\n", encoding="utf-8")


def record(benchmark: str, title: str, figures: list[Figure], *, notes: str = "", machine_extra: str = "",
           details: dict[str, Any] | None = None, path: Path | None = None) -> Result:
    """Record one run of a benchmark (replacing its previous run of the same size) and return it."""
    extra = machine_extra if "load average" in machine_extra else ", ".join(filter(None, [machine_extra, load_average()]))
    result = Result(benchmark, title, with_ratios(figures), this_machine(extra),
                    _dt.date.today().isoformat(), command_line(), quick(), MEASURED, notes, details or {})
    results = read(path)
    results[result.key] = result
    write(results, path)
    print(f"recorded {result.key} in {path or results_path()}", flush=True)
    return result
