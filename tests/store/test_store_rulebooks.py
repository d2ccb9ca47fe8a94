"""Rulebooks are stored by the sha256 of their text, so a run is re-judged with exactly its rules."""

import hashlib

import pytest
from tests.helpers.store_testkit import rows, tamper

from store import Store

TEXT = "the templates are:\n*a vehicle* must stop at *a light*.\n"


def test_address_is_the_sha256_of_the_utf8_text(store):
    address = store.put_rulebook("highway code", "2024.1", TEXT)
    assert address == hashlib.sha256(TEXT.encode("utf-8")).hexdigest()
    assert store.get_rulebook(address) == {"sha256": address, "name": "highway code", "version": "2024.1", "text": TEXT}


def test_storing_the_same_text_again_changes_nothing(store, db_path):
    first = store.put_rulebook("highway code", "1", TEXT)
    again = store.put_rulebook("renamed", "2", TEXT)
    assert again == first
    assert store.get_rulebook(first)["name"] == "highway code"
    assert rows(db_path, "SELECT count(*) FROM rulebooks") == [(1,)]


def test_different_texts_get_different_addresses(store):
    a = store.put_rulebook("hc", "1", TEXT)
    b = store.put_rulebook("hc", "1", TEXT + " ")
    assert a != b
    assert store.get_rulebook(b)["text"] == TEXT + " "


def test_non_ascii_text(store):
    text = "Fahrzeug – muss halten, wenn Ampel rot ist.\n"
    address = store.put_rulebook("StVO", "§37", text)
    assert address == hashlib.sha256(text.encode("utf-8")).hexdigest()
    assert store.get_rulebook(address)["text"] == text


def test_unknown_address(store):
    assert store.get_rulebook("0" * 64) is None


def test_rulebooks_persist(db_path):
    with Store(db_path) as first:
        address = first.put_rulebook("hc", "1", TEXT)
    with Store(db_path) as second:
        assert second.get_rulebook(address)["text"] == TEXT
        assert second.verify().ok


# --- lookup by name and version, listing ----------------------------------------------------------

def test_lookup_by_name_and_version(store):
    first = store.put_rulebook("highway code", "2024.9", TEXT)
    second = store.put_rulebook("highway code", "2024.10", TEXT + "more.\n")
    store.put_rulebook("stvo", "1", "other rules\n")
    assert store.get_rulebook_by_name("highway code", "2024.9")["sha256"] == first
    assert store.get_rulebook_by_name("highway code")["sha256"] == second  # 10 > 9 as numbers
    assert store.get_rulebook_by_name("highway code", "2025") is None
    assert store.get_rulebook_by_name("nothing") is None


def test_newest_among_equal_versions_is_the_last_stored(store):
    store.put_rulebook("hc", "1", "a\n")
    later = store.put_rulebook("hc", "1", "b\n")
    assert store.get_rulebook_by_name("hc")["sha256"] == later
    assert store.get_rulebook_by_name("hc", "1")["sha256"] == later


def test_version_order():
    from store.rulebooks import version_key

    ordered = ["", "1", "1.2", "1.10", "2", "2a", "2b", "10", "v1", "²"]
    assert sorted(ordered, key=version_key) == ordered


def test_listing(store):
    store.put_rulebook("zebra", "1", "z\n")
    store.put_rulebook("hc", "2", "two\n")
    store.put_rulebook("hc", "10", "ten\n")
    listed = store.rulebooks()
    assert [(r["name"], r["version"]) for r in listed] == [("hc", "2"), ("hc", "10"), ("zebra", "1")]
    assert listed[0]["bytes"] == 4 and "text" not in listed[0]
    assert all(isinstance(r["stored_at"], int) and r["stored_at"] > 0 for r in listed)
    assert listed[0]["sha256"] == hashlib.sha256(b"two\n").hexdigest()


def test_lookup_by_name_refuses_altered_text(db_path):
    with Store(db_path) as store:
        store.put_rulebook("hc", "1", TEXT)
    tamper(db_path, ("UPDATE rulebooks SET text = 'lenient'", ()))
    with Store(db_path) as store:
        with pytest.raises(ValueError, match="does not match its text"):
            store.get_rulebook_by_name("hc")
