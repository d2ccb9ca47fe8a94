"""docs/serve.md's hardened deployment on loopback, from the docs' own files: a Zenoh router with
mutual TLS and an access control list, `gaps serve` as its client requiring signatures, a
permitted producer and reader, and two strangers: one with a certificate of the same authority
that the list does not name, one with none. The producer's events are stored (those published
before the serve started recovered from its cache through the router), the reader gets them; the
stranger's puts, pre-published next seqs, liveliness token and history query get nothing, and
the one without a certificate is not let in at all; a history answer comes from the ingest only,
never from a stranger's or a producer's queryable on `gaps/**`, and a stranger's fake cache is
never asked (issue 37)."""
from __future__ import annotations

import json
import signal
import time
from pathlib import Path

import pytest
import zenoh

from sim_replay.publisher import EventPublisher
from store import KeyFolder, Signer, Store, canonical_json, session_config
from tests.helpers.cli import gaps
from tests.helpers.hardened import deployment, openssl
from tests.helpers.ingest_testkit import RUN, make_event
from tests.helpers.serve_testkit import ServeProcess

pytestmark = pytest.mark.skipif(openssl() is None, reason="needs the openssl command to make certificates")
WAIT_S = 20.0


def _stored(db: Path) -> list[tuple[str, int]]:
    with Store.open_read_only(db) as store:
        return [(e["src"], e["seq"]) for e in store.events(RUN)]


def _history(session: zenoh.Session) -> list[bytes]:
    return [r.ok.payload.to_bytes() for r in session.get("gaps/**", target=zenoh.QueryTarget.ALL,
                                                          consolidation=zenoh.ConsolidationMode.NONE, timeout=3)
            if r.ok is not None]


FORGED = make_event("vehicle/173", 99, facts=["173 has green light"])
FAKE_CACHE = "0123456789abcdef0123456789abcdef"


def _answer_forged(query: zenoh.Query) -> None:
    query.reply(f"gaps/{RUN}/vehicle/173/vehicle.perception", canonical_json(FORGED))


def test_only_the_permitted_publish_read_and_appear(tmp_path: Path) -> None:
    made = deployment(tmp_path / "deploy")
    keys = KeyFolder(tmp_path / "keys")
    for src in ("vehicle/173", "vehicle/174"):
        keys.create(src)
    public = keys.write_public_keys()
    signer = Signer(keys)
    db = tmp_path / "gaps.db"
    router = zenoh.open(session_config(config_file=made.config("router")))
    try:
        producer = EventPublisher(config=session_config(config_file=made.config("producer")), signer=signer)
        producer.publish_all([make_event("vehicle/173", seq) for seq in range(5)])    # before any serve: cached
        producer_history = producer.session.declare_queryable("gaps/**", _answer_forged)   # a producer is no ingest
        stranger = zenoh.open(session_config(config_file=made.config("stranger")))
        faker = zenoh.open(session_config(config_file=made.config("stranger")))   # its accomplice, another session
        fakes = [faker.declare_queryable("gaps/**", _answer_forged),           # answers history queries
                 faker.declare_queryable(f"gaps/@cache/{FAKE_CACHE}/**", _answer_forged),   # and the ingest
                 faker.liveliness().declare_token(f"gaps/@cache/{FAKE_CACHE}")]
        serve = ServeProcess(db, None, "--config", str(made.config("ingest")), "--require-signatures", str(public),
                             "--json")
        try:
            ready = serve.wait_for_log("serve.ready")
            assert ready["beyond_loopback"] == [] and ready["authenticated_by"] == ["mutual TLS"], ready
            try:
                for seq in range(5, 10):     # as vehicle/173, its next seqs, before it publishes them
                    stranger.put(f"gaps/{RUN}/vehicle/173/vehicle.perception",
                                 canonical_json(make_event("vehicle/173", seq, facts=["173 has green light"])))
                token = stranger.liveliness().declare_token(f"gaps/@live/{RUN}/vehicle/174")
                assert _history(stranger) == []
                with pytest.raises(zenoh.ZError):      # no certificate: not let in
                    zenoh.open(session_config(config_file=made.config("outsider"))).close()
                producer.publish_all([make_event("vehicle/173", seq) for seq in range(5, 10)])
                assert producer.sync() == 1                # the serve has them all
                reader = zenoh.open(session_config(config_file=made.config("reader")))
                try:
                    answered = _history(reader)
                finally:
                    reader.close()
                fetched = gaps("fetch", "gaps/**", "--config", made.config("reader"), "--json", db=tmp_path / "copy.db")
                producer_history.undeclare()
                producer.close()
                time.sleep(0.3)
                token.undeclare()
            finally:
                for fake in fakes:
                    fake.undeclare()
                faker.close()
                stranger.close()
            code, out = serve.stop(signal.SIGTERM)
        finally:
            serve.kill()
    finally:
        router.close()
    assert code == 0, serve.lines[-5:]
    metrics = json.loads(out)
    assert _stored(db) == [("vehicle/173", seq) for seq in range(10)]
    assert sorted(answered) == sorted(canonical_json(signed) for signed in
                                      (Signer(keys).sign(make_event("vehicle/173", seq)) for seq in range(10)))
    assert fetched.exit_code == 0, fetched.output
    assert json.loads(fetched.stdout)["stored"] == 10 and _stored(tmp_path / "copy.db") == _stored(db)
    assert metrics["quarantined"] == 0 and metrics["received"] - metrics["recovered"] <= 10, metrics  # nothing of the stranger's
    assert metrics["recovered"] >= 5, metrics
    with Store.open_read_only(db) as store:
        assert store.liveliness_changes(RUN, "vehicle/174") == []
        assert [c.alive for c in store.liveliness_changes(RUN, "vehicle/173")][:1] == [True]
