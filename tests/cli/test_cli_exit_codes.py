"""The exit codes README.md states, each as a user meets it (issue 39: a rulebook compile error
was 1 or 2 by command, `gaps sim` on a store a serve holds 2 where the README says 4)."""
from __future__ import annotations

import pytest

from ingest.serve_lock import ServeLock
from tests.helpers.cli import gaps

BAD_LE = ("the target language is: prolog.\nthe templates are:\n*a vehicle* is red.\n"
          "the knowledge base x includes:\na vehicle is blue if the vehicle is green.\n")


@pytest.fixture
def bad_le(tmp_path):
    path = tmp_path / "bad.le"
    path.write_text(BAD_LE)
    return path


def test_a_rulebook_that_does_not_compile_is_a_user_error_for_a_judging_command(db, bad_le):
    judged = gaps("incidents", "--rules", bad_le, db=db)
    assert judged.exit_code == 2 and "rulebook error: " in judged.stderr and "bad.le:5:1" in judged.stderr


def test_rules_check_reports_it_as_its_finding(bad_le):
    checked = gaps("rules", "check", bad_le)
    assert checked.exit_code == 1 and "bad.le:5:1" in checked.output


@pytest.mark.parametrize("command", [("sim", "--vehicles", "1", "--duration", "5s"),
                                     ("demo", "--paper", "--overwrite")])
def test_a_store_a_serve_is_writing_is_exit_4(tmp_path, monkeypatch, command):
    monkeypatch.chdir(tmp_path)
    db = tmp_path / "held.db"
    with ServeLock(db):
        refused = gaps(*command, db=db)
    assert refused.exit_code == 4, refused.output
    assert "already being written by a gaps serve" in refused.stderr


def test_no_store_is_a_user_error(tmp_path):
    assert gaps("runs", db=tmp_path / "none.db").exit_code == 2
