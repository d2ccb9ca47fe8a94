"""Secure by default for producers (issue 37): `gaps sim`, `gaps replay` and the publisher API
reachable beyond loopback (a non-loopback endpoint, scouting on) with no Zenoh authentication in
their config refuse to start unless told `--insecure-beyond-loopback`, which is logged; signing
the events covers the events, not the cache's queryable or the liveliness tokens. Read from the
Zenoh config the session opens with (store/reachability.py, the ingest's reading too)."""
from __future__ import annotations

import logging
from pathlib import Path

import pytest

from ingest.service import IngestService
from sim_replay import publisher as publisher_module
from sim_replay.paper import paper_run
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store, canonical_json
from store.keys import KeyFolder, Signer
from store.wire import WireConfigError, session_config
from store.wire import Exposure, check_producer
from tests.helpers.cli import gaps
from tests.helpers.hardened import doc_block
from tests.helpers.ingest_testkit import free_endpoint

OPEN = Exposure(("listens on tcp/0.0.0.0:7447",), ())


def test_a_producer_beyond_loopback_needs_zenoh_authentication_signed_or_not() -> None:
    assert check_producer(Exposure((), ()), signed=False, insecure=False) == []
    assert check_producer(Exposure(("connects to tls/router.example.org:7447",), ("mutual TLS",)),
                          signed=False, insecure=False) == []
    with pytest.raises(WireConfigError, match=r"events are not signed .*; and its Zenoh config authenticates nobody"
                                              r".*--insecure-beyond-loopback") as refused:
        check_producer(OPEN, signed=False, insecure=False)
    assert refused.value.exit_code == 2
    with pytest.raises(WireConfigError) as signed:     # signatures cover the events, not the cache or tokens
        check_producer(OPEN, signed=True, insecure=False)
    assert "not signed" not in str(signed.value) and "cache's recent events" in str(signed.value)
    assert len(check_producer(OPEN, signed=False, insecure=True)) == 2


def test_the_publisher_refuses_an_open_config_before_opening_zenoh(tmp_path: Path) -> None:
    anywhere = free_endpoint().replace("127.0.0.1", "0.0.0.0")
    with pytest.raises(WireConfigError, match=r"listens on tcp/0\.0\.0\.0:.*authenticates nobody"):
        EventPublisher(config=zenoh_config(listen=[anywhere]))
    keys = KeyFolder(tmp_path / "keys")
    keys.create("vehicle/173")
    with pytest.raises(WireConfigError, match="authenticates nobody") as signed:
        EventPublisher(config=zenoh_config(listen=[anywhere]), signer=Signer(keys))
    assert "not signed" not in str(signed.value)
    scouting = tmp_path / "scouting.json5"       # loopback endpoints, Zenoh's scouting left on
    scouting.write_text('{ listen: { endpoints: ["tcp/127.0.0.1:7447"] } }')
    with pytest.raises(WireConfigError, match="multicast scouting is on"):
        EventPublisher(config=session_config(config_file=scouting))
    hardened = tmp_path / "producer.json5"       # the docs' client file: beyond loopback, mutual TLS
    hardened.write_text(doc_block("serve.json5"))
    assert publisher_module.check_producer(publisher_module.exposure(session_config(config_file=hardened)),
                                           signed=False, insecure=False) == []


def test_the_cli_refuses_an_open_producer_and_its_opt_out_is_logged(tmp_path: Path, monkeypatch, caplog) -> None:
    anywhere = free_endpoint().replace("127.0.0.1", "0.0.0.0")
    refused = gaps("sim", "--duration", "2s", "--vehicles", "1", "--listen", anywhere)
    assert refused.exit_code == 2 and f"can be reached beyond loopback (listens on {anywhere})" in refused.output
    local = tmp_path / "local.db"
    with Store(local) as store:
        store.append(paper_run())
    refused = gaps("replay", "--db", local, "--listen", anywhere, "--speed", "max")
    assert refused.exit_code == 2 and "--insecure-beyond-loopback" in refused.output, refused.output
    missing = gaps("replay", "--db", local, "--config", tmp_path / "nowhere.json5")
    assert missing.exit_code == 2 and "no Zenoh config file at" in missing.output
    # an open producer told to run anyway (its config read as open: no strangers needed for that)
    monkeypatch.setattr(publisher_module, "exposure", lambda config: OPEN)
    endpoint = free_endpoint()
    with IngestService(tmp_path / "gaps.db", listen=[endpoint]) as ingest:
        refused = gaps("replay", "--db", local, "--connect", endpoint, "--speed", "max")
        with caplog.at_level(logging.WARNING, logger="gaps.producer"):
            ran = gaps("replay", "--db", local, "--connect", endpoint, "--speed", "max", "--insecure-beyond-loopback")
        assert ran.exit_code == 0, ran.output
        assert ingest.wait_until_settled(len(paper_run()), 20), ingest.stats()
    assert refused.exit_code == 2 and "listens on tcp/0.0.0.0:7447" in refused.output
    assert [r.getMessage() for r in caplog.records if r.name == "gaps.producer"] == [
        "--insecure-beyond-loopback: this producer can be reached beyond loopback (listens on tcp/0.0.0.0:7447), "
        "and its events are not signed (--sign-keys DIR): whoever it reaches takes them as its sources'; and its "
        "Zenoh config authenticates nobody (no access_control, mutual TLS or user/password in --config): anyone "
        "reaching it can read its cache's recent events and declare its sources' liveliness"]
    with Store.open_read_only(tmp_path / "gaps.db") as store:
        assert sorted(canonical_json(e) for e in store.events(paper_run()[0]["run"])) == sorted(
            canonical_json(e) for e in paper_run())
