"""The wire contract is written once (store/wire.py): a producer's session and an ingest's are built by
the same function, so the settings that keep events from being lost cannot drift apart, and every
event publisher is declared with the audit QoS."""
from __future__ import annotations

import pytest
import zenoh
import zenoh.ext

from sim_replay.publisher import EventPublisher, zenoh_config
from store.wire import BLOCK_FOR_US, audit_qos, session_config
from tests.helpers.ingest_testkit import free_endpoint, make_event

SETTINGS = ("mode", "listen/endpoints", "connect/endpoints", "scouting/multicast/enabled",
            "scouting/gossip/enabled", "transport/link/tx/queue/congestion_control/block/wait_before_close")


def test_a_producer_and_an_ingest_build_the_same_session() -> None:
    producer = zenoh_config(listen=["tcp/127.0.0.1:7447"], connect=["tcp/127.0.0.1:7448"])
    ingest = session_config(listen=["tcp/127.0.0.1:7447"], connect=["tcp/127.0.0.1:7448"])
    assert [producer.get_json(k) for k in SETTINGS] == [ingest.get_json(k) for k in SETTINGS]
    assert producer.get_json(SETTINGS[-1]) == str(BLOCK_FOR_US)     # a put waits for room, never drops
    assert producer.get_json("scouting/multicast/enabled") == "false"


def test_an_operators_file_keeps_its_own_transport_settings(tmp_path) -> None:
    path = tmp_path / "zenoh.json5"
    path.write_text('{ mode: "client", transport: { link: { tx: { queue: { congestion_control: '
                    '{ block: { wait_before_close: 7000000 } } } } } } }')
    config = session_config(config_file=path, connect=["tcp/127.0.0.1:7449"])
    assert config.get_json(SETTINGS[-1]) == "7000000" and config.get_json("mode") == '"client"'


def test_publishers_are_declared_with_the_audit_qos_and_sequence_numbers(monkeypatch: pytest.MonkeyPatch) -> None:
    declared: list[dict] = []
    real = zenoh.ext.declare_advanced_publisher

    def spy(session, key, **options):
        declared.append(options)
        return real(session, key, **options)

    monkeypatch.setattr(zenoh.ext, "declare_advanced_publisher", spy)
    publisher = EventPublisher(config=zenoh_config(listen=[free_endpoint()]), cache_s=2)
    try:
        publisher.publish(make_event("vehicle/1", 0))
    finally:
        publisher.close()
    assert len(declared) == 1
    assert {k: v for k, v in declared[0].items() if k in audit_qos()} == audit_qos()
    assert declared[0]["sample_miss_detection"] is not None
    # no Zenoh cache nor publisher detection per key: each declares a queryable or a token per
    # source and kind, which cost the ingest most of a CPU at fleet size (docs/serve.md)
    assert "cache" not in declared[0] and not declared[0].get("publisher_detection")
    assert audit_qos()["congestion_control"] == zenoh.CongestionControl.BLOCK
    assert audit_qos()["reliability"] == zenoh.Reliability.RELIABLE
