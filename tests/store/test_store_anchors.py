"""Issue 15, finding 4: attacks on a store by someone holding the file (raw sqlite3 on a copy)
that `gaps verify` alone cannot see, caught by signed checkpoints (the checkpoint key), by tree
heads kept outside the store (a witness file), and by the append checking a run's tail before
it extends it."""
from __future__ import annotations

import hashlib
import shutil
import sqlite3

import pytest
from tests.helpers.store_testkit import event, rows, tamper

from store import Store, canonical_json
from store.keys import CheckpointKey, WitnessFile, read_heads, recorded_heads
from store.tail_check import TamperedTail
from store.chain import GENESIS, link


@pytest.fixture
def key(tmp_path):
    return CheckpointKey.create(tmp_path / "checkpoint.key")


def witnessed_store(path, key, witness_path, calls=((0, 10), (10, 20), (20, 25))):
    """A store of run r1 (and r2) written in several appends, every checkpoint signed and witnessed."""
    witness = WitnessFile(witness_path)
    with Store(path, checkpoint_key=key, checkpoint_every=8) as store:
        store.add_checkpoint_hook(witness.append)
        for lo, hi in calls:
            store.append([event(i) for i in range(lo, hi)] + [event(lo, run="r2")])
    witness.close()
    return read_heads(witness_path)


def sha(path):
    return hashlib.sha256(path.read_bytes()).hexdigest()


def rewrite_run(path, run, events, every=8, key=None):
    """A consistent rewrite: the run's events and checkpoints replaced by those an honest store
    would write for `events`, keeping the ids of the checkpoints replaced."""
    scratch = path.with_name("scratch.db")
    with Store(scratch, checkpoint_every=every, checkpoint_key=key) as honest:
        honest.append(events)
    new_events = rows(scratch, "SELECT * FROM events WHERE run = ? ORDER BY chain_pos", (run,))
    new_checkpoints = rows(scratch, "SELECT run, count, head, created_at, merkle_root, frontier, prev_count, "
                                    "signature, key_id FROM checkpoints WHERE run = ? ORDER BY id", (run,))
    ids = [i for (i,) in rows(path, "SELECT id FROM checkpoints WHERE run = ? ORDER BY id", (run,))]
    scratch.unlink()
    statements = [("DELETE FROM events WHERE run = ?", (run,)), ("DELETE FROM checkpoints WHERE run = ?", (run,))]
    statements += [("INSERT INTO events VALUES (?, ?, ?, ?, ?, ?, ?, ?)", row) for row in new_events]
    statements += [("INSERT INTO checkpoints (id, run, count, head, created_at, merkle_root, frontier, prev_count, "
                    "signature, key_id) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)", (i, *row))
                   for i, row in zip(ids, new_checkpoints)]
    tamper(path, *statements)


def test_signed_checkpoints_and_witness_heads_are_the_same_statements(tmp_path, key):
    heads = witnessed_store(tmp_path / "s.db", key, tmp_path / "w.jsonl")
    stored = rows(tmp_path / "s.db", "SELECT run, count, merkle_root, signature, key_id FROM checkpoints ORDER BY id")
    assert [(h.run, h.size, h.root, h.sig, h.key) for h in heads] == stored
    assert all(h.signature_problem(key.public) is None for h in heads)
    assert [h.size for h in heads if h.run == "r1"] == [8, 10, 16, 20, 24, 25]


def test_an_untouched_store_matches_every_head_and_the_key(tmp_path, key):
    heads = witnessed_store(tmp_path / "s.db", key, tmp_path / "w.jsonl")
    with Store.open_read_only(tmp_path / "s.db") as store:
        outcomes, keyed = store.check_anchors(heads, key.public)
    assert all(o.ok for o in outcomes) and keyed.ok and keyed.signed == len(heads)
    latest = [o for o in outcomes if o.run == "r1"][-1]
    assert latest.outcome == "matches" and latest.stored == 25
    older = [h for h in heads if h.run == "r1" and h.size <= 20]  # a witness that saw the run up to 20 events
    with Store.open_read_only(tmp_path / "s.db") as store:
        outcomes, _ = store.check_anchors(older)
    assert [o.outcome for o in outcomes] == ["matches"] * 3 + ["consistent"]
    assert outcomes[-1].stored == 25 and outcomes[-1].proof_nodes >= 1


def test_truncation_to_a_checkpoint_passes_verify_but_not_the_witness(tmp_path, key):
    db = tmp_path / "s.db"
    heads = witnessed_store(db, key, tmp_path / "w.jsonl")
    copy = tmp_path / "cut.db"
    shutil.copy(db, copy)
    tamper(copy, ("DELETE FROM events WHERE run = 'r1' AND chain_pos >= 16", ()),
           ("DELETE FROM checkpoints WHERE run = 'r1' AND count > 16", ()))
    with Store.open_read_only(copy) as store:
        assert store.verify().ok  # the attack is real: the file agrees with itself
        outcomes, keyed = store.check_anchors(heads, key.public)
    cut = [o for o in outcomes if not o.ok]
    assert {o.size for o in cut} == {20, 24, 25} and {o.outcome for o in cut} == {"truncated"}
    assert "events 16 to 19 were removed" in cut[0].what
    assert keyed.ok  # what is left is signed: only the witness knows there was more


def test_a_forged_tail_is_refused_by_the_next_append_not_sealed(tmp_path, key):
    db = tmp_path / "s.db"
    witnessed_store(db, key, tmp_path / "w.jsonl")
    (head,) = rows(db, "SELECT hash FROM events WHERE run = 'r1' ORDER BY chain_pos DESC LIMIT 1")[0:1]
    forged = event(25, body={"objects": []})
    text = canonical_json(forged)
    digest = link(bytes.fromhex(head[0]), text)
    for with_key in (key, None):
        copy = tmp_path / f"forged-{with_key is None}.db"
        shutil.copy(db, copy)
        tamper(copy, ("INSERT INTO events VALUES ('r1', 25, ?, 25, ?, ?, ?, ?)",
                      (forged["src"], forged["t"], forged["kind"], text.decode(), digest.hex())))
        before = rows(copy, "SELECT count(*) FROM events")
        with Store(copy, checkpoint_key=with_key) as store, pytest.raises(TamperedTail, match="25 to 25 were not "
                                                                           "written by an append"):
            store.append([event(26)])
        assert rows(copy, "SELECT count(*) FROM events") == before  # nothing appended, nothing sealed
        assert rows(copy, "SELECT max(count) FROM checkpoints WHERE run = 'r1'") == [(25,)]


def test_a_forged_tail_with_a_checkpoint_over_it_is_refused_with_the_key(tmp_path, key):
    db = tmp_path / "s.db"
    witnessed_store(db, key, tmp_path / "w.jsonl")
    copy = tmp_path / "sealed.db"
    shutil.copy(db, copy)
    rewrite_run(copy, "r1", [event(i) for i in range(25)] + [event(25, body={"objects": []})], every=8)
    # the attacker's checkpoints are unsigned: an append with the key refuses, --key fails
    with Store(copy, checkpoint_key=key) as store, pytest.raises(TamperedTail, match="its signatures were stripped or it was rewritten"):
        store.append([event(26)])
    with Store.open_read_only(copy) as store:
        assert store.verify().ok
        _, keyed = store.check_anchors((), key.public, recorded=recorded_heads(key.public_file(), key.public))
    assert not keyed.ok and "the checkpoint of 8 events is unsigned; the key file records the run's first signed " \
        "head there" in keyed.problem.what


def test_nulled_merkle_roots_under_a_raised_legacy_flag_fail_verify(tmp_path, key):
    db = tmp_path / "s.db"
    heads = witnessed_store(db, key, tmp_path / "w.jsonl")
    (top,) = rows(db, "SELECT max(id) FROM checkpoints")[0]
    roots_only = tmp_path / "roots.db"
    shutil.copy(db, roots_only)
    tamper(roots_only, ("UPDATE checkpoints SET merkle_root = NULL", ()),
           ("UPDATE legacy_checkpoints SET through_id = ?", (top,)))
    everything = tmp_path / "all.db"
    shutil.copy(db, everything)
    tamper(everything, ("UPDATE checkpoints SET merkle_root = NULL, frontier = NULL, prev_count = NULL", ()),
           ("UPDATE legacy_checkpoints SET through_id = ?", (top,)))
    for copy in (roots_only, everything):
        with Store.open_read_only(copy) as store:
            report = store.verify()
        assert not report.ok and "the legacy record was raised" in report.problem.what
    tamper(everything, ("UPDATE checkpoints SET signature = NULL, key_id = NULL", ()))
    with Store.open_read_only(everything) as store:
        assert store.verify().ok  # nothing in the file tells: the key and the witness do
        outcomes, keyed = store.check_anchors(heads, key.public)
    assert not keyed.ok and "no checkpoint is signed" in keyed.problem.what
    assert all(o.ok for o in outcomes)  # the events are the originals


def test_a_consistent_rewrite_of_a_whole_run_is_caught(tmp_path, key):
    db = tmp_path / "s.db"
    witness = WitnessFile(tmp_path / "w.jsonl")
    spawn = event(0, kind="entity.spawn", src="vehicle/253", body={"type": "ambulance", "driver": "human"})
    with Store(db, checkpoint_key=key) as store:
        store.add_checkpoint_hook(witness.append)
        store.append([spawn, *(event(i) for i in range(5))])
    witness.close()
    heads = read_heads(tmp_path / "w.jsonl")
    car = {**spawn, "body": {"type": "car", "driver": "human"}}
    thief = CheckpointKey.create(tmp_path / "thief.key")
    rewrite_run(db, "r1", [car, *(event(i) for i in range(5))], every=1000, key=thief)
    with Store.open_read_only(db) as store:
        assert store.verify().ok  # the rewrite agrees with itself
        [spawned] = store.events("r1", kinds=["entity.spawn"])
        assert spawned["body"]["type"] == "car"
        outcomes, keyed = store.check_anchors(heads, key.public)
    assert [o.outcome for o in outcomes] == ["rewritten"]
    assert not keyed.ok  # the run's signed checkpoints are gone: "no checkpoint is signed by key …"


def test_a_deleted_run_is_caught_by_the_witness_only(tmp_path, key):
    db = tmp_path / "s.db"
    heads = witnessed_store(db, key, tmp_path / "w.jsonl")
    tamper(db, ("DELETE FROM events WHERE run = 'r2'", ()), ("DELETE FROM checkpoints WHERE run = 'r2'", ()))
    with Store.open_read_only(db) as store:
        assert store.verify().ok
        outcomes, keyed = store.check_anchors(heads, key.public)
        assert keyed.ok  # what is left is signed
        _, recorded = store.check_anchors((), key.public, recorded=recorded_heads(key.public_file(), key.public))
    assert {o.outcome for o in outcomes if o.run == "r2"} == {"run missing"}
    # the key file records r2, and says the store lacks it; it cannot say whether r2 was deleted or
    # signed into another store with this key, so only the witness fails
    assert recorded.ok and recorded.absent == ("r2",)


def test_a_head_not_signed_by_the_key_fails(tmp_path, key):
    heads = witnessed_store(tmp_path / "s.db", key, tmp_path / "w.jsonl")
    other = CheckpointKey.create(tmp_path / "other.key")
    with Store.open_read_only(tmp_path / "s.db") as store:
        outcomes, _ = store.check_anchors([other.sign(heads[0])], key.public)
    assert outcomes[0].outcome == "bad signature"


def test_an_honest_reopen_and_append_with_the_key_passes_the_tail_check(tmp_path, key):
    db = tmp_path / "s.db"
    witnessed_store(db, key, tmp_path / "w.jsonl")
    with Store(db, checkpoint_key=key) as store:
        store.append([event(25), event(26)])
        assert store.verify().ok
    with Store.open_read_only(db) as store:
        _, keyed = store.check_anchors((), key.public)
    assert keyed.ok


def test_signing_begins_where_the_key_first_signs(tmp_path, key):
    db = tmp_path / "s.db"
    with Store(db) as store:
        store.append([event(i) for i in range(3)])
    with Store(db, checkpoint_key=key) as store:
        store.append([event(i) for i in range(3, 6)])
    with Store.open_read_only(db) as store:
        _, keyed = store.check_anchors((), key.public)
    assert keyed.ok and keyed.unsigned_before == 1 and keyed.signed == 1
    tamper(db, ("INSERT INTO checkpoints (run, count, head, created_at, merkle_root, frontier, prev_count) "
                "SELECT run, count, head, created_at, merkle_root, frontier, prev_count FROM checkpoints "
                "WHERE id = 2", ()))
    with Store.open_read_only(db) as store:
        _, keyed = store.check_anchors((), key.public)
    assert not keyed.ok and "unsigned" in keyed.problem.what
