"""Appending: the chain, duplicates, quarantine, checkpoints, transactions and the file format."""

import hashlib
import json
import sqlite3

import pytest

from store.ddl import SCHEMA_VERSION
from tests.helpers.store_testkit import event, rows

from store.ddl import SCHEMA_VERSION
from store import AppendReport, Rejection, Store, StoreError, canonical_json
from store.ddl import SCHEMA_VERSION


def checkpoints(db_path):
    return rows(db_path, "SELECT run, count, head FROM checkpoints ORDER BY id")


def test_append_stores_and_reads_back(store):
    evs = [event(seq) for seq in range(5)]
    report = store.append(evs)
    assert report == AppendReport(stored=5, duplicates=0, rejected=[])
    assert report.as_dict() == {"stored": 5, "duplicates": 0, "rejected": [], "quarantine_repeats": 0, "quarantine_full": 0}
    assert list(store.events("r1")) == evs
    assert store.count() == store.count("r1") == 5


def test_event_column_is_exactly_the_hashed_canonical_bytes(store, db_path):
    evs = [event(seq) for seq in range(4)]
    store.append(evs)
    prev = bytes(32)
    stored = rows(db_path, "SELECT chain_pos, run, src, seq, t, kind, event, hash FROM events ORDER BY chain_pos")
    for ev, (pos, run, src, seq, t, kind, text, digest) in zip(evs, stored, strict=True):
        assert text.encode("utf-8") == canonical_json(ev)
        assert (run, src, seq, t, kind) == (ev["run"], ev["src"], ev["seq"], ev["t"], ev["kind"])
        expected = hashlib.sha256(prev + text.encode("utf-8")).digest()
        assert digest == expected.hex()
        prev = expected
    assert [row[0] for row in stored] == [0, 1, 2, 3]


def test_raw_input_is_stored_in_canonical_form(store, db_path):
    ev = event(body={"facts": ["173 fährt"]})
    raw = json.dumps(ev, indent=4, ensure_ascii=True).encode()
    assert store.append_raw([(raw, "file.jsonl:1")]).stored == 1
    assert rows(db_path, "SELECT event FROM events") == [(canonical_json(ev).decode("utf-8"),)]


def test_each_run_has_its_own_chain(store, db_path):
    store.append([event(0, run="a"), event(0, run="b"), event(1, run="a"), event(1, run="b"), event(2, run="a")])
    positions = rows(db_path, "SELECT run, seq, chain_pos FROM events ORDER BY run, chain_pos")
    assert positions == [("a", 0, 0), ("a", 1, 1), ("a", 2, 2), ("b", 0, 0), ("b", 1, 1)]
    firsts = rows(db_path, "SELECT hash, event FROM events WHERE chain_pos = 0")
    for digest, text in firsts:
        assert digest == hashlib.sha256(bytes(32) + text.encode()).hexdigest()


def test_identical_duplicate_is_counted_and_ignored(store, db_path):
    store.append([event(0), event(1)])
    before = checkpoints(db_path)
    report = store.append([event(1), event(0)])
    assert report == AppendReport(stored=0, duplicates=2, rejected=[])
    assert store.count() == 2
    assert store.quarantined() == []
    assert checkpoints(db_path) == before  # nothing stored, no checkpoint


def test_duplicate_within_one_batch(store):
    report = store.append([event(0), event(0), event(1)])
    assert (report.stored, report.duplicates) == (2, 1)


def test_same_content_in_another_key_order_or_spacing_is_a_duplicate(store):
    ev = event(0)
    store.append([ev])
    reordered = dict(reversed(list(ev.items())))
    assert store.append([reordered]).duplicates == 1
    assert store.append_raw([(json.dumps(ev, indent=1).encode(), "k")]).duplicates == 1


def test_conflicting_duplicate_is_quarantined_with_its_bytes(store):
    original = event(0)
    store.append([original])
    forged = event(0, body={"facts": ["173 has green light"]})
    report = store.append([forged], origin="zenoh:gaps/r1/vehicle/173/vehicle.perception")
    assert report.stored == 0 and report.duplicates == 0
    assert report.rejected == [
        Rejection("zenoh:gaps/r1/vehicle/173/vehicle.perception", "conflicting duplicate of r1/vehicle/173/0")
    ]
    [held] = store.quarantined()
    assert held["raw"] == canonical_json(forged)
    assert held["reason"] == "conflicting duplicate of r1/vehicle/173/0"
    assert list(store.events("r1")) == [original]


def test_refusals_are_frozen_values_printed_as_origin_then_reason(store):
    """An append report's refusals cross rooms (ingest's stats, an import's and a fetch's report):
    frozen values whose JSON is the {origin, reason} the reports have always printed."""
    report = store.append_raw([(b"{not json", "file.jsonl:1")])
    [refused] = report.rejected
    assert isinstance(refused, Rejection)
    with pytest.raises(AttributeError):
        refused.reason = "changed"          # type: ignore[misc]
    assert list(refused.to_json()) == ["origin", "reason"]
    assert refused.to_json() == {"origin": "file.jsonl:1", "reason": refused.reason}
    assert report.as_dict()["rejected"] == [refused.to_json()]


def test_conflicting_duplicate_from_raw_keeps_the_raw_bytes(store):
    store.append([event(0)])
    raw = json.dumps(event(0, t=5)).encode()
    report = store.append_raw([(raw, "file.jsonl:7")])
    assert report.rejected == [Rejection("file.jsonl:7", "conflicting duplicate of r1/vehicle/173/0")]
    assert store.quarantined()[0]["raw"] == raw


def test_conflicting_duplicate_within_one_batch(store):
    report = store.append([event(0), event(0, t=1)])
    assert report.stored == 1
    assert [r.reason for r in report.rejected] == ["conflicting duplicate of r1/vehicle/173/0"]
    assert next(store.events("r1"))["t"] == event(0)["t"]


def test_old_seq_is_checked_against_the_stored_event(store):
    """Below a source's highest seq, an event may be new (a gap filled), a duplicate or a conflict."""
    store.append([event(0), event(2), event(3)])
    report = store.append([event(1), event(2), event(0, t=9)])
    assert (report.stored, report.duplicates, len(report.rejected)) == (1, 1, 1)
    assert [ev["seq"] for ev in store.events("r1")] == [0, 1, 2, 3]


def test_duplicates_are_found_after_reopening(db_path):
    with Store(db_path) as first:
        first.append([event(0), event(1)])
    with Store(db_path) as second:
        report = second.append([event(1), event(1, t=3), event(2)])
        assert (report.stored, report.duplicates, len(report.rejected)) == (1, 1, 1)


def test_invalid_input_is_quarantined_with_origin_reason_and_raw_bytes(store):
    items = [
        (b'{"v": 1, "run": "r1"', "file.jsonl:1"),
        (b"\xff\xfe", "file.jsonl:2"),
        (json.dumps(dict(event(0), seq=-1)).encode(), "file.jsonl:3"),
        (json.dumps(event(0)).encode(), "file.jsonl:4"),
    ]
    report = store.append_raw(items)
    assert report.stored == 1
    assert [r.origin for r in report.rejected] == ["file.jsonl:1", "file.jsonl:2", "file.jsonl:3"]
    held = store.quarantined()
    assert [(h["origin"], h["raw"]) for h in held] == [(origin, raw) for raw, origin in items[:3]]
    assert "malformed JSON at line 1" in held[0]["reason"]
    assert "not valid UTF-8" in held[1]["reason"]
    assert "seq must be between 0" in held[2]["reason"]
    assert [h["reason"] for h in held] == [r.reason for r in report.rejected]
    assert all(isinstance(h["received_at"], int) and h["received_at"] > 0 for h in held)


def test_invalid_dict_is_quarantined_as_canonical_json(store):
    bad = dict(event(0), kind="vehicle.dream")
    report = store.append([bad], origin="api")
    assert "kind 'vehicle.dream' is unknown" in report.rejected[0].reason
    assert store.quarantined()[0]["raw"] == canonical_json(bad)


def test_unserialisable_dict_is_quarantined_as_repr(store):
    bad = event(0, kind="entity.spawn", body={"type": "car", "tags": {"a"}})
    report = store.append([bad])
    assert "cannot be written as canonical JSON" in report.rejected[0].reason
    assert store.quarantined()[0]["raw"] == repr(bad).encode()


def test_nan_in_a_dict_is_quarantined(store):
    report = store.append([event(0, kind="entity.state", body={"x": float("nan"), "y": 0, "speed_mps": 0})])
    assert report.stored == 0 and "canonical JSON" in report.rejected[0].reason


def test_nothing_offered_is_dropped(store):
    offered = [event(0), event(0), event(0, t=1), {"v": 1}, "not an event", event(1)]
    report = store.append(offered)
    assert report.stored + report.duplicates + len(report.rejected) == len(offered)
    assert len(store.quarantined()) == len(report.rejected) == 3


def test_one_checkpoint_per_run_per_call(store, db_path):
    store.append([event(0, run="a"), event(0, run="b"), event(1, run="a")])
    store.append([event(2, run="a")])
    heads = dict(rows(db_path, "SELECT run, hash FROM events e WHERE chain_pos = "
                               "(SELECT max(chain_pos) FROM events WHERE run = e.run)"))
    recorded = checkpoints(db_path)
    assert [(run, count) for run, count, _ in recorded] == [("a", 2), ("b", 1), ("a", 3)]
    assert recorded[1][2] == heads["b"] and recorded[2][2] == heads["a"]


def test_a_call_that_only_rejects_writes_no_checkpoint(store, db_path):
    store.append_raw([(b"nonsense", "x")])
    assert checkpoints(db_path) == []


def test_chain_continues_after_reopening(db_path):
    with Store(db_path) as first:
        first.append([event(0), event(1)])
    with Store(db_path) as second:
        second.append([event(2)])
        assert second.verify().ok
    assert rows(db_path, "SELECT seq, chain_pos FROM events ORDER BY chain_pos") == [(0, 0), (1, 1), (2, 2)]


def test_two_stores_on_one_file_keep_one_chain(db_path):
    """Each store caches chain heads; a commit by the other must invalidate them."""
    with Store(db_path) as first, Store(db_path) as second:
        first.append([event(0)])
        second.append([event(1)])
        first.append([event(2)])
        second.append([event(2), event(3)])
        assert first.verify().ok
    assert rows(db_path, "SELECT seq FROM events ORDER BY chain_pos") == [(0,), (1,), (2,), (3,)]


def test_a_failing_batch_stores_nothing_and_the_store_stays_usable(store):
    store.append([event(0)])

    def broken():
        yield event(1)
        yield event(2)
        raise RuntimeError("producer died")

    with pytest.raises(RuntimeError):
        store.append(broken())
    assert store.count() == 1
    assert store.append([event(1), event(2)]).stored == 2
    assert store.verify().ok


def test_append_refuses_a_bare_event():
    with Store(":memory:") as mem:
        with pytest.raises(TypeError):
            mem.append(event(0))
        with pytest.raises(TypeError):
            mem.append_raw(b"{}")


def test_schema_version_and_pragmas(db_path):
    with Store(db_path) as durable:
        assert durable._conn.execute("PRAGMA journal_mode").fetchone() == ("wal",)
        assert durable._conn.execute("PRAGMA synchronous").fetchone() == (2,)  # FULL
    with Store(db_path, durable=False) as fast:
        assert fast._conn.execute("PRAGMA synchronous").fetchone() == (1,)  # NORMAL
    assert rows(db_path, "SELECT version FROM schema_version") == [(v,) for v in range(1, SCHEMA_VERSION + 1)]
    tables = {name for (name,) in rows(db_path, "SELECT name FROM sqlite_master WHERE type = 'table'")}
    assert {"events", "quarantine", "checkpoints", "rulebooks", "schema_version", "liveliness", "wire_misses"} <= tables


def test_a_newer_schema_is_refused(db_path):
    Store(db_path).close()
    conn = sqlite3.connect(db_path)
    conn.execute("INSERT INTO schema_version VALUES (99)")
    conn.commit()
    conn.close()
    with pytest.raises(StoreError, match="newer"):
        Store(db_path)


def test_store_works_across_threads_when_allowed(db_path):
    import threading

    with Store(db_path, check_same_thread=False) as shared:
        worker = threading.Thread(target=lambda: shared.append([event(0)]))
        worker.start()
        worker.join()
        assert shared.count() == 1


def test_append_candidates_keeps_the_callers_refusals_in_order(store):
    """The ingest judges some samples itself; its refusals are quarantined like the store's."""
    from store import Candidate, decode_event

    good = json.dumps(event(0)).encode()
    ev, canonical = decode_event(good)
    misrouted = json.dumps(event(1)).encode()
    report = store.append_candidates([
        Candidate("gaps/r1/vehicle/174/vehicle.perception", misrouted, reason="key does not match"),
        Candidate("gaps/r1/vehicle/173/vehicle.perception", good, ev, canonical),
        Candidate("gaps/r1/vehicle/173/vehicle.perception", good, ev, canonical),
    ])
    assert (report.stored, report.duplicates) == (1, 1)
    assert report.rejected == [Rejection("gaps/r1/vehicle/174/vehicle.perception", "key does not match")]
    assert store.quarantined()[0]["raw"] == misrouted
    assert list(store.events("r1")) == [event(0)]
    assert store.verify().ok


def test_quarantine_first_and_latest(store):
    store.append_raw([(f"bad {i}".encode(), f"o{i}") for i in range(5)])
    assert [q["origin"] for q in store.quarantined()] == ["o0", "o1", "o2", "o3", "o4"]
    assert [q["origin"] for q in store.quarantined(2)] == ["o0", "o1"]
    assert [q["origin"] for q in store.quarantined(2, latest=True)] == ["o3", "o4"]
    assert store.quarantine_count() == 5


def test_a_new_file_gets_16_kib_pages_and_an_existing_one_keeps_its_own(tmp_path):
    import sqlite3
    with Store(tmp_path / "new.db") as store:
        assert store.connection.execute("PRAGMA page_size").fetchone() == (16384,)
    old = tmp_path / "old.db"
    conn = sqlite3.connect(old)
    conn.execute("PRAGMA page_size=4096")
    conn.execute("CREATE TABLE x (y)")
    conn.close()
    with Store(old) as store:
        assert store.connection.execute("PRAGMA page_size").fetchone() == (4096,)
