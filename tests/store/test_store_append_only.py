"""Triggers make every table of the log append-only, whoever connects to the file."""

import sqlite3

import pytest
from tests.helpers.store_testkit import event, rows

from store import Store

STATEMENTS = {
    "events": ("UPDATE events SET t = t + 1", "DELETE FROM events"),
    "quarantine": ("UPDATE quarantine SET reason = 'fine'", "DELETE FROM quarantine"),
    "checkpoints": ("UPDATE checkpoints SET count = 0", "DELETE FROM checkpoints"),
    "rulebooks": ("UPDATE rulebooks SET text = 'lenient'", "DELETE FROM rulebooks"),
}


@pytest.fixture
def filled(db_path):
    with Store(db_path) as store:
        store.append([event(0), event(1)])
        store.append_raw([(b"garbage", "test")])
        store.put_rulebook("highway code", "2024", "A vehicle must stop at a red light.\n")
    return db_path


@pytest.mark.parametrize("table", sorted(STATEMENTS))
@pytest.mark.parametrize("operation", [0, 1], ids=["update", "delete"])
def test_rows_cannot_be_changed_or_removed(filled, table, operation):
    before = rows(filled, f"SELECT * FROM {table}")
    assert before, "the fixture must put a row in every table"
    conn = sqlite3.connect(filled)
    with pytest.raises(sqlite3.IntegrityError, match=f"append-only: {table} rows cannot be"):
        conn.execute(STATEMENTS[table][operation])
    conn.close()
    assert rows(filled, f"SELECT * FROM {table}") == before


def test_refused_tampering_leaves_a_verifiable_store(filled):
    conn = sqlite3.connect(filled)
    with pytest.raises(sqlite3.IntegrityError):
        conn.execute("DELETE FROM events WHERE chain_pos = 1")
    conn.close()
    with Store(filled) as store:
        assert store.verify().ok
