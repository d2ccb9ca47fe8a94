"""`gaps export` writes the whole run the chain holds, or fails (issue 15, finding 3).

With one bit of the time index flipped, `gaps runs` and verify counted 79,576 events and the
export, which reads the run through that index, wrote 4,382 and exited 0. Here the bit flipped is
in the cell count of the index's only page, so a read through it finds fewer entries, the way
the damage found them.
"""
from __future__ import annotations

import json
import sqlite3
from pathlib import Path

import pytest

from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event

EVENTS = 40


@pytest.fixture
def db(tmp_path) -> Path:
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(i, run="r1") for i in range(EVENTS)])
    return path


def flip_cell_count_bit(path: Path, index: str) -> tuple[int, int]:
    """Flip one bit of the cell count of the index's root page (a leaf: the index is small), so
    that it holds fewer entries to a reader; returns (cells before, cells after)."""
    conn = sqlite3.connect(path)
    try:
        (root,) = conn.execute("SELECT rootpage FROM sqlite_master WHERE name = ?", (index,)).fetchone()
        (page_size,) = conn.execute("PRAGMA page_size").fetchone()
    finally:
        conn.close()
    with open(path, "r+b") as f:
        f.seek((root - 1) * page_size)
        header = bytearray(f.read(8))
        assert header[0] == 0x0A, "the index's root is not a leaf page"
        cells = int.from_bytes(header[3:5], "big")
        bit = 1 << (cells.bit_length() - 1)  # the highest set bit: the count drops most
        header[3:5] = (cells ^ bit).to_bytes(2, "big")
        f.seek((root - 1) * page_size)
        f.write(header)
    return cells, cells ^ bit


@pytest.mark.parametrize("name, order", [("r1.mcap", None), ("r1.jsonl", "time")])
def test_export_through_a_damaged_time_index_fails_and_writes_no_file(db, tmp_path, name, order):
    before, after = flip_cell_count_bit(db, "events_by_time")
    assert (before, after) == (EVENTS, EVENTS - 32)
    runs = json.loads(gaps("runs", "--json", db=db).stdout)
    assert runs[0]["events"] == EVENTS  # counted without that index, as in the finding
    target = tmp_path / name
    args = ("export", "--run", "r1", "-o", target) + (("--order", order) if order else ())
    out = gaps(*args, db=db)
    assert out.exit_code == 1, out.output
    assert (f"gaps: export of run r1 stopped: it read {after} events, but the run's chain holds {EVENTS} "
            "(its latest checkpoint") in out.stderr
    assert not target.exists() and list(tmp_path.glob(f".{name}.*")) == []
    assert gaps("verify", db=db).exit_code == 1  # and verify says the file is damaged


def test_export_in_chain_order_does_not_use_the_time_index(db, tmp_path):
    """The default order reads (run, chain_pos): the damaged time index does not shorten it."""
    flip_cell_count_bit(db, "events_by_time")
    out = gaps("export", "--run", "r1", "-o", tmp_path / "r1.jsonl", db=db)
    assert out.exit_code == 0, out.output
    assert len((tmp_path / "r1.jsonl").read_bytes().splitlines()) == EVENTS


def test_an_export_whose_text_is_not_the_chain_fails(db, tmp_path):
    """Chain order re-hashes what it writes: a store whose events no longer hash to the latest
    checkpoint's head (one event rewritten, hashes and all) is not exported as if it were sound."""
    from tests.helpers.store_testkit import tamper
    tamper(db, ("UPDATE events SET event = replace(event, 'red light', 'green light') "
                "WHERE run = 'r1' AND seq = 39", ()))
    out = gaps("export", "--run", "r1", "-o", tmp_path / "r1.jsonl", db=db)
    assert out.exit_code == 1
    assert "the 40 events read hash to head" in out.stderr and "latest checkpoint records" in out.stderr
    assert not (tmp_path / "r1.jsonl").exists()


def test_a_whole_export_still_succeeds(db, tmp_path):
    for name in ("r1.mcap", "r1.jsonl"):
        out = gaps("export", "--run", "r1", "-o", tmp_path / name, "--json", db=db)
        assert out.exit_code == 0, out.output
        assert json.loads(out.stdout)["events"] == EVENTS
