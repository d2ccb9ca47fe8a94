"""A file written by the v1 schema opens, verifies and grows under v2; its old checkpoints, which
carry no Merkle root, are recognised as such and nothing later may lack one."""


import pytest

from store.ddl import SCHEMA_VERSION
from tests.helpers.store_testkit import event, rows, tamper, write_v1_file

from store.ddl import SCHEMA_VERSION
from store import Store, merkle
from store.ddl import SCHEMA_VERSION


@pytest.fixture
def v1_file(db_path):
    write_v1_file(db_path, [event(i) for i in range(7)], calls=[3, 4])
    return db_path


def test_a_v1_file_opens_at_the_current_version_and_verifies(v1_file):
    with Store(v1_file) as store:
        assert store.verify().ok
        assert [ev["seq"] for ev in store.events("r1")] == list(range(7))
        assert store.get_rulebook_by_name("hc")["text"] == "old rules"
        assert store.rulebooks()[0]["stored_at"] is None
    assert rows(v1_file, "SELECT version FROM schema_version") == [(v,) for v in range(1, SCHEMA_VERSION + 1)]
    assert rows(v1_file, "SELECT name FROM sqlite_master WHERE name = 'events_by_kind'") == [("events_by_kind",)]
    assert rows(v1_file, "SELECT through_id FROM legacy_checkpoints") == [(2,)]
    assert rows(v1_file, "SELECT merkle_root FROM checkpoints") == [(None,), (None,)]


def test_a_v1_file_grows_with_v2_checkpoints(v1_file):
    with Store(v1_file, checkpoint_every=4) as store:
        assert store.append([event(i) for i in range(7, 10)]).stored == 3
        assert store.verify().ok
    hashes = [bytes.fromhex(h) for (h,) in rows(v1_file, "SELECT hash FROM events ORDER BY chain_pos")]
    new = rows(v1_file, "SELECT count, merkle_root, prev_count FROM checkpoints WHERE id > 2 ORDER BY id")
    assert new == [(8, merkle.merkle_root(hashes[:8]).hex(), 7), (10, merkle.merkle_root(hashes).hex(), 8)]


def test_migrating_twice_changes_nothing(v1_file):
    Store(v1_file).close()
    before = rows(v1_file, "SELECT * FROM sqlite_master ORDER BY name")
    Store(v1_file).close()
    assert rows(v1_file, "SELECT * FROM sqlite_master ORDER BY name") == before
    assert rows(v1_file, "SELECT version FROM schema_version") == [(v,) for v in range(1, SCHEMA_VERSION + 1)]
    assert rows(v1_file, "SELECT name FROM sqlite_master WHERE name = 'events_by_kind'") == [("events_by_kind",)]


def test_a_v2_checkpoint_without_its_root_fails_verify(v1_file):
    with Store(v1_file) as store:
        store.append([event(7)])
    tamper(v1_file, ("UPDATE checkpoints SET merkle_root = NULL WHERE id = 3", ()))
    with Store(v1_file) as store:
        report = store.verify()
    assert not report.ok
    assert report.problem.chain_pos == 7
    assert "lacks the Merkle root" in report.problem.what


def test_a_fresh_file_holds_every_checkpoint_to_v2(db_path):
    with Store(db_path) as store:
        store.append([event(0)])
    assert rows(db_path, "SELECT through_id FROM legacy_checkpoints") == [(0,)]
    tamper(db_path, ("UPDATE checkpoints SET prev_count = NULL", ()))
    with Store(db_path) as store:
        assert "lacks the Merkle root, frontier or previous count" in store.verify().problem.what


def test_a_signal_just_after_the_schemas_commit_is_what_reaches_the_caller(tmp_path):
    """SIGTERM and Ctrl-C raise wherever the code is (cli/main.py). One raised just after
    migrate's COMMIT left no transaction to roll back, and the ROLLBACK's own error ("cannot
    rollback - no transaction is active") replaced it: `gaps regress` stopped by SIGTERM while
    creating its temporary store said the file "may be damaged or altered" and exited 1, not 143
    (tests/cli/test_cli_sigterm.py, now and then)."""
    import sqlite3

    from store.ddl import SCHEMA_VERSION, current_version, migrate

    class SignalAfterCommit(sqlite3.Connection):
        def execute(self, sql, *args):
            cursor = super().execute(sql, *args)
            if sql == "COMMIT":
                raise KeyboardInterrupt
            return cursor

    conn = sqlite3.connect(tmp_path / "s.db", isolation_level=None, factory=SignalAfterCommit)
    with pytest.raises(KeyboardInterrupt):
        migrate(conn)
    assert not conn.in_transaction and current_version(conn) == SCHEMA_VERSION
