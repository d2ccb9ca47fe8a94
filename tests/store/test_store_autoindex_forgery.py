"""Issue 15: the automatic indexes (sqlite_autoindex_*, made by SQLite for the UNIQUE and PRIMARY
KEY constraints) decide which row a read by (run, chain_pos), by (run, src, seq) or by a rulebook's
address finds, and hold no text the chain covers. An entry forged in their b-tree pages
(tests/helpers/index_pages.py: the split view cannot hide an index that has no definition) changes
what such a read answers; `gaps verify` runs SQLite's integrity check, which names the index."""
from __future__ import annotations

import json
import shutil
from pathlib import Path

import pytest
from tests.helpers.index_pages import cells, forge_entry
from tests.helpers.store_testkit import event

from store import Store
from tests.helpers.cli import gaps

RULES = "rules text"


@pytest.fixture(scope="module")
def store_file(tmp_path_factory) -> tuple[Path, str]:
    db = tmp_path_factory.mktemp("autoindex") / "s.db"
    with Store(db) as store:
        store.append([event(i) for i in range(400)])  # more than one page: the walk goes through interior pages
        address = store.put_rulebook("hc", "1", RULES)
    return db, address


def forged_copy(store_file, tmp_path, index: str, key: tuple, position: int) -> Path:
    """A copy of the store whose `index` entry with these leading values has value `position` changed."""
    copy = tmp_path / "forged.db"
    shutil.copy(store_file[0], copy)
    [entry] = [c for c in cells(copy, index) if c.values[:len(key)] == key]
    assert forge_entry(copy, index, entry.values[-1], position)
    return copy


def integrity_messages(db: Path) -> tuple[str, ...]:
    with Store.open_read_only(db) as store:
        report = store.verify()
    assert not report.ok
    return report.integrity.messages


def test_the_walk_finds_every_entry_of_a_multi_page_index(store_file):
    db, address = store_file
    entries = cells(db, "sqlite_autoindex_events_2")
    assert [c.values[:3] for c in entries] == [("r1", "vehicle/173", seq) for seq in range(400)]
    assert [c.values for c in cells(db, "sqlite_autoindex_rulebooks_1")] == [(address, 1)]


def test_a_forged_seq_entry_hides_an_event_from_a_read_and_fails_verify(store_file, tmp_path):
    copy = forged_copy(store_file, tmp_path, "sqlite_autoindex_events_2", ("r1", "vehicle/173", 200), 2)
    with Store.open_read_only(copy) as store:
        assert store.t_of("r1", "vehicle/173", 200) is None  # the attack is real: the event is not found
        assert store.t_of("r1", "vehicle/173", 201) is not None
    assert any("sqlite_autoindex_events_2" in m for m in integrity_messages(copy))


def test_a_forged_rulebook_address_entry_hides_the_rulebook_and_fails_verify(store_file, tmp_path):
    copy = forged_copy(store_file, tmp_path, "sqlite_autoindex_rulebooks_1", (store_file[1],), 0)
    with Store.open_read_only(copy) as store:
        assert store.get_rulebook(store_file[1]) is None  # a run naming these rules would find none
    assert any("sqlite_autoindex_rulebooks_1" in m for m in integrity_messages(copy))


@pytest.mark.parametrize("index, key, position", [
    ("sqlite_autoindex_events_1", ("r1", 7), 0),     # the run's name in the (run, chain_pos) entry
    ("sqlite_autoindex_events_1", ("r1", 399), 1),   # the chain position of the last event
    ("sqlite_autoindex_events_2", ("r1", "vehicle/173", 0), 1),  # the source
])
def test_every_forged_automatic_index_entry_fails_gaps_verify_naming_the_index(store_file, tmp_path, index, key,
                                                                              position):
    """Verify walks a run's chain through the (run, chain_pos) index, so a forged entry there may be
    named first as a chain problem; the integrity check names the index in any case."""
    copy = forged_copy(store_file, tmp_path, index, key, position)
    result = gaps("verify", "--no-snapshots", "--json", db=copy)
    assert result.exit_code == 1
    report = json.loads(result.stdout)
    assert not report["ok"] and not report["integrity"]["ok"]
    assert any(index in message for message in report["integrity"]["messages"])
