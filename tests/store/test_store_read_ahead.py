"""Reading ahead on a second connection gives the same events, stops when the reader stops, and
hands SQLite's errors to the reader."""
from __future__ import annotations

import sqlite3
import threading

import pytest

from store import Store
from store.read_ahead import read_ahead_rows
from test_store_kind_index import KINDS, mixed_events


def test_read_ahead_gives_the_events_of_a_plain_read(tmp_path):
    path = tmp_path / "a dir with spaces #1" / "s.db"
    path.parent.mkdir()
    with Store(path) as store:
        store.append(mixed_events(3000, 5))
        for kinds in (["monitor.observation"], KINDS, ["entity.state", "signal.state"]):
            assert list(store.events("r", kinds=kinds, read_ahead=True)) == list(store.events("r", kinds=kinds))


def test_the_thread_stops_when_the_reader_stops(tmp_path):
    with Store(tmp_path / "s.db") as store:
        store.append(mixed_events(5000, 6))
        before = threading.active_count()
        reader = store.events("r", kinds=KINDS, read_ahead=True)
        next(reader)
        reader.close()
        assert not [t for t in threading.enumerate() if t.name == "gaps-read-ahead"]
        assert threading.active_count() == before


def test_an_error_of_the_query_reaches_the_reader(tmp_path):
    with Store(tmp_path / "s.db") as store:
        store.append(mixed_events(10, 7))
    with pytest.raises(sqlite3.OperationalError):
        list(read_ahead_rows(str(tmp_path / "s.db"), "SELECT nope FROM events", ()))
