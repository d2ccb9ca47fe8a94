"""The quarantine stays bounded and accountable (issue 15, finding 6: 10 MB of junk lines became 5.2
million rows, 570 MB, that nothing could remove): identical junk is one row with a count, a cap
refuses to keep more and counts what it refused, and a prune removes rows only with a record of them."""
from __future__ import annotations

import hashlib
import sqlite3
from pathlib import Path

import pytest

from store import QuarantineCap, Store, StoreError, parse_before
from store.ddl import MIGRATIONS, SCHEMA_VERSION
from store.migration import migrate_copy
from store.quarantine import OTHERS, SUMMARY_KEYS
from tests.helpers.store_testkit import event, rows

JUNK = b"\x00junk"


def test_identical_junk_is_one_row_with_a_count(tmp_path: Path) -> None:
    with Store(tmp_path / "q.db") as store:
        report = store.append_raw([(JUNK, "zenoh:gaps/x")] * 1_000)
        store.append_raw([(JUNK, "zenoh:gaps/x")] * 500)
        store.append_raw([(JUNK, "zenoh:gaps/y"), (b"other junk", "zenoh:gaps/x")])
        kept = store.quarantined()
        held = store.quarantine_summary()["held"]
    assert len(report.rejected) == 1_000 and report.quarantine_repeats == 999
    assert [(q["origin"], q["raw"], q["count"]) for q in kept] == [
        ("zenoh:gaps/x", JUNK, 1_500), ("zenoh:gaps/y", JUNK, 1), ("zenoh:gaps/x", b"other junk", 1)]
    first = kept[0]
    assert first["last_at"] > first["received_at"] and first["digest"] == hashlib.sha256(JUNK).hexdigest()
    assert held == {"rows": 3, "samples": 1_502, "bytes": 2 * len(JUNK) + len(b"other junk")}


def test_the_same_junk_down_a_file_is_one_row(tmp_path: Path) -> None:
    with Store(tmp_path / "q.db") as store:
        store.append_raw([(JUNK, f"run.jsonl:{line}") for line in range(1, 1_001)])
        store.append_raw([(JUNK, f"run.mcap:channel gaps/r/x/y:message {n} (log_time {n}, chunk at 9)")
                          for n in range(3)])
        store.append_raw([(JUNK, "other.jsonl:5")])
        kept = store.quarantined()
    assert [(q["origin"], q["last_origin"], q["count"]) for q in kept] == [
        ("run.jsonl:1", "run.jsonl:1000", 1_000),
        ("run.mcap:channel gaps/r/x/y:message 0 (log_time 0, chunk at 9)",
         "run.mcap:channel gaps/r/x/y:message 2 (log_time 2, chunk at 9)", 3),
        ("other.jsonl:5", "other.jsonl:5", 1)]


def test_past_the_cap_refusals_are_counted_not_kept(tmp_path: Path) -> None:
    path = tmp_path / "q.db"
    with Store(path, quarantine_cap=QuarantineCap(rows=5, bytes=10**6)) as store:
        report = store.append_raw([(b"junk %d" % i, f"key/{i % 2}") for i in range(12)])
        repeat = store.append_raw([(b"junk 0", "key/0")])  # a kept row still counts repeats
        assert (report.quarantine_full, len(report.rejected), repeat.quarantine_repeats) == (7, 12, 1)
        summary = store.quarantine_summary()
    assert summary["held"] == {"rows": 5, "samples": 6, "bytes": 5 * 6}
    over = {o["origin"]: (o["samples"], o["bytes"]) for o in summary["over_cap"]}
    assert over == {"key/1": (4, 4 * 6 + 1), "key/0": (3, 3 * 6 + 1)}
    with Store(path, quarantine_cap=QuarantineCap(rows=1000, bytes=40)) as store:  # the byte cap, on reopening
        assert store.append_raw([(b"x" * 11, "b")]).quarantine_full == 1
        assert store.append_raw([(b"x" * 10, "b")]).quarantine_full == 0


def test_a_prune_removes_rows_only_with_a_record_of_them(tmp_path: Path) -> None:
    path = tmp_path / "q.db"
    with Store(path) as store:
        store.append([event(0)])
        store.append_raw([(JUNK, "a")] * 3 + [(b"old", "b")])
        cutoff = store.quarantined()[-1]["last_at"] + 1
        store.append_raw([(b"new", "c")])
        with pytest.raises(sqlite3.IntegrityError, match="recorded prune"):
            store.connection.execute("DELETE FROM quarantine")
        pruned = store.prune_quarantine(cutoff)
        assert [q["raw"] for q in store.quarantined()] == [b"new"]
        assert store.prune_quarantine(cutoff) is None  # nothing older left
        summary = store.quarantine_summary()
        assert store.verify().ok
    assert (pruned.rows, pruned.samples, pruned.bytes) == (2, 4, len(JUNK) + 3)
    assert pruned.by_reason and sum(pruned.by_reason.values()) == 4 and pruned.by_origin == {"a": 3, "b": 1}
    expected = hashlib.sha256(f"1 {hashlib.sha256(JUNK).hexdigest()} 3\n2 {hashlib.sha256(b'old').hexdigest()} 1\n"
                              .encode()).hexdigest()
    assert pruned.digest == expected
    assert summary["prunes"] == [pruned.to_json()]
    raw = sqlite3.connect(path, isolation_level=None)
    with pytest.raises(sqlite3.IntegrityError, match="recorded prune"):  # the record does not open the door again
        raw.execute("DELETE FROM quarantine")
    with pytest.raises(sqlite3.IntegrityError, match="append-only"):
        raw.execute("DELETE FROM quarantine_prunes")
    raw.close()


def test_a_row_can_only_count_upwards(tmp_path: Path) -> None:
    with Store(tmp_path / "q.db") as store:
        store.append_raw([(JUNK, "a")] * 2)
        conn = store.connection
        for change in ("count = 1", "raw = x'00'", "reason = 'fine'", "last_at = 0", "last_origin = 'x'",
                       "source = 'x'"):
            with pytest.raises(sqlite3.IntegrityError, match="append-only"):
                conn.execute(f"UPDATE quarantine SET {change}")
        store.append_raw([(JUNK, "b")])
        store.append_raw([(b"x", "c")] * 2 + [(b"y", "d")])
        with Store.open_read_only(store.path) as reader:
            assert [q["count"] for q in reader.quarantined()] == [2, 1, 2, 1]


def test_a_prune_summary_names_the_largest_and_sums_the_rest(tmp_path: Path) -> None:
    with Store(tmp_path / "q.db") as store:
        store.append_raw([(b"junk", f"origin {i}") for i in range(SUMMARY_KEYS + 7)])
        pruned = store.prune_quarantine(parse_before("0s", 2**62))
    assert len(pruned.by_origin) == SUMMARY_KEYS + 1 and pruned.by_origin[OTHERS] == 7


def test_before_takes_a_time_or_an_age() -> None:
    now = 1_800_000_000 * 10**9
    assert parse_before("2026-11-26T08:00:00Z", now) == 1_795_680_000 * 10**9
    assert parse_before("7d", now) == now - 7 * 86_400 * 10**9
    for bad in ("yesterday", "2026-11-26T08:00:00"):
        with pytest.raises(ValueError, match="--before"):
            parse_before(bad, now)


def write_v6_file(path: Path) -> None:
    """A store as schema 6 wrote it, with three quarantined lines (two identical)."""
    conn = sqlite3.connect(path, isolation_level=None)
    conn.execute("CREATE TABLE schema_version (version INTEGER NOT NULL)")
    for step in range(1, 7):
        for statement in MIGRATIONS[step]:
            conn.execute(statement)
        conn.execute("INSERT INTO schema_version VALUES (?)", (step,))
    conn.executemany("INSERT INTO quarantine (received_at, origin, reason, raw) VALUES (?, ?, ?, ?)",
                     [(1, "f:1", "not JSON", JUNK), (2, "f:2", "not JSON", JUNK), (3, "f:1", "not JSON", JUNK)])
    conn.close()


def test_a_v6_store_migrates_and_its_old_rows_can_be_pruned(tmp_path: Path) -> None:
    old, new = tmp_path / "v6.db", tmp_path / "v7.db"
    write_v6_file(old)
    with pytest.raises(StoreError, match="gaps migrate"):
        Store.open_read_only(old)
    report = migrate_copy(old, new)
    assert (report.from_version, report.to_version) == (6, SCHEMA_VERSION)
    with Store(new) as store:
        assert [(q["count"], q["digest"], q["last_at"]) for q in store.quarantined()] == [(1, None, 1), (1, None, 2),
                                                                                           (1, None, 3)]
        store.append_raw([(JUNK, "f:1")] * 2)   # an old row has no digest: a new row, then counted there
        assert [q["count"] for q in store.quarantined()] == [1, 1, 1, 2]
        pruned = store.prune_quarantine(3)
        assert (pruned.rows, [q["received_at"] for q in store.quarantined()][0]) == (2, 3)
    assert rows(new, "SELECT count(*) FROM quarantine_prunes") == [(1,)]
