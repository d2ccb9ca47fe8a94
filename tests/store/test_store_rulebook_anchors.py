"""Issue 15, the last gap: the stored rulebooks anchored by the checkpoints, as the wire tables are.

A run's events may cite a rulebook by sha256 only: the reasoner then loads its text from the
`rulebooks` table, and a report shows that table's version when the run's `run.start` records
none. Its text is proven by its address, but a row deleted (a stage falls back to another
rulebook), or a name or version changed (the report changes), left a store `gaps verify` passed.
Now the table is one more chain whose end (last rowid, head) every checkpoint records in its
`wire` part, signed with the run's tree head: plain verify checks those records against the
table, and once someone rewrites them too, a witness (`--against`) and the checkpoint key catch it.
"""
from __future__ import annotations

import hashlib
import json
from pathlib import Path

import pytest
from tests.helpers.store_testkit import event, rows, tamper

from store import Store
from store.keys import CheckpointKey, WitnessFile, read_heads
from store.chain import GENESIS
from store.keys.tree_heads import TreeHead

TEXT = "the templates are:\n*a vehicle* must stop at *a light*.\n"
OTHER = "the templates are:\n*a vehicle* may proceed.\n"


@pytest.fixture
def key(tmp_path):
    return CheckpointKey.create(tmp_path / "checkpoint.key")


def booked_store(db: Path, key: CheckpointKey, witness_path: Path) -> tuple[str, list[TreeHead]]:
    """Events, a rulebook put, more events: the checkpoints of the later append (signed,
    witnessed) record the rulebooks' end with the rulebook in it; the earlier ones an empty table."""
    witness = WitnessFile(witness_path)
    with Store(db, checkpoint_key=key, checkpoint_every=8) as store:
        store.add_checkpoint_hook(witness.append)
        store.append([event(i) for i in range(10)])
        sha = store.put_rulebook("highway code", "2024.1", TEXT)
        store.append([event(i) for i in range(10, 14)])
    witness.close()
    return sha, read_heads(witness_path)


def plain_verify_problem(db: Path) -> str | None:
    with Store.open_read_only(db) as store:
        report = store.verify()
    return None if report.ok else report.problem.what


def _parts(db: Path) -> list[tuple[int, dict]]:
    return [(id_, json.loads(text)) for id_, text in rows(db, "SELECT id, wire FROM checkpoints ORDER BY id")]


def drop_rulebooks_key(db: Path) -> None:
    """The attacker's cover: the checkpoints' record of the rulebooks removed, so their parts look
    like parts written before the rulebooks were chained."""
    tamper(db, *(("UPDATE checkpoints SET wire = ? WHERE id = ?",
                  (json.dumps({k: v for k, v in part.items() if k != "rulebooks"}), id_))
                 for id_, part in _parts(db)))


def rerecord_rulebooks_end(db: Path) -> None:
    """The attacker's better cover: every checkpoint that recorded the rulebook now records the end
    the changed table recomputes to, as an append would have written it."""
    from store.wire.ends import ends_now, to_part
    with Store.open_read_only(db) as store:
        now = to_part(ends_now(store.connection))["rulebooks"]
    tamper(db, *(("UPDATE checkpoints SET wire = ? WHERE id = ?", (json.dumps({**part, "rulebooks": now}), id_))
                 for id_, part in _parts(db) if part["rulebooks"]["count"] > 0))


ATTACKS = {
    "deleted": (lambda sha: [("DELETE FROM rulebooks WHERE sha256 = ?", (sha,))], "rulebooks cut back"),
    "version changed": (lambda sha: [("UPDATE rulebooks SET version = '2019.3' WHERE sha256 = ?", (sha,))],
                        "rulebooks rewritten"),
    "name changed": (lambda sha: [("UPDATE rulebooks SET name = 'old code' WHERE sha256 = ?", (sha,))],
                     "rulebooks rewritten"),
    # another text under its own address: the address check passes, the chain does not
    "text and address changed": (lambda sha: [("UPDATE rulebooks SET text = ?, sha256 = ? WHERE sha256 = ?",
                                               (OTHER, hashlib.sha256(OTHER.encode()).hexdigest(), sha))],
                                 "rulebooks rewritten"),
}


def test_an_untouched_store_records_the_rulebooks_end_and_matches(tmp_path, key):
    db = tmp_path / "s.db"
    _, heads = booked_store(db, key, tmp_path / "w.jsonl")
    parts = [h.wire_part()["rulebooks"] for h in heads]
    assert parts[0] == {"count": 0, "head": GENESIS.hex()}  # before the rulebook was put
    assert parts[-1]["count"] == 1 and parts[-1]["head"] != GENESIS.hex()
    assert [p for _, p in _parts(db)] == [h.wire_part() for h in heads]  # the rows record what was signed
    assert plain_verify_problem(db) is None
    with Store.open_read_only(db) as store:
        outcomes, keyed = store.check_anchors(heads, key.public)
    assert all(o.ok and o.rulebooks == "checked" and o.wire == "checked" for o in outcomes) and keyed.ok


@pytest.mark.parametrize("attack", ATTACKS)
def test_a_stored_rulebook_changed_or_removed_fails_verify_then_against_and_key(tmp_path, key, attack):
    db = tmp_path / "s.db"
    sha, heads = booked_store(db, key, tmp_path / "w.jsonl")
    statements, outcome = ATTACKS[attack]
    tamper(db, *statements(sha))
    problem = plain_verify_problem(db)  # the checkpoints' record of the rulebooks' end is still there
    assert problem is not None and "rulebooks" in problem and "the checkpoint of 14 events of run r1" in problem
    assert f"({outcome})" in problem
    for cover in (rerecord_rulebooks_end, drop_rulebooks_key):
        copy = tmp_path / f"{cover.__name__}.db"
        copy.write_bytes(db.read_bytes())
        cover(copy)
        assert plain_verify_problem(copy) is None  # the file agrees with itself: only what is kept outside tells
        with Store.open_read_only(copy) as store:
            outcomes, keyed = store.check_anchors(heads, key.public)
        failed = [o for o in outcomes if not o.ok]
        assert [o.size for o in failed] == [14] and failed[0].outcome == outcome
        assert "rulebooks" in failed[0].what and failed[0].rulebooks == "checked"
        assert not keyed.ok and "does not match the head" in keyed.problem.what


def test_a_rulebook_put_after_the_last_checkpoint_is_covered_by_the_next_append(tmp_path, key):
    db = tmp_path / "s.db"
    booked_store(db, key, tmp_path / "w.jsonl")
    with Store(db, checkpoint_key=key) as store:
        later = store.put_rulebook("highway code", "2024.2", OTHER)
    assert _parts(db)[-1][1]["rulebooks"]["count"] == 1  # no checkpoint records it yet
    uncovered = tmp_path / "uncovered.db"
    uncovered.write_bytes(db.read_bytes())
    tamper(uncovered, ("DELETE FROM rulebooks WHERE sha256 = ?", (later,)))
    assert plain_verify_problem(uncovered) is None  # the limit: nothing recorded it (docs/guarantees.md)
    witness = WitnessFile(tmp_path / "w.jsonl")
    with Store(db, checkpoint_key=key) as store:
        store.add_checkpoint_hook(witness.append)
        store.append([event(14)])
    witness.close()
    heads = read_heads(tmp_path / "w.jsonl")
    assert heads[-1].wire_part()["rulebooks"]["count"] == 2 and _parts(db)[-1][1] == heads[-1].wire_part()
    tamper(db, ("UPDATE rulebooks SET version = '2024.1' WHERE sha256 = ?", (later,)))
    problem = plain_verify_problem(db)
    assert problem is not None and "the checkpoint of 15 events of run r1" in problem and "rulebooks row 2" in problem
    rerecord_rulebooks_end(db)
    with Store.open_read_only(db) as store:
        outcomes, keyed = store.check_anchors(heads, key.public)
    assert [o.size for o in outcomes if not o.ok] == [15] and not keyed.ok


def test_a_part_without_the_rulebooks_key_checks_the_wire_and_says_the_rulebooks_are_not_covered(tmp_path, key):
    """Heads and checkpoints written before the rulebooks were chained still read and check."""
    db = tmp_path / "s.db"
    sha, heads = booked_store(db, key, tmp_path / "w.jsonl")
    older = []
    for head in heads:
        line = head.to_json()
        line["wire"].pop("rulebooks")
        older.append(key.sign(TreeHead.from_json(line, "older")))  # signed as such a head was
    drop_rulebooks_key(db)  # the checkpoints as a writer before this change wrote them: signed without it
    tamper(db, *(("UPDATE checkpoints SET signature = ? WHERE id = ?", (h.sig, id_))
                 for (id_, _), h in zip(_parts(db), older)))
    assert plain_verify_problem(db) is None
    tamper(db, ("DELETE FROM rulebooks WHERE sha256 = ?", (sha,)))
    assert plain_verify_problem(db) is None  # nothing records the rulebooks: not covered
    with Store.open_read_only(db) as store:
        outcomes, keyed = store.check_anchors(older, key.public)
    assert all(o.ok and o.wire == "checked" and o.rulebooks == "not covered" for o in outcomes) and keyed.ok


@pytest.mark.parametrize("rulebooks", [{"count": -1, "head": GENESIS.hex()}, {"count": 1}, "x",
                                       {"count": 1, "head": "nothex"}])
def test_a_checkpoint_whose_rulebooks_part_is_not_one_fails_plain_verify(tmp_path, key, rulebooks):
    db = tmp_path / "s.db"
    booked_store(db, key, tmp_path / "w.jsonl")
    id_, part = _parts(db)[-1]
    tamper(db, ("UPDATE checkpoints SET wire = ? WHERE id = ?", (json.dumps({**part, "rulebooks": rulebooks}), id_)))
    assert plain_verify_problem(db).startswith(f"checkpoint {id_} (run 'r1', 14 events) records a wire part that is "
                                               "not one")


def test_a_rulebook_row_of_a_value_no_put_writes_is_a_problem_not_a_crash(tmp_path, key):
    db = tmp_path / "s.db"
    sha, _ = booked_store(db, key, tmp_path / "w.jsonl")
    tamper(db, ("UPDATE rulebooks SET version = CAST(x'ff00' AS BLOB) WHERE sha256 = ?", (sha,)))
    problem = plain_verify_problem(db)
    assert problem is not None and "rulebooks row 1" in problem


def test_a_writers_running_end_is_the_recomputed_one_across_puts_here_and_elsewhere(tmp_path):
    """The writer hashes only the rulebooks put since its last append (store/rulebook_chain.py),
    and forgets that when another connection commits: every end it records is the table's."""
    from store.rulebook_chain import recomputed
    db = tmp_path / "s.db"
    with Store(db) as store, Store(db) as other:
        store.append([event(0)])
        store.put_rulebook("a", "1", TEXT)
        store.put_rulebook("b", "1", OTHER)
        store.append([event(1)])  # two rows hashed onto the running end
        other.put_rulebook("c", "1", TEXT + " ")
        store.append([event(2)])  # another connection put one: recomputed from the table
        store.put_rulebook("d", "1", OTHER + " ")
        store.append([event(3)])
        table = [(0, GENESIS.hex()), *recomputed(store.connection)]  # the end after each row
    recorded = [(part["rulebooks"]["count"], part["rulebooks"]["head"]) for _, part in _parts(db)]
    assert recorded == [table[i] for i in (0, 2, 3, 4)]
    assert plain_verify_problem(db) is None
