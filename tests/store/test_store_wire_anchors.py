"""Issue 15: the wire tables' chains (liveliness, wire_misses) anchored by the signed tree heads.

The liveliness changes and wire misses are hash chains with checkpoints in `wire_checkpoints`
(store/liveliness.py), so `gaps verify` notices an edited row; but rows cut off the end together
with their wire checkpoints, a table rewritten with its hashes recomputed, or a table emptied,
leave a file that agrees with itself. Since schema v8 every checkpoint records where the wire
chains stood when it was written (rows and head hash per table), and the ingest signs that with
the run's tree head: plain verify checks those records against the tables, and once someone drops
or changes them too, a witness (`--against`) and the checkpoint key (`--key`) still catch it.
"""
from __future__ import annotations

import json
import shutil
import sqlite3
from pathlib import Path

import pytest
from tests.helpers.store_testkit import event, old_schema, rows, tamper

from store import Store
from store.keys import CheckpointKey, WitnessFile, read_heads
from store.wire import LivelinessChange, WireMiss
from store.chain import GENESIS
from store.wire.liveliness import row_hash
from store.keys.tree_heads import TreeHead

CHANGES = [LivelinessChange("r1", "vehicle/1", True, 10, None), LivelinessChange("r1", "vehicle/2", True, 11, None),
           LivelinessChange("r1", "vehicle/1", False, 20, 4), LivelinessChange("r1", "vehicle/2", False, 30, 9)]
MISSES = [WireMiss("r1", "vehicle/2", "entity.state", 3, 25, 7)]


@pytest.fixture
def key(tmp_path):
    return CheckpointKey.create(tmp_path / "checkpoint.key")


def wired_store(db: Path, key: CheckpointKey, witness_path: Path) -> list[TreeHead]:
    """Events, then what the ingest noticed on the wire, then more events: the checkpoints of the
    later append (signed, witnessed) cover the wire rows written before it."""
    witness = WitnessFile(witness_path)
    with Store(db, checkpoint_key=key, checkpoint_every=8) as store:
        store.add_checkpoint_hook(witness.append)
        store.append([event(i) for i in range(10)])
        store.record_wire(CHANGES[:2])
        store.append([event(i) for i in range(10, 14)])
        store.record_wire(CHANGES[2:], MISSES)
        store.append([event(i) for i in range(14, 20)])
    witness.close()
    return read_heads(witness_path)


HIDE = ("UPDATE checkpoints SET wire = NULL", ())  # the checkpoints' record of the wire ends, dropped


def plain_verify_problem(db: Path) -> str | None:
    with Store.open_read_only(db) as store:
        report = store.verify()
    return None if report.ok else report.problem.what


def anchored(db: Path, heads, public):
    assert plain_verify_problem(db) is None  # each attack is real: the file alone agrees with itself
    with Store.open_read_only(db) as store:
        return store.check_anchors(heads, public)


def test_cutting_back_liveliness_with_its_wire_checkpoints_fails_against_and_key(tmp_path, key):
    db = tmp_path / "s.db"
    heads = wired_store(db, key, tmp_path / "w.jsonl")
    # the attack: the two disappearances ("stopped publishing") cut off, with the checkpoint over them
    tamper(db, ("DELETE FROM liveliness WHERE id > 2", ()),
           ("DELETE FROM wire_checkpoints WHERE tbl = 'liveliness' AND through_id > 2", ()))
    with Store.open_read_only(db) as store:
        assert [c.alive for c in store.liveliness_changes("r1")] == [True, True]  # both look alive now
        outcomes, keyed = store.check_anchors(heads, key.public)
    # the checkpoints the events' appends wrote since record the longer chain: plain verify sees it
    assert "the checkpoint of 16 events of run r1 records the wire tables' ends, and liveliness holds no row 4" \
        in plain_verify_problem(db)
    assert not keyed.ok and "liveliness holds no row 4" in keyed.problem.what
    tamper(db, HIDE)  # unless those records go too; then only what is kept outside the file tells
    for seen in (outcomes, anchored(db, heads, key.public)[0]):
        failed = [o for o in seen if not o.ok]
        assert failed and {o.outcome for o in failed} == {"wire cut back"}
        assert all("liveliness" in o.what and "row 4" in o.what for o in failed)
        assert [o.size for o in failed] == [16, 20]  # the heads written after the disappearances
    _, keyed = anchored(db, heads, key.public)
    assert not keyed.ok and "does not match the head" in keyed.problem.what


def test_a_wire_table_rewritten_with_its_hashes_recomputed_fails(tmp_path, key):
    db = tmp_path / "s.db"
    heads = wired_store(db, key, tmp_path / "w.jsonl")
    # vehicle/1 said to disappear later than it did: the row and every hash after it recomputed
    stored = rows(db, "SELECT id, run, src, alive, at, last_seq FROM liveliness ORDER BY id")
    prev, statements = GENESIS, []
    for id_, *values in stored:
        values[3] = 5_000 if id_ == 3 else values[3]
        prev = row_hash("liveliness", prev, id_, tuple(values))
        statements.append(("UPDATE liveliness SET at = ?, hash = ? WHERE id = ?", (values[3], prev.hex(), id_)))
    statements.append(("UPDATE wire_checkpoints SET head = ? WHERE tbl = 'liveliness' AND through_id = 4",
                       (prev.hex(),)))
    tamper(db, *statements)
    assert "(wire rewritten)" in plain_verify_problem(db)
    with Store.open_read_only(db) as store:
        _, keyed = store.check_anchors((), key.public)
    assert not keyed.ok and "the table was rewritten" in keyed.problem.what
    tamper(db, HIDE)
    outcomes, keyed = anchored(db, heads, key.public)
    assert {o.outcome for o in outcomes if not o.ok} == {"wire rewritten"}
    assert not keyed.ok


def test_an_emptied_wire_table_fails(tmp_path, key):
    db = tmp_path / "s.db"
    heads = wired_store(db, key, tmp_path / "w.jsonl")
    tamper(db, ("DELETE FROM wire_misses", ()), ("DELETE FROM wire_checkpoints WHERE tbl = 'wire_misses'", ()), HIDE)
    outcomes, keyed = anchored(db, heads, key.public)
    failed = [o for o in outcomes if not o.ok]
    assert [o.size for o in failed] == [16, 20] and {o.outcome for o in failed} == {"wire cut back"}
    assert "wire_misses" in failed[0].what and "holds no row 1" in failed[0].what
    assert not keyed.ok


def test_an_untouched_wired_store_matches_and_later_wire_rows_are_an_extension(tmp_path, key):
    db = tmp_path / "s.db"
    heads = wired_store(db, key, tmp_path / "w.jsonl")
    with Store(db) as store:
        store.record_wire([LivelinessChange("r1", "vehicle/3", True, 40, None)])  # the chains grow on
    outcomes, keyed = anchored(db, heads, key.public)
    assert all(o.ok for o in outcomes) and keyed.ok
    assert all(o.wire == "checked" for o in outcomes)
    with Store(db, checkpoint_key=key) as store:  # the tail check re-verifies the latest signature, wire part and all
        assert store.append([event(20)]).stored == 1
    lines = [json.loads(line) for line in (tmp_path / "w.jsonl").read_text().splitlines()]
    assert lines[-1]["wire"] == {"liveliness": {"count": 4, "head": heads[-1].wire_part()["liveliness"]["head"]},
                                 "wire_misses": {"count": 1, "head": heads[-1].wire_part()["wire_misses"]["head"]},
                                 "rulebooks": {"count": 0, "head": GENESIS.hex()}}  # none stored (their own test)
    assert lines[0]["wire"] == {"liveliness": {"count": 0, "head": GENESIS.hex()},
                                "wire_misses": {"count": 0, "head": GENESIS.hex()},
                                "rulebooks": {"count": 0, "head": GENESIS.hex()}}


def test_a_head_without_the_wire_part_checks_the_events_and_says_so(tmp_path, key):
    """A witness line written before v8 (no `wire`) still reads and checks what it covers."""
    db = tmp_path / "s.db"
    heads = wired_store(db, key, tmp_path / "w.jsonl")
    old = [json.dumps({k: v for k, v in h.to_json().items() if k != "wire"}) for h in heads]
    (tmp_path / "old.jsonl").write_text("\n".join(old) + "\n")
    old_heads = read_heads(tmp_path / "old.jsonl")
    assert all(h.wire is None for h in old_heads)
    tamper(db, ("DELETE FROM liveliness WHERE id > 2", ()),
           ("DELETE FROM wire_checkpoints WHERE tbl = 'liveliness' AND through_id > 2", ()), HIDE)
    outcomes, _ = anchored(db, old_heads, None)
    assert all(o.ok and o.wire == "not covered" for o in outcomes)
    # and signed as the v1 statement they were, they verify as before
    v1 = [key.sign(TreeHead(h.run, h.size, h.root, h.head, h.prev_size, h.created_at)) for h in old_heads]
    outcomes, _ = anchored(db, v1, key.public)
    assert all(o.ok for o in outcomes)


def test_a_forged_wire_part_in_a_witness_line_breaks_its_signature(tmp_path, key):
    db = tmp_path / "s.db"
    heads = wired_store(db, key, tmp_path / "w.jsonl")
    line = heads[-1].to_json()
    line["wire"]["liveliness"]["count"] = 2
    forged = TreeHead.from_json(line, "forged")
    assert forged.signature_problem(key.public) is not None


def test_a_checkpoint_row_records_the_wire_part_it_signed(tmp_path, key):
    db = tmp_path / "s.db"
    heads = wired_store(db, key, tmp_path / "w.jsonl")
    stored = [json.loads(w) for (w,) in rows(db, "SELECT wire FROM checkpoints WHERE run = 'r1' ORDER BY id")]
    assert stored == [h.wire_part() for h in heads if h.run == "r1"]
    copy = tmp_path / "nulled.db"
    shutil.copy(db, copy)
    tamper(copy, HIDE)  # the wire parts dropped: the signatures break
    with Store.open_read_only(copy) as store:
        _, keyed = store.check_anchors((), key.public)
    assert not keyed.ok and "does not match" in keyed.problem.what
    conn = sqlite3.connect(db)
    assert conn.execute("SELECT max(version) FROM schema_version").fetchone() == (8,)
    conn.close()


def v7_file(path: Path, key: CheckpointKey, witness_path: Path) -> None:
    """A store as gaps wrote it at schema v7: checkpoints signed as v1 tree heads (no wire part),
    witnessed, and a liveliness row chained with its wire checkpoint."""
    written = path.with_name("written.db")
    with Store(written, checkpoint_every=8) as store:
        store.append([event(i) for i in range(10)])
    conn = old_schema(path, 7)
    conn.execute("ATTACH DATABASE ? AS w", (str(written),))
    conn.execute("INSERT INTO events SELECT * FROM w.events")
    witness = WitnessFile(witness_path)
    for id_, run, count, head, created_at, root, frontier, prev in conn.execute(
            "SELECT id, run, count, head, created_at, merkle_root, frontier, prev_count FROM w.checkpoints").fetchall():
        signed = key.sign(TreeHead(run, count, root, head, prev, created_at))
        conn.execute("INSERT INTO checkpoints (id, run, count, head, created_at, merkle_root, frontier, prev_count, "
                     "signature, key_id) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
                     (id_, run, count, head, created_at, root, frontier, prev, signed.sig, signed.key))
        witness.append([signed])
    witness.close()
    values = ("r1", "vehicle/1", 1, 10, None)
    digest = row_hash("liveliness", GENESIS, 1, values).hex()
    conn.execute("INSERT INTO liveliness (id, run, src, alive, at, last_seq, hash) VALUES (1, ?, ?, ?, ?, ?, ?)",
                 (*values, digest))
    conn.execute("INSERT INTO wire_checkpoints (tbl, through_id, head) VALUES ('liveliness', 1, ?)", (digest,))
    conn.close()
    written.unlink()


def test_a_v7_store_migrates_its_signed_checkpoints_kept_and_later_ones_cover_the_wire(tmp_path, key):
    from store import migrate_copy
    old, new = tmp_path / "v7.db", tmp_path / "v8.db"
    v7_file(old, key, tmp_path / "w.jsonl")
    report = migrate_copy(old, new)
    assert (report.from_version, report.to_version) == (7, 8)
    assert rows(new, "SELECT count(*), count(wire) FROM checkpoints") == [(2, 0)]
    witness = WitnessFile(tmp_path / "w.jsonl")
    with Store(new, checkpoint_key=key, checkpoint_every=8) as store:
        store.add_checkpoint_hook(witness.append)
        store.record_wire([LivelinessChange("r1", "vehicle/1", False, 20, 9)])
        store.append([event(i) for i in range(10, 12)])
        assert store.verify().ok
    witness.close()
    heads = read_heads(tmp_path / "w.jsonl")
    with Store.open_read_only(new) as store:
        outcomes, keyed = store.check_anchors(heads, key.public)
    assert all(o.ok for o in outcomes) and keyed.ok and keyed.signed == 3
    assert [o.wire for o in outcomes] == ["not covered", "not covered", "checked"]
    assert heads[-1].wire_part()["liveliness"]["count"] == 2
    tamper(new, ("DELETE FROM liveliness WHERE id = 2", ()),
           ("DELETE FROM wire_checkpoints WHERE tbl = 'liveliness' AND through_id = 2", ()), HIDE)
    outcomes, keyed = anchored(new, heads, key.public)
    assert [o.outcome for o in outcomes] == ["matches", "matches", "wire cut back"] and not keyed.ok


@pytest.mark.parametrize("value", ['{"liveliness": 1}', "not json", b"\xff{", "[]"])
def test_a_checkpoint_whose_wire_part_is_not_one_fails_plain_verify(tmp_path, key, value):
    """A flipped bit in the column (issue 15's bit flips) is a located problem, never a traceback."""
    db = tmp_path / "s.db"
    wired_store(db, key, tmp_path / "w.jsonl")
    (first,) = rows(db, "SELECT min(id) FROM checkpoints")[0]
    tamper(db, ("UPDATE checkpoints SET wire = CAST(? AS TEXT) WHERE id = ?", (value, first)))
    assert plain_verify_problem(db).startswith(f"checkpoint {first} (run 'r1', 8 events) records a wire part that is "
                                               "not one")
