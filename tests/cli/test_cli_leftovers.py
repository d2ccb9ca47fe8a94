"""No lock or output file left or overwritten without saying so (issue 39: every demo or sim left
a `*.serve.lock` with a dead pid; a second demo overwrote gaps-report.html silently)."""
from __future__ import annotations

import os

import pytest

from ingest.serve_lock import ServeLock, lock_path
from ingest.errors import StoreInUse
from tests.helpers.cli import gaps


def test_a_released_serve_lock_leaves_no_file(tmp_path):
    db = tmp_path / "gaps.db"
    with ServeLock(db):
        assert lock_path(db).is_file()
    assert not lock_path(db).exists()


def test_a_serve_that_fails_while_holding_the_lock_leaves_no_file(tmp_path):
    db = tmp_path / "gaps.db"
    with pytest.raises(RuntimeError), ServeLock(db):
        raise RuntimeError("the ingest could not start")
    assert not lock_path(db).exists()


def test_a_refused_second_holder_leaves_the_first_ones_file(tmp_path):
    db = tmp_path / "gaps.db"
    with ServeLock(db):
        with pytest.raises(StoreInUse):
            ServeLock(db).acquire()
        assert lock_path(db).is_file()      # still the holder's, with its pid
        with pytest.raises(StoreInUse):
            ServeLock(db).acquire()


def test_a_holder_that_opened_the_file_before_it_was_removed_does_not_share_the_store(tmp_path):
    """The file is removed on release: a second process that had opened it just before would lock
    a file nobody else can find, while a third makes a new one. The lock taken must be on the file
    at the path, or it is taken again."""
    db = tmp_path / "gaps.db"
    first = ServeLock(db).acquire()
    late = ServeLock(db)
    opened = [os.open(lock_path(db), os.O_RDWR)]    # the late one's open, before the first releases
    first.release()
    third = ServeLock(db).acquire()                 # makes the file anew and holds it
    real_open = late._open
    late._open = lambda: opened.pop() if opened else real_open()
    try:
        with pytest.raises(StoreInUse):
            late.acquire()
    finally:
        third.release()


def test_a_second_demo_writes_beside_the_report_unless_told_to_replace_it(tmp_path, monkeypatch):
    """Issue 39: "a second demo writes beside the first or asks"; `make demo` twice must work."""
    monkeypatch.chdir(tmp_path)
    db = tmp_path / "gaps.db"
    first = gaps("demo", "--paper", db=db)
    assert first.exit_code == 0, first.output
    report = tmp_path / "gaps-report.html"
    before = report.read_bytes()
    assert not lock_path(db).exists()

    again = gaps("demo", "--paper", db=db)      # not a terminal: nobody to ask
    assert again.exit_code == 0, again.output
    assert report.read_bytes() == before and (tmp_path / "gaps-report-2.html").exists()
    assert "gaps-report-2.html (beside the earlier gaps-report.html)" in again.output

    replaced = gaps("demo", "--paper", "--overwrite", db=db)
    assert replaced.exit_code == 0, replaced.output
    assert "replaced the earlier" in replaced.stdout
    assert not lock_path(db).exists()
