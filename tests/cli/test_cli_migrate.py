"""`gaps migrate SRC DST`, and what the read commands say of a store they cannot read as it is."""

import hashlib
import json

from tests.helpers.store_testkit import event
from tests.helpers.store_testkit import write_v1_file
from tests.helpers.cli import gaps


def test_verify_of_an_old_store_says_to_migrate_and_changes_nothing(tmp_path):
    old = tmp_path / "old.db"
    write_v1_file(old, [event(i) for i in range(7)], calls=[7])
    before = hashlib.sha256(old.read_bytes()).hexdigest()
    result = gaps("verify", "--db", old)
    assert result.exit_code == 2
    assert "schema version 1 is older" in result.output and "gaps migrate SRC DST" in result.output
    assert "verified" not in result.output
    assert hashlib.sha256(old.read_bytes()).hexdigest() == before


def test_verify_of_an_empty_file_says_it_is_not_an_event_store(tmp_path):
    empty = tmp_path / "empty.db"
    empty.touch()
    result = gaps("verify", "--db", empty)
    assert result.exit_code == 2 and "not an event store" in result.output
    assert empty.stat().st_size == 0


def test_migrate_writes_a_copy_that_verifies(tmp_path):
    old, new = tmp_path / "old.db", tmp_path / "new.db"
    write_v1_file(old, [event(i) for i in range(7)], calls=[3, 4])
    result = gaps("migrate", old, new)
    assert result.exit_code == 0, result.output
    assert "schema version 1" in result.output and "7 events" in result.output
    assert gaps("verify", "--db", new).exit_code == 0
    assert json.loads(gaps("migrate", old, tmp_path / "other.db", "--json").output)["from_version"] == 1


def test_migrate_refuses_an_existing_destination(tmp_path):
    old, new = tmp_path / "old.db", tmp_path / "new.db"
    write_v1_file(old, [event(0)], calls=[1])
    new.write_bytes(b"keep me")
    result = gaps("migrate", old, new)
    assert result.exit_code == 2 and "already exists" in result.output
    assert new.read_bytes() == b"keep me"
