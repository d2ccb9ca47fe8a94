"""verify(): recomputes every chain and names the first event that does not match.

Each tampering test alters the file the way an attacker with write access would (triggers
dropped first) and checks that verify fails and points at the right event.
"""

import hashlib
import json

import pytest
from tests.helpers.store_testkit import event, rows, tamper

from store import IntegrityResult, RunCheck, Store, VerifyReport

N = 10  # events of run r1, appended in two calls of 5 (so two checkpoints)


@pytest.fixture
def filled(db_path):
    """r1: vehicle/1 and vehicle/2 interleaved; r2: three monitor events."""
    r1 = [event(i // 2, src=f"vehicle/{1 + i % 2}", t=1_000 + i) for i in range(N)]
    r2 = [event(i, run="r2", src="monitor/m1", kind="monitor.observation") for i in range(3)]
    with Store(db_path) as store:
        store.append(r1[:5] + r2)
        store.append(r1[5:])
        assert store.verify().ok
    return db_path


def at(db_path, pos, run="r1"):
    """(src, seq, t, event text, hash) stored at a chain position."""
    [row] = rows(db_path, "SELECT src, seq, t, event, hash FROM events WHERE run = ? AND chain_pos = ?", (run, pos))
    return row


def verify(db_path, run=None) -> VerifyReport:
    with Store(db_path) as store:
        return store.verify(run)


def failed_at(db_path, pos, *, run="r1", named=True):
    """verify fails at chain position pos of run; returns the problem sentence."""
    report = verify(db_path)
    assert not report.ok
    problem = report.problem
    assert (problem.run, problem.chain_pos) == (run, pos)
    if named:
        src, seq = at(db_path, pos, run)[:2]
        assert (problem.src, problem.seq) == (src, seq)
    else:
        assert (problem.src, problem.seq) == (None, None)
    assert {entry.run: entry.ok for entry in report.runs} == {"r1": run != "r1", "r2": run != "r2"}
    return problem.what


def chain_from(prev_hex, texts):
    """Hashes a forger would compute for texts following a known head."""
    prev, out = bytes.fromhex(prev_hex), []
    for text in texts:
        prev = hashlib.sha256(prev + text.encode()).digest()
        out.append(prev.hex())
    return out


def test_untampered_store_verifies(filled):
    report = verify(filled)
    assert report.ok and report.problem is None
    heads = {run: digest for run, digest in rows(filled, "SELECT run, hash FROM events e WHERE chain_pos = "
                                                          "(SELECT max(chain_pos) FROM events WHERE run = e.run)")}
    assert report.runs == (RunCheck("r1", N, heads["r1"], True, 0, N), RunCheck("r2", 3, heads["r2"], True, 0, 3))
    runs = [{"run": "r1", "events": N, "head": heads["r1"], "ok": True, "signed": 0, "unsigned": N},
            {"run": "r2", "events": 3, "head": heads["r2"], "ok": True, "signed": 0, "unsigned": 3}]
    counted = {"signed": 0, "unsigned": N + 3, "checked": False, "keys": None, "valid": None, "invalid": None,
               "first_invalid": None}
    assert report.to_json() == {"ok": True, "runs": runs, "problem": None, "signatures": counted,
                                "integrity": {"ok": True, "messages": []}}
    assert VerifyReport.from_json(report.to_json()) == report       # as the cache keeps and reads it back


def test_empty_store_verifies():
    with Store(":memory:") as store:
        report = store.verify()
        assert report == VerifyReport(ok=True, runs=(), problem=None, signatures=report.signatures,
                                      integrity=IntegrityResult(True, ()))
        assert report.signatures.signed == report.signatures.unsigned == 0


def test_one_byte_of_an_event_changed(filled):
    text = at(filled, 4)[3]
    altered = text.replace("red light", "red lighT")
    assert len(altered) == len(text) and altered != text
    tamper(filled, ("UPDATE events SET event = ? WHERE run = 'r1' AND chain_pos = 4", (altered,)))
    what = failed_at(filled, 4)
    assert what.startswith("hash does not match: stored ")
    assert at(filled, 4)[4][:12] in what


@pytest.mark.parametrize("column, value", [("t", None), ("seq", 77), ("src", "vehicle/9"), ("kind", "collision")])
def test_an_index_column_changed(filled, column, value):
    if value is None:
        value = at(filled, 6)[2] + 1  # t one nanosecond later
    said = json.loads(at(filled, 6)[3])[column]
    tamper(filled, (f"UPDATE events SET {column} = ? WHERE run = 'r1' AND chain_pos = 6", (value,)))
    what = failed_at(filled, 6)
    shown = (lambda v: json.dumps(v) if isinstance(v, str) else str(v))
    assert what == f"column {column} is {shown(value)} but the event says {shown(said)}"


def test_a_middle_row_deleted(filled):
    tamper(filled, ("DELETE FROM events WHERE run = 'r1' AND chain_pos = 5", ()))
    what = failed_at(filled, 5, named=False)
    assert what.startswith("chain position 5 is missing")
    assert "at position 6" in what


def test_the_first_row_deleted(filled):
    tamper(filled, ("DELETE FROM events WHERE run = 'r1' AND chain_pos = 0", ()))
    assert failed_at(filled, 0, named=False).startswith("chain position 0 is missing")


def test_the_last_row_deleted(filled):
    tamper(filled, ("DELETE FROM events WHERE run = 'r1' AND chain_pos = ?", (N - 1,)))
    what = failed_at(filled, N - 1, named=False)
    assert what.startswith(f"chain position {N - 1} is missing")
    assert f"checkpoint of {N} events" in what


def test_a_whole_run_deleted(filled):
    tamper(filled, ("DELETE FROM events WHERE run = 'r2'", ()))
    assert failed_at(filled, 0, run="r2", named=False).startswith("chain position 0 is missing")


def test_a_forged_row_appended_with_a_valid_hash(filled):
    """The forger extends the chain correctly; only the checkpoints show the row is new."""
    forged = event(50, src="vehicle/1", t=5_000, body={"facts": ["173 has green light"]})
    text = json.dumps(forged, sort_keys=True, separators=(",", ":"))
    [digest] = chain_from(at(filled, N - 1)[4], [text])
    tamper(filled, ("INSERT INTO events (run, chain_pos, src, seq, t, kind, event, hash) VALUES (?,?,?,?,?,?,?,?)",
                    ("r1", N, "vehicle/1", 50, 5_000, "vehicle.perception", text, digest)))
    assert "not covered by any checkpoint" in failed_at(filled, N)


def test_a_forged_row_inserted_in_the_middle(filled):
    """Positions 3.. shifted up to make room; the forged row's hash is made up."""
    forged = event(40, src="vehicle/2", t=1_003)
    text = json.dumps(forged, sort_keys=True, separators=(",", ":"))
    shifts = [("UPDATE events SET chain_pos = chain_pos + 1 WHERE run = 'r1' AND chain_pos = ?", (pos,))
              for pos in range(N - 1, 2, -1)]
    insert = ("INSERT INTO events (run, chain_pos, src, seq, t, kind, event, hash) VALUES (?,?,?,?,?,?,?,?)",
              ("r1", 3, "vehicle/2", 40, 1_003, "vehicle.perception", text, "ab" * 32))
    tamper(filled, *shifts, insert)
    assert failed_at(filled, 3).startswith("hash does not match")


def test_a_forged_row_inserted_and_the_whole_chain_rehashed(filled):
    """The strongest forger rewrites every later hash; the first checkpoint still disagrees."""
    texts = [at(filled, pos)[3] for pos in range(N)]
    forged = json.dumps(event(40, src="vehicle/2", t=1_003), sort_keys=True, separators=(",", ":"))
    new_texts = texts[:3] + [forged] + texts[3:]
    hashes = chain_from(at(filled, 2)[4], new_texts[3:])
    statements = [("DELETE FROM events WHERE run = 'r1' AND chain_pos >= 3", ())]
    for pos, (text, digest) in enumerate(zip(new_texts[3:], hashes), start=3):
        ev = json.loads(text)
        statements.append(("INSERT INTO events (run, chain_pos, src, seq, t, kind, event, hash) VALUES (?,?,?,?,?,?,?,?)",
                           ("r1", pos, ev["src"], ev["seq"], ev["t"], ev["kind"], text, digest)))
    tamper(filled, *statements)
    what = failed_at(filled, 4)  # the end of the first checkpoint's span
    assert what.startswith("the checkpoint of 5 events records head")
    assert "chain position 0 to 4" in what


def test_two_rows_swapped(filled):
    swap = "UPDATE events SET chain_pos = ? WHERE run = 'r1' AND chain_pos = ?"
    moved = at(filled, 7)[:2]
    tamper(filled, (swap, (-1, 2)), (swap, (2, 7)), (swap, (7, -1)))
    assert failed_at(filled, 2).startswith("hash does not match")
    assert at(filled, 2)[:2] == moved


def test_a_hash_overwritten(filled):
    true_hash = at(filled, 8)[4]
    tamper(filled, ("UPDATE events SET hash = ? WHERE run = 'r1' AND chain_pos = 8", ("00" * 32,)))
    assert failed_at(filled, 8) == f"hash does not match: stored 000000000000…, recomputed {true_hash[:12]}…"


def test_non_canonical_text_with_a_rehashed_chain(filled):
    """Hashes recomputed over a re-spaced event: the text itself is no longer canonical."""
    texts = [at(filled, pos)[3] for pos in range(N)]
    texts[6] = texts[6].replace(",", ", ", 1)
    statements = [("UPDATE events SET event = ?, hash = ? WHERE run = 'r1' AND chain_pos = ?", (text, digest, pos))
                  for pos, (text, digest) in enumerate(zip(texts[6:], chain_from(at(filled, 5)[4], texts[6:])), start=6)]
    tamper(filled, *statements)
    assert failed_at(filled, 6) == "the stored event text is not in canonical form"


def test_a_checkpoint_forged_in_the_v1_form(filled):
    tamper(filled, ("INSERT INTO checkpoints (run, count, head, created_at) VALUES ('r1', 3, ?, 0)", ("cd" * 32,)))
    assert failed_at(filled, 2).startswith("the checkpoint of 3 events lacks the Merkle root")


def test_a_checkpoint_forged_in_sequence(filled):
    """A forger who links the checkpoint into the sequence still cannot make its head match."""
    tamper(filled,
           ("DELETE FROM checkpoints WHERE run = 'r1'", ()),
           ("INSERT INTO checkpoints (run, count, head, created_at, merkle_root, frontier, prev_count) "
            "VALUES ('r1', 10, ?, 0, ?, '', 0)", ("cd" * 32, "cd" * 32)))
    assert failed_at(filled, 9).startswith("the checkpoint of 10 events records head cdcdcdcdcdcd…")


def test_the_first_problem_is_reported(filled):
    tamper(filled,
           ("UPDATE events SET t = 0 WHERE run = 'r1' AND chain_pos = 8", ()),
           ("UPDATE events SET t = 0 WHERE run = 'r1' AND chain_pos = 3", ()),
           ("UPDATE events SET t = 0 WHERE run = 'r2' AND chain_pos = 0", ()))
    report = verify(filled)
    assert (report.problem.run, report.problem.chain_pos) == ("r1", 3)
    assert [entry.ok for entry in report.runs] == [False, False]
    assert [entry.head for entry in report.runs] == [None, None]


def test_verify_one_run(filled):
    tamper(filled, ("UPDATE events SET t = 0 WHERE run = 'r1' AND chain_pos = 1", ()))
    assert verify(filled, "r2").ok
    assert [entry.run for entry in verify(filled, "r2").runs] == ["r2"]
    assert not verify(filled, "r1").ok


def test_verify_an_unknown_run_fails(filled):
    report = verify(filled, "nope")
    assert not report.ok
    assert report.problem.what == "no events or checkpoints are recorded for run nope"


def test_a_rulebook_altered(filled):
    with Store(filled) as store:
        address = store.put_rulebook("hc", "1", "A vehicle must stop at a red light.\n")
    tamper(filled, ("UPDATE rulebooks SET text = 'A vehicle may go.\n' WHERE sha256 = ?", (address,)))
    report = verify(filled)
    assert not report.ok
    assert report.problem.run is None
    assert report.problem.what.startswith(f"rulebook hc 1 is stored under {address[:12]}…")
    with Store(filled) as store:
        with pytest.raises(ValueError, match="does not match its text"):
            store.get_rulebook(address)


# --- checkpoints: Merkle roots, frontiers and their sequence --------------------------------------

@pytest.fixture
def checkpointed(db_path):
    """r1 of 10 events, checkpointed every 3: at 3, 6, 9 and 10 (ids 1-4)."""
    with Store(db_path, checkpoint_every=3) as store:
        store.append([event(i) for i in range(10)])
        assert store.verify().ok
    return db_path


def failed_with(db_path, pos):
    report = verify(db_path)
    assert not report.ok
    assert (report.problem.run, report.problem.chain_pos) == ("r1", pos)
    assert (report.problem.src, report.problem.seq) == at(db_path, pos)[:2]
    return report.problem.what


def test_a_merkle_root_altered(checkpointed):
    tamper(checkpointed, ("UPDATE checkpoints SET merkle_root = ? WHERE count = 6", ("ee" * 32,)))
    what = failed_with(checkpointed, 5)
    assert what.startswith("the checkpoint of 6 events records Merkle root eeeeeeeeeeee…, but the events recompute to")


def test_a_frontier_altered(checkpointed):
    [(frontier,)] = rows(checkpointed, "SELECT frontier FROM checkpoints WHERE count = 9")
    tamper(checkpointed, ("UPDATE checkpoints SET frontier = ? WHERE count = 9", (frontier[::-1],)))
    assert "records a Merkle frontier that the events do not produce" in failed_with(checkpointed, 8)


def test_a_middle_checkpoint_deleted(checkpointed):
    tamper(checkpointed, ("DELETE FROM checkpoints WHERE count = 6", ()))
    what = failed_with(checkpointed, 8)
    assert what == ("the checkpoint of 9 events follows a checkpoint of 6 events, but the one recorded before it "
                    "is of 3: a checkpoint was removed, added or changed")


def test_the_first_checkpoint_deleted(checkpointed):
    tamper(checkpointed, ("DELETE FROM checkpoints WHERE count = 3", ()))
    assert "follows a checkpoint of 3 events, but the one recorded before it is of 0" in failed_with(checkpointed, 5)


def test_the_latest_checkpoint_deleted(checkpointed):
    tamper(checkpointed, ("DELETE FROM checkpoints WHERE count = 10", ()))
    assert failed_with(checkpointed, 9).startswith("the event is not covered by any checkpoint (the latest records 9")


def test_a_previous_count_altered(checkpointed):
    tamper(checkpointed, ("UPDATE checkpoints SET prev_count = 5 WHERE count = 9", ()))
    assert "follows a checkpoint of 5 events" in failed_with(checkpointed, 8)


def test_two_checkpoints_reordered(checkpointed):
    swap = "UPDATE checkpoints SET id = ? WHERE id = ?"
    tamper(checkpointed, (swap, (-1, 2)), (swap, (2, 3)), (swap, (3, -1)))
    assert "is recorded after one of 9 events: checkpoints were reordered or added" in failed_with(checkpointed, 5)


def test_a_checkpoint_count_altered(checkpointed):
    tamper(checkpointed, ("UPDATE checkpoints SET count = 7 WHERE count = 6", ()))
    assert failed_with(checkpointed, 6).startswith("the checkpoint of 7 events records head")


def test_a_true_checkpoint_added_at_the_head(checkpointed):
    """Head, root and frontier all correct for the count: only its place in the sequence is wrong."""
    [(head, root, frontier)] = rows(checkpointed, "SELECT head, merkle_root, frontier FROM checkpoints WHERE count = 10")
    tamper(checkpointed, ("INSERT INTO checkpoints (run, count, head, created_at, merkle_root, frontier, prev_count) "
                          "VALUES ('r1', 10, ?, 0, ?, ?, 10)", (head, root, frontier)))
    assert "is recorded after one of 10 events" in failed_with(checkpointed, 9)


def test_a_checkpoint_moved_to_another_run(checkpointed):
    tamper(checkpointed, ("UPDATE checkpoints SET run = 'r9' WHERE count = 3", ()))
    report = verify(checkpointed)
    assert not report.ok
    assert {entry.run: entry.ok for entry in report.runs} == {"r1": False, "r9": False}


def test_a_checkpoint_with_an_impossible_count(checkpointed):
    tamper(checkpointed, ("UPDATE checkpoints SET count = 'ten' WHERE count = 10", ()))
    assert failed_with(checkpointed, 0) == 'the checkpoint of "ten" events records an impossible event count'


def test_progress_is_reported_and_ends_at_the_total(db_path, monkeypatch):
    import store.verify as verify_module

    monkeypatch.setattr(verify_module, "_PROGRESS_EVERY", 4)
    with Store(db_path) as store:
        store.append([event(i) for i in range(10)] + [event(0, run="r2")])
        calls = []
        assert store.verify(progress=lambda done, total: calls.append((done, total))).ok
        assert calls == [(4, 11), (8, 11), (11, 11)]
        calls.clear()
        assert store.verify("r2", progress=lambda done, total: calls.append((done, total))).ok
        assert calls == [(1, 1)]
