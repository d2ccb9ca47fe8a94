"""A flood of junk on the wire leaves a bounded quarantine and an exact count (issue 15, finding 6)."""
from __future__ import annotations

from pathlib import Path

import zenoh

from store import QuarantineCap, Store
from tests.helpers.ingest_testkit import RUN, await_match, linked, make_event

KEY = f"gaps/{RUN}/vehicle/173/vehicle.perception"


def flood(db_path: Path, payloads: list[bytes], cap: QuarantineCap) -> dict:
    with linked(db_path, "pub-listens", quarantine_cap=cap) as (publisher, service):
        await_match(publisher, make_event("vehicle/173", 0))
        for payload in payloads:
            publisher.session.put(KEY, payload, congestion_control=zenoh.CongestionControl.BLOCK)
        assert service.wait_until_settled(len(payloads), timeout=20), service.stats()
        return service.stats()


def test_identical_junk_on_the_wire_is_one_row(db_path: Path) -> None:
    stats = flood(db_path, [b"junk"] * 2_000, QuarantineCap())
    assert (stats["rejected"], stats["failed"], stats["quarantine_full"]) == (2_000, 0, 0)
    with Store.open_read_only(db_path) as store:
        [row] = store.quarantined()
    assert (row["origin"], row["raw"], row["count"]) == (KEY, b"junk", 2_000)


def test_past_the_cap_junk_is_counted_and_the_ingest_says_so(db_path: Path, caplog) -> None:
    stats = flood(db_path, [b"junk %d" % i for i in range(300)], QuarantineCap(rows=100, bytes=10**6))
    assert (stats["rejected"], stats["failed"], stats["quarantine_full"]) == (300, 0, 200)
    assert any("the quarantine is full" in r.getMessage() for r in caplog.records)
    with Store.open_read_only(db_path) as store:
        summary = store.quarantine_summary()
    assert summary["held"]["rows"] == 100
    assert [(o["origin"], o["samples"]) for o in summary["over_cap"]] == [(KEY, 200)]
