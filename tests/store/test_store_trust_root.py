"""Issue 37: whether a run must be signed, and which signed head its tail must extend, is decided
by what the file's holder does not hold (the checkpoint key's public file, which records each
run's first signed head, and the witness), never by checkpoint ids or columns in the store.

Each attack (tests/helpers/trust_attacks.py) changes what a verdict reads (an ambulance made a
car, a red light made green, events no source sent) on a copy of a store the key's holder wrote
in several appends, every checkpoint signed and witnessed; and each passed `gaps verify`, and most
passed `--key` (and the forged tails `--against`), before issue 37."""
from __future__ import annotations

import json
import random
import shutil
from dataclasses import replace

import pytest

from store import Store
from store.keys import CheckpointKey, load_public, recorded_heads
from store.tail_check import TamperedTail
from tests.helpers.cli import gaps
from tests.helpers.trust_attacks import (
    attack, forge_tail, honest_append, honest_store, passes, perception, rows, stored_events, tamper,
)


@pytest.fixture(scope="module")
def honest(tmp_path_factory):
    return honest_store(tmp_path_factory.mktemp("honest"))


def attacked(honest, tmp_path, name, seed=0):
    done = attack(name, honest, tmp_path / "attacked.db", random.Random(seed))
    return done, passes(done, honest.public)


def test_the_untouched_store_passes_every_check(honest, tmp_path):
    _, found = attacked(honest, tmp_path, "none (untouched)")
    assert found == {"plain": True, "--key": True, "--against": True, "--key --against": True}


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_rewrite_keeping_the_checkpoint_ids_fails_key(honest, tmp_path, seed):
    """The ids of r1's checkpoints are below every id of r2's, where signing 'began' by the ids."""
    done, found = attacked(honest, tmp_path, "rewrite, ids kept", seed)
    with Store.open_read_only(done.db) as store:
        [spawned] = store.events("r1", kinds=["entity.spawn"])
    assert spawned["body"]["type"] == "car"  # the attack is real: the ambulance is gone
    assert found["plain"]  # and the file agrees with itself
    assert not found["--key"] and not found["--against"]


def test_a_rewrite_under_checkpoint_id_0_fails_plain_verify_and_key(honest, tmp_path):
    done, found = attacked(honest, tmp_path, "rewrite, id <= 0")
    assert rows(done.db, "SELECT id FROM checkpoints WHERE run = 'r2'")[0][0] <= 0
    assert found == {"plain": False, "--key": False, "--against": False, "--key --against": False}
    result = gaps("verify", "--no-snapshots", db=done.db)
    assert "which no append writes (ids start at 1)" in result.output


@pytest.mark.parametrize("seed", [0, 1])
def test_nulling_the_key_id_of_untouched_checkpoints_does_not_move_where_signing_began(honest, tmp_path, seed):
    done, found = attacked(honest, tmp_path, "rewrite tail, key_id nulled", seed)
    assert rows(done.db, "SELECT count(*) FROM checkpoints WHERE run = 'r1' AND key_id IS NOT NULL") == [(0,)]
    assert found["plain"] and not found["--key"] and not found["--against"]
    result = gaps("verify", "--no-snapshots", "--key", honest.public, db=done.db)
    assert "CHECKPOINT KEY" in result.output and "FAILED: run r1" in result.output


def test_a_rewrite_signed_by_another_key_fails_key(honest, tmp_path):
    done, found = attacked(honest, tmp_path, "rewrite, thief's key")
    assert found["plain"] and not found["--key"] and not found["--against"]


def test_a_deleted_run_fails_against_and_key_names_it_absent(honest, tmp_path):
    """A limit, stated in docs/guarantees.md: the key file records each run the key signed, in any
    store, so --key names a recorded run the store lacks without failing; the witness fails."""
    for seed in range(4):  # both runs are drawn
        done, found = attacked(honest, tmp_path, "run deleted", seed)
        assert found == {"plain": True, "--key": True, "--against": False, "--key --against": False}
        [gone] = {"r1", "r2"} - {run for (run,) in rows(done.db, "SELECT DISTINCT run FROM events")}
        result = gaps("verify", "--no-snapshots", "--key", honest.public, "--json", db=done.db)
        assert json.loads(result.stdout)["checkpoint_key"]["absent"] == [gone]
        text = gaps("verify", "--no-snapshots", "--key", honest.public, db=done.db)
        assert f"records 1 run(s) this store does not hold: {gone}" in text.output


def test_a_run_cut_back_to_a_signed_checkpoint_passes_key_and_fails_against(honest, tmp_path):
    """A limit, stated in docs/guarantees.md: what is left is signed; only a witness knows there was more."""
    done, found = attacked(honest, tmp_path, "truncation")
    assert found == {"plain": True, "--key": True, "--against": False, "--key --against": False}


@pytest.mark.parametrize("ident", [0, -1])
def test_an_append_with_key_and_witness_refuses_a_forged_tail_under_an_unsigned_checkpoint_at_id_0(
        honest, tmp_path, ident):
    """The issue's case: three forged events, r2's signed checkpoint replaced by an unsigned one at
    id 0. The ingest stored an honest event on top and signed checkpoint and witness head over the
    forgery; now it refuses (TamperedTail) and writes nothing."""
    copy, witness = tmp_path / "forged.db", tmp_path / "w.jsonl"
    shutil.copy(honest.db, copy)
    shutil.copy(honest.witness, witness)
    forge_tail(copy, random.Random(3), ident)
    before = stored_events(copy, "r2")
    assert not honest_append(replace(honest, witness=witness), copy)  # as gaps serve --checkpoint-key --witness
    assert stored_events(copy, "r2") == before
    assert witness.read_bytes() == honest.witness.read_bytes()  # no head signed over the forgery
    with Store(copy, checkpoint_key=honest.key(), witness=witness) as store:
        with pytest.raises(TamperedTail, match="under an id no append writes"):
            store.append([perception("r2", len(before), ["173 stopped"])])


def test_an_append_refuses_a_forged_tail_under_a_modern_unsigned_checkpoint_with_the_witness_alone(honest, tmp_path):
    """The witness's last head of r2 decides; the key file, which records r2's first head, too."""
    copy = tmp_path / "forged.db"
    shutil.copy(honest.db, copy)
    forge_tail(copy, random.Random(1), 100)
    for witness in (honest.witness, None):
        with Store(copy, checkpoint_key=honest.key(), witness=witness) as store:
            with pytest.raises(TamperedTail, match="though the run was signed up to 4|records one of the first signed heads"):
                store.append([perception("r2", 99)])


def test_a_forged_tail_under_an_unsigned_checkpoint_at_id_100_fails_against_alone(honest, tmp_path):
    """docs/store.md said a forged tail fails --against; under a modern unsigned checkpoint it did
    not (the store was 'an extension' of the witness's last head). Events past that head are
    proven by nothing in the witness: --against alone fails, naming them; the key says who wrote them."""
    done, found = attacked(honest, tmp_path, "forged tail, unsigned id 100")
    assert done.appended is False  # the honest append on top was refused
    assert found["plain"] and not found["--against"] and not found["--key"]
    result = gaps("verify", "--no-snapshots", "--against", done.witness, "--json", db=done.db)
    [r2] = [p for p in json.loads(result.stdout)["proven"] if p["run"] == "r2"]
    assert r2["witnessed"] == 4 and r2["events"] > 4 and not r2["ok"]
    assert "nothing outside the file vouches for them" in r2["what"]


def test_a_forged_tail_sealed_by_a_pre_fix_ingest_fails_against_and_key(honest, tmp_path):
    """Stores sealed before the fix (a checkpoint and a witness head signed by the real key over
    the forgery): the witness's heads of r2 no longer follow one another, and a checkpoint after
    r2's first signed head is unsigned."""
    for seed in (0, 1):
        done, found = attacked(honest, tmp_path, "forged tail sealed (pre-fix ingest)", seed)
        assert not found["--against"] and not found["--key"]
        result = gaps("verify", "--no-snapshots", "--against", done.witness, "--json", db=done.db)
        assert "unwitnessed link" in {h["outcome"] for h in json.loads(result.stdout)["heads"]["checked"]}


def test_a_witness_copied_before_the_last_appends_needs_the_key_for_the_tail(honest, tmp_path):
    """Not an attack: the store grew after the investigator copied the witness. The witness proves
    what it saw; the key proves the rest; the report says which proves what."""
    done, found = attacked(honest, tmp_path, "none (witness copied before the last appends)")
    assert found == {"plain": True, "--key": True, "--against": False, "--key --against": True}
    result = gaps("verify", "--no-snapshots", "--against", done.witness, "--key", honest.public, db=done.db)
    events = len(stored_events(done.db, "r2"))
    assert f"run r2: {events} events; proven: 4 by the witness's heads, {events} by checkpoints signed by the key" \
        in result.output


def test_the_key_file_records_each_runs_first_signed_head_once(honest, tmp_path):
    public = load_public(honest.public)
    heads = recorded_heads(honest.public, public)
    assert [(h.run, h.size, h.prev_size) for h in heads] == [("r1", 8, 0), ("r2", 4, 0)]
    copy, witness = tmp_path / "s.db", tmp_path / "w.jsonl"
    shutil.copy(honest.db, copy)
    shutil.copy(honest.witness, witness)
    key_file = honest.key_path.with_name("ckpt.key.pub")
    before = key_file.read_text()
    assert honest_append(replace(honest, witness=witness), copy)  # r2 goes on: already recorded
    assert key_file.read_text() == before
    (tmp_path / "bad.pub").write_text(before.replace('"size":4', '"size":5'))
    result = gaps("verify", "--no-snapshots", "--key", tmp_path / "bad.pub", db=copy)
    assert result.exit_code == 2 and "bad.pub:3" in result.output  # an edited line is refused, not believed


def test_a_run_never_signed_may_begin_to_be_and_a_run_stripped_of_its_signatures_may_not(tmp_path):
    """A run written before the key: signing begins at its next append, and the key file records
    where. The same run with its signatures stripped by the file's holder is refused: the key file
    says it was signed."""
    key_path = tmp_path / "k"
    CheckpointKey.create(key_path)
    db = tmp_path / "s.db"
    with Store(db) as store:
        store.append([perception("r1", i) for i in range(3)])
    with Store(db, checkpoint_key=CheckpointKey.load(key_path)) as store:
        store.append([perception("r1", 3)])
    [first] = recorded_heads(tmp_path / "k.pub", load_public(tmp_path / "k.pub"))
    assert (first.run, first.size, first.prev_size) == ("r1", 4, 3)
    result = gaps("verify", "--no-snapshots", "--key", tmp_path / "k.pub", "--json", db=db)
    assert result.exit_code == 0
    assert json.loads(result.stdout)["checkpoint_key"]["runs"][0]["unsigned_before"] == 1
    tamper(db, [("UPDATE checkpoints SET signature = NULL, key_id = NULL", ())])
    with Store(db, checkpoint_key=CheckpointKey.load(key_path)) as store:
        with pytest.raises(TamperedTail, match="its signatures were stripped or it was rewritten"):
            store.append([perception("r1", 4)])
    assert gaps("verify", "--no-snapshots", "--key", tmp_path / "k.pub", db=db).exit_code == 1


def test_key_fails_for_a_run_no_checkpoint_of_which_is_signed(tmp_path):
    """--key vouches for every run it checks: a run it never signed is not proven by it, and says so."""
    key_path = tmp_path / "k"
    CheckpointKey.create(key_path)
    db = tmp_path / "s.db"
    with Store(db) as store:
        store.append([perception("old", i) for i in range(2)])
    with Store(db, checkpoint_key=CheckpointKey.load(key_path)) as store:
        store.append([perception("new", i) for i in range(2)])
    result = gaps("verify", "--no-snapshots", "--key", tmp_path / "k.pub", db=db)
    assert result.exit_code == 1 and "run old: no checkpoint is signed by key" in result.output
    assert gaps("verify", "--no-snapshots", "--key", tmp_path / "k.pub", "--run", "new", db=db).exit_code == 0


def test_a_key_file_that_cannot_be_written_does_not_fail_the_append_and_says_why(tmp_path):
    """The commit is done when the key file is written: the append stands, `trust_problem` says
    why the run's first head is not recorded, and the next signed append tries again."""
    key_path = tmp_path / "k"
    CheckpointKey.create(key_path)
    public = tmp_path / "k.pub"
    text = public.read_text()
    public.unlink()
    public.symlink_to(tmp_path / "gone")  # a file that cannot be opened to append to (even by root)
    with Store(tmp_path / "s.db", checkpoint_key=CheckpointKey.load(key_path)) as store:
        assert store.append([perception("r1", 0)]).stored == 1
        assert "cannot record the first signed heads" in store.trust_problem
        public.unlink()
        public.write_text(text)
        assert store.append([perception("r1", 1)]).stored == 1
        assert store.trust_problem is None
    assert [h.size for h in recorded_heads(public, load_public(public))] == [2]


def test_one_key_signing_runs_of_one_name_in_two_stores_records_a_first_head_for_each(tmp_path):
    """The key file records runs by name, as heads do; a key that signs an r1 in two stores records
    the first head of each, and each store's r1 must extend one of them: both go on, both verify."""
    key_path = tmp_path / "k"
    CheckpointKey.create(key_path)
    for name, facts in (("a.db", ["173 has red light"]), ("b.db", ["173 has green light"])):
        for seq in range(3):  # three connections: the second and third read the run from the file
            with Store(tmp_path / name, checkpoint_key=CheckpointKey.load(key_path)) as store:
                assert store.append([perception("r1", seq, facts)]).stored == 1
    heads = recorded_heads(tmp_path / "k.pub", load_public(tmp_path / "k.pub"))
    assert [(h.run, h.size) for h in heads] == [("r1", 1), ("r1", 1)] and heads[0].root != heads[1].root
    for name in ("a.db", "b.db"):
        result = gaps("verify", "--no-snapshots", "--key", tmp_path / "k.pub", "--json", db=tmp_path / name)
        assert result.exit_code == 0, result.output
        assert json.loads(result.stdout)["checkpoint_key"]["runs"][0]["recorded"]


def test_the_report_says_per_run_what_the_witness_and_the_key_prove(honest, tmp_path):
    """r2's checkpoint stripped of its signature, its events untouched: the witness still proves
    all of r2, the key fails it, and r2 is not reported proven; r1 is, by both."""
    copy = tmp_path / "s.db"
    shutil.copy(honest.db, copy)
    tamper(copy, [("UPDATE checkpoints SET signature = NULL, key_id = NULL WHERE run = 'r2'", ())])
    result = gaps("verify", "--no-snapshots", "--json", "--key", honest.public, "--against", honest.witness, db=copy)
    assert result.exit_code == 1
    proven = {p["run"]: p for p in json.loads(result.stdout)["proven"]}
    assert proven["r1"] == {"run": "r1", "events": 26, "witnessed": 26, "signed": 26, "proven": 26, "ok": True,
                            "what": None}
    assert proven["r2"]["witnessed"] == 4 and proven["r2"]["signed"] == 0 and not proven["r2"]["ok"]
    assert "the checkpoint of 4 events is unsigned" in proven["r2"]["what"]


def test_an_append_without_the_key_does_not_extend_a_signed_run(honest, tmp_path):
    """Once a run is signed, every later checkpoint is: a writer without the key would leave it
    unsigned from there on (and --key failing on it), so it refuses and writes nothing; a new run
    it may write."""
    copy = tmp_path / "s.db"
    shutil.copy(honest.db, copy)
    with Store(copy) as store:
        with pytest.raises(TamperedTail, match="an append without the checkpoint key would leave it unsigned"):
            store.append([perception("r2", 4)])
        assert store.append([perception("r3", 0)]).stored == 1
    assert len(stored_events(copy, "r2")) == 4


def test_a_head_missing_from_the_witness_is_accounted_for_by_the_key_only(honest, tmp_path):
    """A witness write that failed leaves a gap in the run's heads: the witness alone cannot tell
    it from a sealed forgery and fails; checkpoints the key signed over the gap account for it."""
    lines = honest.witness.read_text().splitlines(keepends=True)
    r1 = [i for i, line in enumerate(lines) if json.loads(line)["run"] == "r1"]
    gapped = tmp_path / "gapped.jsonl"
    gapped.write_text("".join(line for i, line in enumerate(lines) if i != r1[2]))
    alone = gaps("verify", "--no-snapshots", "--json", "--against", gapped, db=honest.db)
    assert alone.exit_code == 1
    assert [h["outcome"] for h in json.loads(alone.stdout)["heads"]["checked"] if not h["ok"]] == ["unwitnessed link"]
    keyed = gaps("verify", "--no-snapshots", "--against", gapped, "--key", honest.public, db=honest.db)
    assert keyed.exit_code == 0, keyed.output
