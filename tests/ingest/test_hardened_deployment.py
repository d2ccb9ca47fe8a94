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
from sim_replay.replay import replay as replay_runs
from store import Store, canonical_json
from store.keys import CheckpointKey, KeyFolder, Signer, read_heads
from store.wire import session_config
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


def _events(db: Path, run: str) -> list[bytes]:
    with Store.open_read_only(db) as store:
        return [canonical_json(e) for e in store.events(run)]


def test_gaps_sim_and_gaps_replay_join_with_the_producers_certificate(tmp_path: Path, monkeypatch) -> None:
    """`gaps sim --config producer.json5` and `gaps replay --config producer.json5` publish through
    the TLS router into the serve (issue 37: they took endpoints only, so no producer of ours could
    join the deployment the docs describe); the same replay with the stranger's certificate gets
    nothing stored, and one with no certificate is not let in."""
    made = deployment(tmp_path / "deploy")
    local, keys = tmp_path / "local.db", tmp_path / "keys"
    short = ("--duration", "3s", "--vehicles", "2", "--seed", "7")
    first = gaps("sim", *short, "--run", "r-local", "--sign-keys", keys, "--json", db=local)  # makes the keys
    assert first.exit_code == 0, first.output
    db = tmp_path / "gaps.db"
    router = zenoh.open(session_config(config_file=made.config("router")))
    try:
        serve = ServeProcess(db, None, "--config", str(made.config("ingest")), "--require-signatures",
                             str(keys / "public-keys.json"), "--json")
        try:
            serve.wait_for_log("serve.ready")
            simulated = gaps("sim", *short, "--run", "r-sim", "--sign-keys", keys, "--config",
                             made.config("producer"), "--truth", tmp_path / "r-sim.truth.json", "--json")
            replayed = gaps("replay", "--db", local, "--run", "r-local", "--speed", "max", "--config",
                            made.config("producer"), "--json")
            monkeypatch.setitem(replay_runs.__kwdefaults__, "wait_s", 2.0)   # not 30 s for the refusals
            stranger = gaps("replay", "--db", local, "--run", "r-local", "--speed", "max", "--config",
                            made.config("stranger"), "--json")
            outsider = gaps("replay", "--db", local, "--run", "r-local", "--speed", "max", "--config",
                            made.config("outsider"), "--json")
            code, out = serve.stop(signal.SIGTERM)
        finally:
            serve.kill()
    finally:
        router.close()
    assert simulated.exit_code == 0, simulated.output
    assert replayed.exit_code == 0, replayed.output
    assert code == 0, serve.lines[-5:]
    published = json.loads(simulated.stdout)["published"]["published"]
    assert published > 100 and len(_events(db, "r-sim")) == published
    assert _events(db, "r-local") == _events(local, "r-local")     # the stored bytes, signatures and all
    assert stranger.exit_code == 2 and "no ingest subscribed within 2 s" in stranger.output, stranger.output
    assert outsider.exit_code == 2 and "cannot open Zenoh" in outsider.output, outsider.output
    metrics = json.loads(out)
    assert metrics["quarantined"] == 0 and metrics["duplicates"] == 0, metrics   # nothing of the stranger's


def test_only_the_ingest_publishes_heads_and_readers_hear_them(tmp_path: Path) -> None:
    """`--publish-heads` through the router: a reader (a witness) subscribed to `gaps/@heads/**`
    hears the ingest's signed tree heads, exactly the witness file's lines, and never a head that
    a stranger or a producer puts there (issue 37: the docs' rules did not name the heads at all,
    so the router passed the ingest's to nobody)."""
    made = deployment(tmp_path / "deploy")
    keys = KeyFolder(tmp_path / "keys")
    keys.create("vehicle/173")
    public = keys.write_public_keys()
    key, witness, db = tmp_path / "ckpt.key", tmp_path / "witness.jsonl", tmp_path / "gaps.db"
    CheckpointKey.create(key)
    forged = json.dumps({"run": RUN, "size": 10**6, "forged": True}).encode()
    heard: list[bytes] = []
    router = zenoh.open(session_config(config_file=made.config("router")))
    try:
        serve = ServeProcess(db, None, "--config", str(made.config("ingest")), "--require-signatures", str(public),
                             "--checkpoint-key", str(key), "--witness", str(witness), "--publish-heads", "--json")
        try:
            serve.wait_for_log("serve.ready")
            reader = zenoh.open(session_config(config_file=made.config("reader")))
            forgers = [zenoh.open(session_config(config_file=made.config(role))) for role in ("stranger", "producer")]
            try:
                reader.declare_subscriber("gaps/@heads/**", lambda s: heard.append(s.payload.to_bytes()))
                time.sleep(0.5)                     # the subscription reaches the router and the forgers
                for forger in forgers:
                    forger.put(f"gaps/@heads/{RUN}", forged)
                with EventPublisher(config=session_config(config_file=made.config("producer")),
                                    signer=Signer(keys)) as producer:
                    producer.publish_all([make_event("vehicle/173", seq) for seq in range(5)])
                deadline = time.monotonic() + WAIT_S
                while not heard and time.monotonic() < deadline:
                    time.sleep(0.05)
                for forger in forgers:
                    forger.put(f"gaps/@heads/{RUN}", forged)
                time.sleep(0.5)
            finally:
                for session in (*forgers, reader):
                    session.close()
            code, _ = serve.stop(signal.SIGTERM)
        finally:
            serve.kill()
    finally:
        router.close()
    assert code == 0, serve.lines[-5:]
    written = [line.encode() for line in witness.read_text().splitlines()]
    assert heard, "the reader heard no head of the ingest's"
    assert forged not in heard
    assert all(h in written for h in heard), (heard, written)
    assert all(h.signature_problem(CheckpointKey.load(key).public) is None for h in read_heads(witness))
