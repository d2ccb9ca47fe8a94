"""Signed events over Zenoh: a publisher that signs, an ingest that requires signatures and
quarantines the unsigned, the forged and the misattributed with the reason and their bytes, and
goes on; and an ingest that does not require them, which stores signatures as they came."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from ingest import IngestService
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store, canonical_json
from store.keys import KeyFolder, Signer, TrustedKeys, sign_event
from tests.helpers.ingest_testkit import RUN, await_match, free_endpoint, linked, make_event

WAIT_S = 20.0


@pytest.fixture
def keys(tmp_path: Path) -> KeyFolder:
    folder = KeyFolder(tmp_path / "keys")
    for src in ("vehicle/173", "vehicle/174"):
        folder.create(src)
    return folder


@pytest.fixture
def trusted(keys: KeyFolder) -> TrustedKeys:
    return TrustedKeys.load(keys.write_public_keys())


def quarantine(db: Path) -> list[tuple[str, bytes]]:
    with Store.open_read_only(db) as store:
        return [(row["reason"], row["raw"]) for row in store.quarantined()]


def test_required_signatures_quarantine_unsigned_forged_and_misattributed(db_path, keys, trusted):
    from nacl.signing import SigningKey
    signer = Signer(keys)
    good = [signer.sign(make_event("vehicle/173", seq)) for seq in (0, 1)]
    unsigned = make_event("vehicle/173", 2)
    forged = {**signer.sign(make_event("vehicle/173", 3)), "body": {"facts": ["173 has green light"]}}
    as_another = sign_event(make_event("vehicle/173", 4), SigningKey(keys.seed("vehicle/174")))
    after = signer.sign(make_event("vehicle/173", 5))
    with linked(db_path, "ingest-listens", trusted_keys=trusted) as (publisher, ingest):
        await_match(publisher, good[0])
        publisher.publish_all([*good, unsigned, forged, as_another, after])
        assert ingest.wait_until_settled(6, WAIT_S), ingest.stats()
        stats = ingest.stats()
    assert (stats["stored"], stats["rejected"], stats["signature_refused"]) == (3, 3, 3)
    with Store.open_read_only(db_path) as store:
        assert [ev["seq"] for ev in store.events(RUN)] == [0, 1, 5]          # the stream went on
        assert all("sig" in ev for ev in store.events(RUN))
    refused = quarantine(db_path)
    assert [raw for _, raw in refused] == [canonical_json(ev) for ev in (unsigned, forged, as_another)]
    reasons = [reason for reason, _ in refused]
    assert reasons[0] == f"event run={RUN} src=vehicle/173 seq=2: unsigned, and signatures are required"
    assert "seq=3: signed with key" in reasons[1] and "altered after signing, or forged" in reasons[1]
    assert "seq=4: signed with key" in reasons[2] and "trusted for vehicle/174, not for vehicle/173" in reasons[2]


def test_a_refused_event_still_counts_as_arrived_for_the_gaps(db_path, trusted):
    with linked(db_path, "ingest-listens", trusted_keys=trusted) as (publisher, ingest):
        await_match(publisher, make_event("vehicle/173", 0))
        publisher.publish_all([make_event("vehicle/173", seq) for seq in range(3)])
        assert ingest.wait_until_settled(3, WAIT_S)
        assert ingest.stats()["signature_refused"] == 3 and ingest.gaps() == []


def test_without_the_requirement_signatures_are_stored_as_they_came(db_path, keys):
    endpoint = free_endpoint()
    with IngestService(db_path, listen=[endpoint]) as ingest:
        with EventPublisher(config=zenoh_config(connect=[endpoint]), signer=Signer(keys)) as publisher:
            await_match(publisher, make_event("vehicle/173", 0))
            publisher.publish_all([make_event("vehicle/173", 0), make_event("vehicle/174", 0)])
        assert ingest.wait_until_stored(2, WAIT_S)
        assert ingest.stats()["signature_refused"] == 0
    with Store.open_read_only(db_path) as store:
        events = list(store.events(RUN))
    assert [ev["sig"]["key"] for ev in events] == [Signer(keys).sign(ev)["sig"]["key"] for ev in events]
    with Store.open_read_only(db_path) as store:
        assert store.verify(keys=TrustedKeys.load(keys.write_public_keys())).signatures.valid == 2


def test_a_bad_keys_file_stops_serve_before_it_opens_anything(tmp_path):
    from ingest.serve import Server, ServeOptions
    from store.keys import KeysError
    bad = tmp_path / "keys.json"
    bad.write_text(json.dumps({"vehicle/1": "AAAA"}))
    with pytest.raises(KeysError, match="an Ed25519 public key is 32"):
        with Server(ServeOptions(tmp_path / "s.db", listen=(free_endpoint(),), require_signatures=bad)):
            pass
    assert not (tmp_path / "s.db").exists()
