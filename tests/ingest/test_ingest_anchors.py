"""The ingest with a checkpoint key: every checkpoint signed, each signed tree head appended to a
witness file and put on gaps/@heads/<run>; and a store whose run was extended behind its back is
not sealed: the events of that run go to quarantine naming why, and the forged tail stays uncovered."""
from __future__ import annotations

import json
import threading
from pathlib import Path

import pytest
import zenoh

from ingest import IngestService
from ingest.serve import ServeOptions, Server
from sim_replay.publisher import EventPublisher, zenoh_config
from store import GapsError, Store, canonical_json
from store.keys import CheckpointKey, WitnessFile, read_heads
from store.wire import session_config
from store.chain import link
from tests.helpers.ingest_testkit import RUN, await_match, free_endpoint, linked, make_event
from tests.helpers.store_testkit import rows, tamper

WAIT_S = 20.0


@pytest.fixture
def key(tmp_path: Path) -> CheckpointKey:
    return CheckpointKey.create(tmp_path / "ckpt.key")


def test_signed_heads_go_to_the_witness_file_and_zenoh(db_path, tmp_path, key):
    endpoint = free_endpoint()
    witness = tmp_path / "w.jsonl"
    got, seen = [], threading.Event()

    def heard(sample):
        got.append(json.loads(sample.payload.to_bytes()))
        seen.set()

    with IngestService(db_path, listen=[endpoint], checkpoint_key=key, witness=witness, publish_heads=True) as ingest:
        listener = zenoh.open(session_config(connect=[endpoint]))
        try:
            listener.declare_subscriber("gaps/@heads/**", heard)
            with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
                await_match(publisher, make_event("vehicle/173", 0))
                publisher.publish_all([make_event("vehicle/173", seq) for seq in range(5)])
                assert ingest.wait_until_stored(5, WAIT_S), ingest.stats()
                assert seen.wait(WAIT_S)
        finally:
            listener.close()
    heads = read_heads(witness)
    assert heads and heads[-1].size == 5 and heads[-1].run == RUN
    assert all(h.signature_problem(key.public) is None for h in heads)
    assert got[0] == heads[0].to_json()
    with Store.open_read_only(db_path) as store:
        outcomes, keyed = store.check_anchors(heads, key.public)
    assert all(o.ok for o in outcomes) and keyed.ok


def test_the_ingest_does_not_seal_a_forged_tail(db_path, tmp_path, key):
    with Store(db_path, checkpoint_key=key) as store:
        store.append([make_event("vehicle/173", seq) for seq in range(3)])
    (last,) = rows(db_path, "SELECT hash FROM events ORDER BY chain_pos DESC LIMIT 1")
    forged = make_event("vehicle/173", 3)
    text = canonical_json(forged)
    tamper(db_path, ("INSERT INTO events VALUES (?, 3, ?, 3, ?, ?, ?, ?)",
                     (RUN, forged["src"], forged["t"], forged["kind"], text.decode(),
                      link(bytes.fromhex(last[0]), text).hex())))
    with linked(db_path, "ingest-listens", checkpoint_key=key) as (publisher, ingest):
        await_match(publisher, make_event("vehicle/173", 4))
        publisher.publish_all([make_event("vehicle/173", 4)])
        assert ingest.wait_until_settled(1, WAIT_S), ingest.stats()
        stats = ingest.stats()
    assert stats["stored"] == 0 and stats["rejected"] == 1 and stats["errors"] >= 1
    assert "were not written by an append" in stats["last_errors"][-1]
    with Store.open_read_only(db_path) as store:
        [refused] = store.quarantined()
        assert "TamperedTail" in refused["reason"] and refused["raw"] == canonical_json(make_event("vehicle/173", 4))
        assert store.checkpoints(RUN)[-1]["count"] == 3  # the forged event stays uncovered: verify names it
        assert not store.verify().ok


def test_a_witness_without_a_checkpoint_key_is_refused(tmp_path):
    options = ServeOptions(tmp_path / "s.db", listen=(free_endpoint(),), witness=tmp_path / "w.jsonl")
    with pytest.raises(GapsError, match="--checkpoint-key"):
        with Server(options):
            pass


def test_the_ingest_with_key_and_witness_does_not_seal_a_forged_tail_under_an_unsigned_checkpoint_at_id_0(
        db_path, tmp_path):
    """Issue 37: three forged events, the run's signed checkpoint replaced by an unsigned one at id 0
    (the form of a checkpoint written before signing). `gaps serve --checkpoint-key --witness` stored
    an honest event on top and signed checkpoint and witness head over the forgery. The witness's
    last head of the run (and the key file's record of it) now decides: the event is quarantined
    naming why, no head is signed, and the forgery stays uncovered."""
    key_path = tmp_path / "ckpt.key"
    CheckpointKey.create(key_path)
    witness = tmp_path / "w.jsonl"
    with IngestService(db_path, listen=[free_endpoint()], checkpoint_key=CheckpointKey.load(key_path),
                       witness=witness):
        pass  # opens and closes: the witness file exists, empty
    sink = WitnessFile(witness)
    with Store(db_path, checkpoint_key=CheckpointKey.load(key_path)) as store:
        store.add_checkpoint_hook(sink.append)
        store.append([make_event("vehicle/173", seq) for seq in range(3)])
    sink.close()
    events = [make_event("vehicle/173", seq) for seq in range(6)]
    statements, head = [("DELETE FROM events", ()), ("DELETE FROM checkpoints", ())], bytes(32)
    for pos, ev in enumerate(events):
        text = canonical_json(ev)
        head = link(head, text)
        statements.append(("INSERT INTO events VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                           (RUN, pos, ev["src"], ev["seq"], ev["t"], ev["kind"], text.decode(), head.hex())))
    statements.append(("INSERT INTO checkpoints (id, run, count, head, created_at) VALUES (0, ?, 6, ?, 0)",
                       (RUN, head.hex())))
    tamper(db_path, *statements)
    witnessed = witness.read_bytes()
    with linked(db_path, "ingest-listens", checkpoint_key=CheckpointKey.load(key_path), witness=witness) as (
            publisher, ingest):
        await_match(publisher, make_event("vehicle/173", 6))
        publisher.publish_all([make_event("vehicle/173", 6)])
        assert ingest.wait_until_settled(1, WAIT_S), ingest.stats()
        stats = ingest.stats()
    assert stats["stored"] == 0 and stats["rejected"] == 1
    assert witness.read_bytes() == witnessed  # no head signed over the forgery
    with Store.open_read_only(db_path) as store:
        [refused] = store.quarantined()
        assert "TamperedTail" in refused["reason"]
        assert [c["count"] for c in store.checkpoints(RUN)] == [6]
