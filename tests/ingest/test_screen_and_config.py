"""The ingest's own checks, without a network: key screening and the Zenoh config it builds."""
from __future__ import annotations

import json

import pytest

from ingest.screen import screen
from store.wire import session_config
from tests.helpers.ingest_testkit import make_event
from store import MAX_EVENT_BYTES, canonical_json
from store.wire import key_for


def test_matching_key_is_accepted_with_identity() -> None:
    ev = make_event("vehicle/173", 4)
    item = screen(key_for(ev), canonical_json(ev))
    assert item.candidate.reason is None and item.candidate.event == ev
    assert item.identity == (ev["run"], "vehicle/173", 4)


@pytest.mark.parametrize("field,value", [("run", "other-run"), ("src", "vehicle/174"), ("kind", "entity.state")])
def test_key_body_mismatch_is_refused_without_identity(field: str, value: str) -> None:
    ev = make_event("vehicle/173", 4)
    key = key_for({**ev, field: value})
    item = screen(key, canonical_json(ev))
    reason = item.candidate.reason or ""
    assert key in reason and key_for(ev) in reason and item.identity is None


@pytest.mark.parametrize("payload", [b"", b"{", b"\xff\xfe", b"[]", b'{"seq": true}', b"1e999999"])
def test_unreadable_payloads_are_refused_with_the_bytes(payload: bytes) -> None:
    item = screen("gaps/r/vehicle/1/vehicle.perception", payload)
    assert item.candidate.reason and item.candidate.raw == payload and item.identity is None


def test_invalid_event_keeps_the_identity_it_claims() -> None:
    ev = make_event("vehicle/173", 9)
    del ev["body"]["facts"]
    assert screen(key_for(ev), canonical_json(ev)).identity == (ev["run"], "vehicle/173", 9)
    huge = make_event("vehicle/173", 10, facts=["x" * MAX_EVENT_BYTES])
    item = screen(key_for(huge), canonical_json(huge))
    assert "limit" in (item.candidate.reason or "") and item.identity == (huge["run"], "vehicle/173", 10)


def test_delete_is_refused() -> None:
    assert "DELETE" in (screen("gaps/r/vehicle/1/x", b"", is_put=False).candidate.reason or "")


def test_config_has_explicit_endpoints_and_no_scouting() -> None:
    config = session_config(listen=["tcp/127.0.0.1:7000"], connect=["tcp/127.0.0.1:7001"], mode="client")
    assert json.loads(config.get_json("mode")) == "client"
    assert json.loads(config.get_json("listen/endpoints")) == ["tcp/127.0.0.1:7000"]
    assert json.loads(config.get_json("connect/endpoints")) == ["tcp/127.0.0.1:7001"]
    assert json.loads(config.get_json("scouting/multicast/enabled")) is False
    assert json.loads(config.get_json("scouting/gossip/enabled")) is False
    assert json.loads(session_config().get_json("listen/endpoints")) == []


def test_unknown_mode_is_refused() -> None:
    with pytest.raises(ValueError, match="mode"):
        session_config(mode="router-ish")
