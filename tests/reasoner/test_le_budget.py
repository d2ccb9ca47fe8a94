"""Budgets of evaluating a rulebook (issue 15, finding 6): big-number arithmetic is bounded by the
size of each integer it makes, as recursion is by the inference limit, so a hostile document ends
in a clear error and a non-zero exit, quickly and in little memory, never in an out-of-memory kill
(40 squarings took 2 GB and a minute, and the exhausted memory was read as "no answers")."""

from __future__ import annotations

import resource
import subprocess
import sys
import time
from pathlib import Path

import pytest

from reasoner.bundled import RULES_DIR
from reasoner.engine import QuestionError, get_engine
from reasoner.le.document import parse_question

ROOT = Path(__file__).resolve().parents[2]

SQUARING = """the templates are:
*a number* squared *a count* times is *a result*.
the knowledge base k includes:
a number squared a count times is a result
    if the count = 0
    and the result = the number.
a number squared a count times is a result
    if the count > 0
    and a next = the number * the number
    and a fewer = the count - 1
    and the next squared the fewer times is the result.
scenario s is:
query q is:
2 squared 40 times is which result.
"""


def _answers(text: str, question: str) -> list[str]:
    engine = get_engine()
    rb = engine.load(text, "squaring.le")
    return engine.answers(rb, parse_question(rb.document, question), []).answers


def test_ordinary_arithmetic_is_unchanged():
    assert _answers(SQUARING, "2 squared 5 times is which result") == ["2 squared 5 times is 4294967296"]
    assert _answers(SQUARING, "3 squared 0 times is which result") == ["3 squared 0 times is 3"]
    assert len(_answers(SQUARING, "2 squared 11 times is which result")) == 1  # 2**2048: 2,049 bits
    with pytest.raises(QuestionError):
        _answers(SQUARING, "2 squared 12 times is which result")  # 2**4096: 4,097 bits


def test_repeated_squaring_ends_in_a_clear_error_quickly():
    started = time.monotonic()
    with pytest.raises(QuestionError, match="integer of more than 4096 bits"):
        _answers(SQUARING, "2 squared 40 times is which result")
    assert time.monotonic() - started < 5
    assert _answers(SQUARING, "2 squared 1 times is which result") == ["2 squared 1 times is 4"]  # goes on


def test_an_operation_on_words_still_fails_quietly():
    text = SQUARING.replace("2 squared 40 times", "x squared 3 times")
    assert _answers(text, "x squared 3 times is which result") == []


def _run(*args: str) -> tuple[subprocess.CompletedProcess, float]:
    """`gaps ARGS` in a child process under a 3 GiB address-space cap; returns its peak RSS in MiB."""
    code = ("import resource, sys\nfrom cli.main import main\nsys.argv = ['gaps'] + sys.argv[1:]\n"
            "try:\n    main()\nfinally:\n"
            "    print('peak', resource.getrusage(resource.RUSAGE_SELF).ru_maxrss // 1024, file=sys.stderr)\n")
    cap = 3 << 30
    child = subprocess.run([sys.executable, "-c", code, *args], cwd=ROOT, capture_output=True, text=True,
                           timeout=120, env={"PYTHONPATH": str(ROOT), "PATH": "/usr/bin:/bin"},
                           preexec_fn=lambda: resource.setrlimit(resource.RLIMIT_AS, (cap, cap)))
    peak = int(child.stderr.rsplit("peak ", 1)[1])
    return child, peak


def test_rules_query_on_a_squaring_document_exits_1_with_a_message(tmp_path):
    doc = tmp_path / "squaring.le"
    doc.write_text(SQUARING, encoding="utf-8")
    started = time.monotonic()
    child, peak = _run("rules", "query", str(doc), "-q", "q", "-s", "s")
    assert child.returncode == 1, child.stderr
    assert child.stderr.startswith("gaps: the question computed an integer of more than 4096 bits")
    assert "Traceback" not in child.stderr
    assert peak < 500 and time.monotonic() - started < 30


def test_incidents_with_a_squaring_rulebook_exits_with_a_message(tmp_path):
    from sim_replay.paper import RUN, paper_run
    from store import Store
    with Store(tmp_path / "gaps.db") as store:
        store.append(paper_run())
    text = (RULES_DIR / "validators.le").read_text(encoding="utf-8")
    text = text.replace("the templates are:\n", "the templates are:\n"
                        "*a number* squared *a count* times is *a result*.\n", 1)
    rules = SQUARING.split("the knowledge base k includes:\n", 1)[1].split("scenario s is:")[0]
    text = text.replace("the knowledge base validators includes:\n", "the knowledge base validators includes:\n"
                        + rules + "a vehicle must not enter the junction if\n"
                        "    2 squared 40 times is a result.\n\n", 1)
    hostile = tmp_path / "validators.le"
    hostile.write_text(text, encoding="utf-8")
    child, peak = _run("incidents", "--run", RUN, "--rules", str(hostile), "--db", str(tmp_path / "gaps.db"))
    assert child.returncode != 0, child.stdout
    assert "integer of more than 4096 bits" in child.stderr and "Traceback" not in child.stderr
    assert peak < 500
