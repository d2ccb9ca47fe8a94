"""`gaps keys checkpoint`, `gaps import --checkpoint-key --witness` and `gaps verify --against
HEADS --key PUB`: a store cut back, rewritten or extended behind the ingest's back fails verify
(exit 1) against heads kept outside it, in text and JSON; bad files are one message, exit 2."""
from __future__ import annotations

import json
import shutil

import pytest
from tests.helpers.store_testkit import event, old_schema, tamper

from tests.helpers.cli import gaps


@pytest.fixture
def signed(tmp_path):
    """(store, witness file, public key file) of an import signed and witnessed."""
    made = gaps("keys", "checkpoint", tmp_path / "ckpt.key")
    assert made.exit_code == 0, made.output
    source = tmp_path / "events.jsonl"
    source.write_text("".join(json.dumps(e) + "\n" for e in [event(i) for i in range(30)]
                              + [event(i, run="r2") for i in range(4)]))
    db = tmp_path / "s.db"
    imported = gaps("import", source, "--checkpoint-key", tmp_path / "ckpt.key", "--witness", tmp_path / "w.jsonl",
                    db=db)
    assert imported.exit_code == 0, imported.output
    return db, tmp_path / "w.jsonl", tmp_path / "ckpt.key.pub"


def test_keys_checkpoint_makes_a_key_and_its_public_half_and_never_overwrites(tmp_path):
    made = gaps("keys", "checkpoint", tmp_path / "k", "--json")
    assert made.exit_code == 0
    info = json.loads(made.stdout)
    assert (tmp_path / "k").stat().st_mode & 0o077 == 0 and (tmp_path / "k.pub").is_file()
    again = gaps("keys", "checkpoint", tmp_path / "k")
    assert again.exit_code == 2 and "never overwritten" in again.output
    assert len(info["key"]) == 16


def test_verify_against_an_untouched_store_passes(signed):
    db, witness, public = signed
    result = gaps("verify", "--against", witness, "--key", public, "--json", db=db)
    assert result.exit_code == 0, result.output
    report = json.loads(result.stdout)
    assert report["ok"] and report["heads"]["ok"] and report["checkpoint_key"]["ok"]
    assert {(h["run"], h["size"]) for h in report["heads"]["checked"]} == {("r1", 30), ("r2", 4)}
    text = gaps("verify", "--against", witness, "--key", public, db=db)
    assert "2 tree heads of 2 run(s)" in text.output and "checkpoint key" in text.output


def test_verify_against_catches_a_deleted_run_that_plain_verify_does_not(signed):
    db, witness, public = signed
    tamper(db, ("DELETE FROM events WHERE run = 'r2'", ()), ("DELETE FROM checkpoints WHERE run = 'r2'", ()))
    assert gaps("verify", "--no-snapshots", db=db).exit_code == 0  # the file agrees with itself
    result = gaps("verify", "--against", witness, "--key", public, "--no-snapshots", "--json", db=db)
    assert result.exit_code == 1
    [bad] = [h for h in json.loads(result.stdout)["heads"]["checked"] if not h["ok"]]
    assert bad["run"] == "r2" and bad["outcome"] == "run missing" and bad["stored"] == 0
    text = gaps("verify", "--against", witness, "--no-snapshots", db=db)
    assert text.exit_code == 1 and "HEAD FAILED: run r2 at 4 events (run missing)" in text.output


def test_verify_key_fails_on_a_checkpoint_not_signed_by_it(signed, tmp_path):
    db, _, public = signed
    tamper(db, ("INSERT INTO checkpoints (run, count, head, created_at, merkle_root, frontier, prev_count) "
                "SELECT run, count, head, created_at, merkle_root, frontier, prev_count FROM checkpoints "
                "WHERE run = 'r2'", ()))
    result = gaps("verify", "--key", public, "--no-snapshots", db=db)
    assert result.exit_code == 1
    assert "FAILED" in result.output and "unsigned" in result.output


def test_bad_witness_or_key_files_are_one_message_exit_2(signed, tmp_path):
    db, witness, public = signed
    (tmp_path / "junk.jsonl").write_text('{"run": "r1"}\n')
    result = gaps("verify", "--against", tmp_path / "junk.jsonl", db=db)
    assert result.exit_code == 2 and "junk.jsonl:1" in result.output and "Traceback" not in result.output
    result = gaps("verify", "--key", witness, db=db)
    assert result.exit_code == 2 and "not a public key" in result.output
    result = gaps("import", witness, "--witness", tmp_path / "w2", db=db)
    assert result.exit_code == 2 and "--checkpoint-key" in result.output


def test_import_onto_a_forged_tail_is_refused(signed, tmp_path):
    db, _, _ = signed
    copy = tmp_path / "forged.db"
    shutil.copy(db, copy)
    tamper(copy, ("DELETE FROM checkpoints WHERE run = 'r2' AND count = 4", ()))
    more = tmp_path / "more.jsonl"
    more.write_text(json.dumps(event(4, run="r2")) + "\n")
    result = gaps("import", more, "--checkpoint-key", tmp_path / "ckpt.key", db=copy)
    assert result.exit_code == 1 and "were not written by an append" in result.output


def test_gaps_migrate_brings_a_v6_store_to_signed_checkpoints(tmp_path):
    old, written = tmp_path / "v6.db", tmp_path / "written.db"
    from store import Store
    with Store(written) as store:
        store.append([event(i) for i in range(3)])
    conn = old_schema(old, 6)       # schema 6, as gaps wrote it, with those rows
    conn.execute("ATTACH DATABASE ? AS w", (str(written),))
    conn.execute("INSERT INTO events SELECT run, chain_pos, src, seq, t, kind, event, hash FROM w.events")
    conn.execute("INSERT INTO checkpoints (id, run, count, head, created_at, merkle_root, frontier, prev_count) "
                 "SELECT id, run, count, head, created_at, merkle_root, frontier, prev_count FROM w.checkpoints")
    conn.close()
    assert gaps("verify", db=old).exit_code == 2  # a reader refuses an older schema and says to migrate
    new = tmp_path / "v7.db"
    migrated = gaps("migrate", old, new)
    assert migrated.exit_code == 0, migrated.output
    assert gaps("keys", "checkpoint", tmp_path / "k").exit_code == 0
    more = tmp_path / "more.jsonl"
    more.write_text(json.dumps(event(3)) + "\n")
    assert gaps("import", more, "--checkpoint-key", tmp_path / "k", "--witness", tmp_path / "w", db=new).exit_code == 0
    result = gaps("verify", "--against", tmp_path / "w", "--key", tmp_path / "k.pub", "--json", db=new)
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["checkpoint_key"]["unsigned_before"] == 1


def test_verify_against_and_key_catch_liveliness_cut_back_that_plain_verify_does_not(tmp_path):
    """The wire tables are anchored too (schema v8): the last liveliness change (a source gone)
    cut off with its wire checkpoint and the checkpoints' record of it passes plain verify, not
    --against nor --key."""
    from store import Store
    from store.keys import CheckpointKey, WitnessFile
    from store.wire import LivelinessChange
    key = CheckpointKey.create(tmp_path / "ckpt.key")
    db, witness = tmp_path / "s.db", WitnessFile(tmp_path / "w.jsonl")
    with Store(db, checkpoint_key=key) as store:
        store.add_checkpoint_hook(witness.append)
        store.append([event(i) for i in range(3)])
        store.record_wire([LivelinessChange("r1", "vehicle/173", True, 10, None)])
        store.record_wire([LivelinessChange("r1", "vehicle/173", False, 20, 2)])
        store.append([event(3)])
    witness.close()
    text = gaps("verify", "--against", tmp_path / "w.jsonl", "--no-snapshots", db=db)
    assert text.exit_code == 0 and "(each with the wire tables' and the rulebooks' ends)" in text.output
    tamper(db, ("DELETE FROM liveliness WHERE id = 2", ()),
           ("DELETE FROM wire_checkpoints WHERE tbl = 'liveliness' AND through_id = 2", ()))
    plain = gaps("verify", "--no-snapshots", db=db)  # the checkpoint after it records the longer chain
    assert plain.exit_code == 1 and "liveliness holds no row 2" in plain.output
    tamper(db, ("UPDATE checkpoints SET wire = NULL", ()))  # that record dropped too
    assert gaps("verify", "--no-snapshots", db=db).exit_code == 0  # the file agrees with itself
    result = gaps("verify", "--against", tmp_path / "w.jsonl", "--key", tmp_path / "ckpt.key.pub",
                  "--no-snapshots", "--json", db=db)
    assert result.exit_code == 1
    report = json.loads(result.stdout)
    [bad] = [h for h in report["heads"]["checked"] if not h["ok"]]
    assert (bad["size"], bad["outcome"], bad["wire"]) == (4, "wire cut back", "checked")
    assert not report["checkpoint_key"]["ok"] and "does not match" in report["checkpoint_key"]["problem"]["what"]
    text = gaps("verify", "--against", tmp_path / "w.jsonl", "--no-snapshots", db=db)
    assert text.exit_code == 1 and "HEAD FAILED: run r1 at 4 events (wire cut back): liveliness holds no row 2" \
        in text.output


def test_verify_catches_a_stored_rulebooks_version_changed_and_against_and_key_when_covered_up(tmp_path):
    """The rulebooks table is anchored too: a stored rulebook's version changed (a report would
    show it) fails plain verify, naming the table; with the checkpoints' record of the rulebooks'
    end changed to match, --against and --key."""
    from store import Store
    from store.keys import CheckpointKey, WitnessFile
    from store.wire.ends import ends_now, to_part
    key = CheckpointKey.create(tmp_path / "ckpt.key")
    db, witness = tmp_path / "s.db", WitnessFile(tmp_path / "w.jsonl")
    with Store(db, checkpoint_key=key) as store:
        store.add_checkpoint_hook(witness.append)
        sha = store.put_rulebook("highway code", "2024.1", "the templates are:\n*a vehicle* must stop.\n")
        store.append([event(i) for i in range(3)])
    witness.close()
    text = gaps("verify", "--against", tmp_path / "w.jsonl", "--no-snapshots", db=db)
    assert text.exit_code == 0 and "each with the wire tables' and the rulebooks' ends" in text.output
    tamper(db, ("UPDATE rulebooks SET version = '2019.3' WHERE sha256 = ?", (sha,)))
    plain = gaps("verify", "--no-snapshots", db=db)
    assert plain.exit_code == 1 and "rulebooks row 1" in plain.output and "(rulebooks rewritten)" in plain.output
    with Store.open_read_only(db) as store:
        now = to_part(ends_now(store.connection))
    tamper(db, ("UPDATE checkpoints SET wire = ?", (json.dumps(now),)))  # the record rewritten to match
    assert gaps("verify", "--no-snapshots", db=db).exit_code == 0  # the file agrees with itself
    result = gaps("verify", "--against", tmp_path / "w.jsonl", "--key", tmp_path / "ckpt.key.pub",
                  "--no-snapshots", "--json", db=db)
    assert result.exit_code == 1
    report = json.loads(result.stdout)
    [bad] = report["heads"]["checked"]
    assert (bad["outcome"], bad["rulebooks"]) == ("rulebooks rewritten", "checked")
    assert not report["checkpoint_key"]["ok"]
    text = gaps("verify", "--key", tmp_path / "ckpt.key.pub", "--no-snapshots", db=db)
    assert text.exit_code == 1 and "CHECKPOINT KEY" in text.output and "does not match" in text.output
