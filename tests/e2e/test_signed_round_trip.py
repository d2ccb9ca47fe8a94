"""Signed events the whole way, as an operator and an investigator would run them: keys made with
`gaps keys new`, a publisher signing with them, `gaps serve --require-signatures` quarantining what
they did not sign, then `gaps export`, `gaps import` into another store and `gaps verify --keys`."""
from __future__ import annotations

import json

from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store
from store.keys import KeyFolder, Signer
from tests.helpers.cli import gaps
from tests.helpers.ingest_testkit import RUN, free_endpoint, make_event
from tests.helpers.serve_testkit import ServeProcess


def test_signed_events_round_trip_from_publisher_to_verify(tmp_path):
    keys_dir, db, endpoint = tmp_path / "keys", tmp_path / "live.db", free_endpoint()
    made = gaps("keys", "new", keys_dir, "vehicle/173", "monitor/m1", "--json")
    assert made.exit_code == 0, made.output
    public = json.loads(made.stdout)["public_keys"]
    serve = ServeProcess(db, endpoint, "--require-signatures", public, "--json")
    try:
        serve.wait_for_log("serve.ready")
        signed = [make_event("vehicle/173", seq) for seq in range(4)] + [make_event("monitor/m1", 0, "monitor.observation")]
        with EventPublisher(config=zenoh_config(connect=[endpoint]), signer=Signer(KeyFolder(keys_dir))) as publisher:
            assert publisher.wait_until_matched(signed[0], 10)
            publisher.publish_all(signed)
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as stranger:
            stranger.publish(make_event("vehicle/173", 4))                        # unsigned
        code, out = serve.stop()
    finally:
        serve.kill()
    metrics = json.loads(out)
    assert code == 0 and (metrics["stored"], metrics["quarantined"], metrics["signature_refused"]) == (5, 1, 1)
    assert metrics["require_signatures"] == public

    exported = tmp_path / "run.jsonl"
    assert gaps("export", "--run", RUN, "-o", exported, db=db).exit_code == 0
    assert all("sig" in json.loads(line) for line in exported.read_text().splitlines())
    copy = tmp_path / "copy.db"
    assert gaps("import", exported, db=copy).exit_code == 0
    checked = gaps("verify", "--keys", public, "--json", db=copy)
    assert checked.exit_code == 0, checked.output
    s = json.loads(checked.stdout)["signatures"]
    assert (s["signed"], s["unsigned"], s["valid"], s["invalid"], s["ok"]) == (5, 0, 5, 0, True)
    with Store.open_read_only(copy) as a, Store.open_read_only(db) as b:
        assert list(a.events(RUN)) == list(b.events(RUN))
