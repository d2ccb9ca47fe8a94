"""The figures the docs quote are the ones bench/ recorded: docs/performance.md is what
bench/performance_md.py writes from bench/results.json, and every benchmark records through bench/results.py."""
from __future__ import annotations

import json
import re
import subprocess
import sys
from pathlib import Path
from types import ModuleType

import pytest

from tests.helpers.script_module import load_script

ROOT = Path(__file__).resolve().parents[2]
BENCH = ROOT / "bench"
HELPERS = {"machine.py", "results.py", "performance_md.py", "sim_runs.py"}


def _module(name: str) -> ModuleType:
    return load_script(BENCH / f"{name}.py", f"bench_{name}")


results = _module("results")


def _generate(results_json: Path, page: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, str(BENCH / "performance_md.py"), "--results", str(results_json),
                           "-o", str(page), *extra], capture_output=True, text=True, cwd=ROOT)


def test_committed_performance_page_is_what_the_generator_writes_from_the_committed_results():
    done = _generate(BENCH / "results.json", ROOT / "docs" / "performance.md", "--check")
    assert done.returncode == 0, done.stderr + "\nrun: python bench/performance_md.py"


def test_check_fails_on_a_page_edited_by_hand(tmp_path):
    page = tmp_path / "performance.md"
    assert _generate(BENCH / "results.json", page).returncode == 0
    page.write_text(page.read_text().replace("events/s", "events/min", 1))
    assert _generate(BENCH / "results.json", page, "--check").returncode == 1


def test_record_keeps_a_quick_run_apart_from_a_full_one_and_computes_the_ratio(tmp_path, monkeypatch):
    path = tmp_path / "results.json"
    monkeypatch.setenv("BENCH_RESULTS", str(path))
    figures = [results.Figure("ours", 50.0, "events/s", (40.0, 50.0, 60.0), peer="raw"),
               results.Figure("raw", 200.0, "events/s")]
    monkeypatch.setenv("BENCH_QUICK", "1")
    results.record("demo", "A demo bench", figures, notes="n")
    monkeypatch.delenv("BENCH_QUICK")
    results.record("demo", "A demo bench", [results.Figure("raw", 1.0, "events/s")])
    stored = json.loads(path.read_text())["results"]
    assert set(stored) == {"demo", "demo-quick"}
    quick = stored["demo-quick"]
    assert quick["quick"] is True and quick["source"] == "measured"
    assert quick["command"].startswith("BENCH_QUICK=1 python ")
    assert quick["figures"][0]["ratio"] == 0.25
    assert quick["machine"]["cores"] >= 1 and "Python" in quick["machine"]["line"]
    assert re.fullmatch(r"\d{4}-\d\d-\d\d", quick["date"])
    again = results.read(path)
    assert again["demo-quick"].figures[0].runs == (40.0, 50.0, 60.0)


def test_a_peer_that_was_not_measured_is_refused():
    with pytest.raises(ValueError, match="names peer 'nope'"):
        results.with_ratios([results.Figure("ours", 1.0, "ms", peer="nope")])


def test_every_benchmark_records_its_figures_and_make_bench_runs_it():
    makefile = (ROOT / "Makefile").read_text()
    listed = re.search(r"^BENCHES := (.*)$", makefile, re.M)
    assert listed, "Makefile has no BENCHES list"
    scripts = sorted(p.stem for p in BENCH.glob("*.py") if p.name not in HELPERS)
    assert sorted(listed.group(1).split()) == scripts
    for name in scripts:
        assert re.search(r"^\s*record\(", (BENCH / f"{name}.py").read_text(), re.M), f"bench/{name}.py records nothing"


def test_every_recorded_result_says_where_it_came_from():
    for key, result in results.read(BENCH / "results.json").items():
        assert result.source == "measured" or result.source.startswith("README as of "), key
        assert result.command.startswith(("python bench/", "BENCH_QUICK=1 python bench/")), key
        assert result.machine.line(), key


@pytest.mark.parametrize("ratio, text", [(0.53, "0.53"), (2.0, "2.00"), (0.1, "0.10"), (0.000981, "1/1,019"),
                                         (0.02, "1/50"), (0.0, "0.00")])
def test_a_small_ratio_is_written_as_one_in_n_not_as_zero(ratio, text):
    sys.path.insert(0, str(BENCH))   # performance_md imports results.py beside it, as the bench scripts do
    try:
        assert _module("performance_md").ratio_text(ratio) == text
    finally:
        sys.path.remove(str(BENCH))


@pytest.mark.parametrize("name", sorted(p.stem for p in BENCH.glob("*.py")))
def test_every_benchmark_script_imports_against_the_code_it_measures(name, monkeypatch):
    """A benchmark is run by hand, not by the suite, so a name it imports that the code renamed
    would go unseen until someone measures: importing each one (its main is not run) catches it.
    Run as a script, a benchmark finds its siblings (machine, results) on its own directory."""
    monkeypatch.syspath_prepend(str(BENCH))
    module = _module(name)
    assert module.__file__ == str(BENCH / f"{name}.py")
