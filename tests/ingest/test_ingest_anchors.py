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
from store import CheckpointKey, GapsError, Store, canonical_json, read_heads, session_config
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
