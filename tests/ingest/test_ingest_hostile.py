"""Hostile and wrong input is quarantined with its exact bytes and a reason; the service keeps going."""
from __future__ import annotations

import json
from pathlib import Path

import zenoh

from tests.helpers.ingest_testkit import RUN, await_match, make_event
from ingest import IngestService
from sim_replay.publisher import EventPublisher
from store import MAX_EVENT_BYTES, Store, canonical_json
from store.wire import key_for


def hostile_samples() -> list[tuple[str, bytes, str]]:
    """(key, payload, a word the quarantine reason must contain)."""
    honest = make_event("vehicle/173", 0)
    huge = make_event("vehicle/173", 1, facts=["173 has red light " * (MAX_EVENT_BYTES // 16)])
    prolog = make_event("vehicle/173", 2)
    prolog["body"] = "halt."  # a Prolog-looking body where an object belongs
    return [
        (f"gaps/{RUN}/vehicle/173/vehicle.perception", b'{"v": 1, "run": ', "JSON"),
        (f"gaps/{RUN}/vehicle/174/vehicle.perception", canonical_json(honest), "does not match"),
        (key_for(huge), json.dumps(huge).encode(), "limit"),
        (f"gaps/{RUN}/vehicle/173/vehicle.perception", b'{"v": 1, "run": "caf\xe9"}', "UTF-8"),
        (f"gaps/{RUN}/vehicle/173/vehicle.perception", b"[1, 2, 3]", "object"),
        (key_for(prolog), canonical_json(prolog), "body"),
    ]


def test_hostile_payloads_are_quarantined(link: tuple[EventPublisher, IngestService], db_path: Path) -> None:
    publisher, ingest = link
    samples = hostile_samples()
    good = make_event("vehicle/173", 0)
    await_match(publisher, good)
    for key, payload, _ in samples:  # BLOCK as for real events: the default DROP loses the ones after the huge one
        publisher.session.put(key, payload, congestion_control=zenoh.CongestionControl.BLOCK)
    publisher.session.delete(key_for(good), congestion_control=zenoh.CongestionControl.BLOCK)
    publisher.publish(good)  # the service still works after all that
    sent = len(samples) + 2
    assert ingest.wait_until_settled(sent, timeout=10), ingest.stats()
    stats = ingest.stats()
    assert (stats["stored"], stats["rejected"], stats["errors"], stats["failed"]) == (1, sent - 1, 0, 0)
    assert ingest.gaps() == []  # seq 1 and 2 arrived (then were refused): seen, so not a gap
    assert ingest.stats()["late"] <= 1  # seq 0 (the good one) may come after them
    ingest.stop()
    with Store(db_path) as store:
        assert [ev["seq"] for ev in store.events(RUN)] == [0]
        quarantined = store.quarantined()
    reasons = {(q["origin"], q["raw"]): q["reason"] for q in quarantined}
    assert len(quarantined) == len(reasons) == sent - 1
    for key, payload, word in samples:
        assert word.lower() in reasons[(key, payload)].lower()
    assert "DELETE" in reasons[(key_for(good), b"")]
