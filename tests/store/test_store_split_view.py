"""An index that disagrees with its table (issue 15, finding 1): the split view.

The chains cover the events table. The reasoner reads the sparse kinds through the covering index
`events_by_kind`, which holds each event's text a second time, and every read finds its rows
through an index. Whoever holds the file can rewrite an index entry and leave the row as it was
(tests/helpers/split_view.py): before this, every read believed the forgery and `gaps verify`
passed. Now verify runs SQLite's integrity check and fails, and a read through the covering
index checks each entry against its row and stops (IndexDisagrees) rather than use a forged one.
"""
from __future__ import annotations

import hashlib
import json
import sqlite3

import pytest

from store import Store, canonical_json, state_of
from store.errors import EvidenceError, IndexDisagrees
from tests.helpers.split_view import rowid_of, split
from tests.helpers.store_testkit import T0, event, rows

LAWFUL = "a vehicle may proceed if the light is green.\n"
FORGED = "a vehicle may proceed.\n"


def rulebook(text: str) -> dict:
    return {"name": "highway-code", "sha256": hashlib.sha256(text.encode()).hexdigest(), "text": text}


@pytest.fixture
def recorded(db_path):
    """A run with its rulebook in run.start, a spawn and two observations of vehicle 173."""
    with Store(db_path) as store:
        store.append([
            event(0, kind="run.start", body={"seed": 7, "rulebooks": [rulebook(LAWFUL)]}),
            event(0, kind="entity.spawn", src="vehicle/173"),
            event(1, kind="entity.state", src="vehicle/173"),
            event(0, kind="monitor.observation", body={"vehicle": "173", "facts": ["173 has red light"]}),
            event(1, kind="monitor.observation", body={"vehicle": "173", "facts": ["173 has red light"]}),
        ])
    return db_path


def forged_start(path) -> str:
    """The run.start text with the rulebook swapped, its sha256 made to match."""
    [(text,)] = rows(path, "SELECT event FROM events WHERE kind = 'run.start'")
    start = json.loads(text)
    start["body"]["rulebooks"] = [rulebook(FORGED)]
    return canonical_json(start).decode()


def forge_rulebook_in_index(path) -> None:
    split(path, "events_by_kind", rowid_of(path, "r1", "sim/world", 0), event=forged_start(path))


def hide_observation_from_index(path) -> None:
    """The observation's kind index entry removed: with the row's kind made dense for a moment,
    the partial index drops it, and the row is then put back."""
    split(path, "events_by_kind", rowid_of(path, "r1", "monitor/m1", 1), kind="entity.state")


def test_the_split_view_is_real_and_quick_check_misses_it(recorded):
    """The attack as found: the table (and so the chain) unchanged, a read by kind shows the forgery,
    and SQLite's quick_check, which does not compare indexes with tables, says ok."""
    forge_rulebook_in_index(recorded)
    conn = sqlite3.connect(recorded)
    try:
        [(table_text,)] = conn.execute("SELECT event FROM events NOT INDEXED WHERE kind = 'run.start'").fetchall()
        [(index_text,)] = conn.execute("SELECT event FROM events INDEXED BY events_by_kind WHERE run = 'r1' AND "
                                       "kind = 'run.start' AND kind <> 'entity.state' AND kind <> "
                                       "'vehicle.perception' AND kind <> 'vehicle.trace'").fetchall()
        def rules(text: str) -> str:
            return json.loads(text)["body"]["rulebooks"][0]["text"]
        assert rules(index_text) == FORGED and rules(table_text) == LAWFUL
        assert conn.execute("PRAGMA quick_check").fetchall() == [("ok",)]
        assert conn.execute("PRAGMA integrity_check").fetchall() != [("ok",)]
    finally:
        conn.close()


@pytest.mark.parametrize("attack", [forge_rulebook_in_index, hide_observation_from_index])
def test_verify_fails_on_an_index_that_disagrees_with_its_table(recorded, attack):
    attack(recorded)
    with Store.open_read_only(recorded) as store:
        report = store.verify()
        one_run = store.verify("r1")
    assert [r.ok for r in report.runs] == [True]  # the chain itself matches: the table is intact
    assert not report.ok and not one_run.ok
    assert report.integrity.ok is False
    assert "events_by_kind" in report.integrity.messages[0]
    what = report.problem.what
    assert what.startswith("the store file fails SQLite's integrity check: ") and "events_by_kind" in what
    assert report.problem.run is None


def test_a_run_of_a_damaged_file_is_never_recorded_as_verified(recorded):
    """Explanations cite `verified(run)`; a file failing its integrity check must not be cited as sound."""
    forge_rulebook_in_index(recorded)
    with Store.open_read_only(recorded) as store:
        assert not store.verify("r1").ok
        assert not store.verified("r1").ok


def test_a_forged_time_index_entry_fails_verify(recorded):
    """The time index decides which rows a read by time finds: an entry moved an hour on."""
    split(recorded, "events_by_time", rowid_of(recorded, "r1", "monitor/m1", 0), t=T0 + 3_600_000_000_000)
    with Store.open_read_only(recorded) as store:
        report = store.verify()
    assert not report.ok and "events_by_time" in report.problem.what


def test_reading_a_forged_index_entry_stops_with_a_clear_error(recorded):
    forge_rulebook_in_index(recorded)
    with Store.open_read_only(recorded) as store:
        with pytest.raises(IndexDisagrees) as raised:
            list(store.events("r1", kinds=["run.start"]))
        assert isinstance(raised.value, EvidenceError) and raised.value.exit_code == 1
        assert str(raised.value).startswith("event run=r1 src=sim/world seq=0: the store's index by kind")
        # what the reasoner reads through the same index is checked the same way
        with pytest.raises(IndexDisagrees):
            list(store.events("r1", kinds=["run.start", "monitor.observation"]))


def test_a_forged_observation_is_not_believed(recorded):
    rowid = rowid_of(recorded, "r1", "monitor/m1", 1)
    [(text,)] = rows(recorded, "SELECT event FROM events WHERE rowid = ?", (rowid,))
    split(recorded, "events_by_kind", rowid, event=text.replace("red light", "green light"))
    with Store.open_read_only(recorded) as store:
        for read in (lambda: list(store.events("r1", kinds=["monitor.observation"])),
                     lambda: store.observations_of("r1", "173"),
                     lambda: state_of(store, "r1", T0 + 10**9, observed=[("monitor/m1", "173")])):
            with pytest.raises(IndexDisagrees, match="src=monitor/m1 seq=1"):
                read()


def test_a_forged_spawn_time_is_not_believed(recorded):
    """state_of finds an entity's last spawn in the kind index: an entry whose t was moved."""
    split(recorded, "events_by_kind", rowid_of(recorded, "r1", "vehicle/173", 0), t=T0 - 5)
    with Store.open_read_only(recorded) as store:
        with pytest.raises(IndexDisagrees, match="src=vehicle/173 seq=0"):
            state_of(store, "r1", T0 + 10**9, entities=["vehicle/173"])


def test_untouched_reads_pass_the_guard(recorded):
    with Store.open_read_only(recorded) as store:
        assert store.verify().ok
        assert [e["seq"] for e in store.events("r1", kinds=["monitor.observation"])] == [0, 1]
        assert len(store.observations_of("r1", "173")) == 2
        state = state_of(store, "r1", T0 + 10**9, entities=["vehicle/173"], observed=[("monitor/m1", "173")])
        assert "vehicle/173" in state.entities and state.monitors["monitor/m1"]["observations"]["173"]["seq"] == 1
