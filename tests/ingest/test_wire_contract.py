"""The wire contract is written once (store/wire.py): a producer's session and an ingest's are built by
the same function, so the settings that keep events from being lost cannot drift apart, and every
event publisher is declared with the audit QoS."""
from __future__ import annotations

import zenoh

from sim_replay.publisher import EventPublisher, zenoh_config
from store import BLOCK_FOR_US, audit_qos, session_config
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


def test_publishers_are_declared_with_the_audit_qos() -> None:
    declared: list[dict] = []
    publisher = EventPublisher(config=zenoh_config(listen=[free_endpoint()]))
    session = publisher.session

    class Spy:
        """The session, with its publisher declarations written down."""

        def __getattr__(self, name):
            return getattr(session, name)

        def declare_publisher(self, key, **qos):
            declared.append(qos)
            return session.declare_publisher(key, **qos)

    publisher._session = Spy()
    try:
        publisher.publish(make_event("vehicle/1", 0))
    finally:
        publisher._session = session
        publisher.close()
    assert declared == [audit_qos()]
    assert audit_qos()["congestion_control"] == zenoh.CongestionControl.BLOCK
    assert audit_qos()["reliability"] == zenoh.Reliability.RELIABLE
