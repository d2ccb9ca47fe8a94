"""What the publisher puts on the wire: canonical JSON on key_for(event), application/json, BLOCK."""
from __future__ import annotations

import threading

import zenoh

from ingest import session_config
from tests.helpers.ingest_testkit import free_endpoint, make_event
from sim_replay.publisher import EventPublisher, zenoh_config
from store import canonical_json
from store.wire import key_for


def test_publisher_wire_format() -> None:
    endpoint = free_endpoint()
    events = [make_event("vehicle/173", 0), make_event("signal/s1", 0, "signal.state")]
    received: list[zenoh.Sample] = []
    all_arrived = threading.Event()

    def on_sample(sample: zenoh.Sample) -> None:
        received.append(sample)
        if len(received) == len(events):
            all_arrived.set()

    with zenoh.open(session_config(listen=[endpoint])) as session:
        session.declare_subscriber("gaps/**", on_sample)
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
            assert all(publisher.wait_until_matched(ev, 5) for ev in events)
            publisher.publish_all(events)
            assert all_arrived.wait(5)
        got = {str(s.key_expr): s for s in received}
    assert set(got) == {key_for(ev) for ev in events}
    for ev in events:
        sample = got[key_for(ev)]
        assert sample.payload.to_bytes() == canonical_json(ev)
        assert str(sample.encoding) == "application/json"
        assert sample.congestion_control == zenoh.CongestionControl.BLOCK


def test_given_session_is_left_open() -> None:
    with zenoh.open(zenoh_config()) as session:
        with EventPublisher(session) as publisher:
            publisher.publish(make_event("vehicle/1", 0))  # no subscriber: fine, nothing waits
        assert not session.is_closed()
