"""Tables never cut an id (issue 39): the id you need to copy is whole at any terminal width, the
other columns wrap; piped, every value is whole and nothing wraps."""
from __future__ import annotations

import pytest

from cli.tables import cells, rendered, table
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import event

LONG_RUN = "fleet-2026-12-07.site-a.camera-north.vehicle-173.replayed-from-mcap"[:64]


@pytest.fixture
def long_db(tmp_path):
    path = tmp_path / "gaps.db"
    with Store(path) as store:
        store.append([event(0, run=LONG_RUN), event(1, run=LONG_RUN)])
    return path


def test_piped_runs_keep_a_64_character_run_id_whole_at_80_columns(long_db):
    out = gaps("runs", db=long_db, columns=80).stdout
    assert LONG_RUN in out, out
    assert "…" not in out


@pytest.mark.parametrize("width", [40, 60, 80, 120])
def test_on_a_terminal_the_id_column_is_whole_and_the_others_wrap(width):
    drawn = table("run", "events", "sources", "start (UTC)", "end (UTC)", "duration", "chain")
    drawn.add_row(*cells(LONG_RUN, 48363, 5, "2024-11-21T08:00:00Z", "2024-11-21T08:03:00Z", "3m", "verified"))
    text = rendered(drawn, terminal_width=width)
    assert LONG_RUN in text, text
    assert "…" not in text


def test_on_a_wide_terminal_the_table_fits_it():
    drawn = table("run", "chain")
    drawn.add_row(*cells("r1", "verified"))
    assert max(len(line) for line in rendered(drawn, terminal_width=100).splitlines()) < 100


def test_piped_nothing_wraps():
    drawn = table("run", "reason")
    drawn.add_row(*cells("r1", "a long reason " * 12))
    lines = rendered(drawn, terminal_width=None).splitlines()
    assert len(lines) == 5 and ("a long reason " * 12).strip() in lines[3]
