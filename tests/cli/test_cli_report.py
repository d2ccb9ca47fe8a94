"""`gaps report` and the report `gaps demo` writes, as a user runs them: files written, the format
from the suffix, and one-line errors with the documented exit codes."""
from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from sim_replay.paper import RUN

GAPS = str(Path(sys.executable).with_name("gaps"))


def gaps(*args: str, db: Path, env: dict | None = None) -> subprocess.CompletedProcess:
    """The installed `gaps` in a real process: the report's browser and exit codes as a user meets them."""
    import os
    return subprocess.run([GAPS, *args, "--db", str(db)], capture_output=True, text=True, timeout=180,
                          env={**os.environ, **(env or {})})


def one_line_error(r: subprocess.CompletedProcess, code: int, text: str) -> None:
    assert r.returncode == code, (r.stdout, r.stderr)
    assert text in r.stderr and "Traceback" not in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


@pytest.mark.parametrize("suffix", ["html", "md", "json"])
def test_report_in_each_format(paper_db, tmp_path, suffix):
    out = tmp_path / f"report.{suffix}"
    r = gaps("report", "--run", RUN, "-o", str(out), db=paper_db)
    assert r.returncode == 0, r.stderr
    assert f"Wrote the report of run {RUN} (2 incidents" in r.stdout and str(out) in r.stdout
    text = out.read_text(encoding="utf-8")
    if suffix == "json":
        assert [e["row"]["verdict"] for e in json.loads(text)["incidents"]] == ["punishable", "mitigated"]
    elif suffix == "md":
        assert text.startswith("# Incident report: run paper-junctions")
    else:
        assert text.startswith("<!DOCTYPE html>") and text.count('class="gaps-scene"') == 2


def test_report_of_one_incident(paper_db, tmp_path):
    out = tmp_path / "one.json"
    r = gaps("report", "--run", RUN, "--incident", "monitor/m1:3", "-o", str(out), db=paper_db)
    assert r.returncode == 0 and "(1 incident," in r.stdout
    assert [e["row"]["vehicle"] for e in json.loads(out.read_text())["incidents"]] == ["253"]


def test_report_errors_are_one_line(paper_db, tmp_path):
    one_line_error(gaps("report", "--run", RUN, "-o", str(tmp_path / "r.txt"), db=paper_db), 2, "name the file .html")
    one_line_error(gaps("report", "--run", "nope", "-o", str(tmp_path / "r.html"), db=paper_db), 2, "no run 'nope'")
    one_line_error(gaps("report", "--run", RUN, "--incident", "9", "-o", str(tmp_path / "r.html"), db=paper_db), 2,
                   "no incident '9' in run 'paper-junctions'; incidents: 1=monitor/m1:1, 2=monitor/m1:3")
    one_line_error(gaps("report", "--run", RUN, "-o", str(tmp_path / "no" / "r.html"), db=paper_db), 2,
                   "no such folder for the report")
    one_line_error(gaps("report", "--run", RUN, "--rules", str(tmp_path / "x.le"), "-o", str(tmp_path / "r.html"),
                        db=paper_db), 2, "no such rulebook file")
    one_line_error(gaps("report", "--run", RUN, "-o", str(tmp_path / "r.html"), db=tmp_path / "none.db"), 2,
                   "no event store at")
    assert not list(tmp_path.glob("r.*"))


def test_pdf_without_chromium_is_a_missing_tool(paper_db, tmp_path):
    r = gaps("report", "--run", RUN, "-o", str(tmp_path / "r.html"), "--pdf", db=paper_db,
             env={"GAPS_CHROMIUM": "no-such-chromium"})
    one_line_error(r, 3, "--pdf needs a headless Chromium")
    assert not (tmp_path / "r.html").exists()         # refused before any work


def test_demo_writes_the_report_and_says_where(tmp_path):
    report = tmp_path / "demo-report.html"
    r = gaps("demo", "--paper", "--report", str(report), db=tmp_path / "gaps.db")
    assert r.returncode == 0, r.stderr
    assert "Vehicle 173 committed a punishable violation" in r.stdout
    assert "Vehicle 253 committed a mitigated violation" in r.stdout
    assert f"Report of run {RUN}: {report}" in r.stdout
    assert report.read_text(encoding="utf-8").count('class="gaps-timeline"') == 2


def test_demo_report_defaults_to_beside_the_store(tmp_path):
    r = gaps("demo", "--paper", db=tmp_path / "gaps.db")
    assert r.returncode == 0, r.stderr
    assert (tmp_path / "gaps-report.html").is_file()
    assert str(tmp_path / "gaps-report.html") in r.stdout
