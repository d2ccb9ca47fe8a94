"""Rulebooks are stored by the sha256 of their text, so a run is re-judged with exactly its rules."""

import hashlib

from store_testkit import rows

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
