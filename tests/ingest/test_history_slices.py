"""Slices: several ingests share one Zenoh network, each owning a key slice and writing its own
store; a history query on `gaps/**` through the router is answered by all of them.

No `zenohd` is packaged here: the router is an eclipse-zenoh session in router mode, listening on a
free loopback port; publishers and ingests are clients connected to it (scouting off)."""
from __future__ import annotations

import json
from pathlib import Path

import zenoh

from ingest import IngestService
from ingest.history_fetch import FetchOptions, fetch
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store
from store.wire import session_config
from tests.helpers.ingest_testkit import free_endpoint, make_event

SITES = ("site-a", "site-b")
PER_SITE = 3 * 40   # three sources of each site, 40 events each


def site_events(site: str) -> list[dict]:
    return [make_event(src, seq, kind, run=site) for seq in range(40)
            for src, kind in (("vehicle/1", "entity.state"), ("vehicle/2", "entity.state"),
                              ("signal/j1", "signal.state"))]


def stored_ids(db: Path) -> set[tuple[str, str, int]]:
    with Store.open_read_only(db) as store:
        return {(e["run"], e["src"], e["seq"]) for run in store.run_names() for e in store.events(run)}


def ids(events: list[dict]) -> set[tuple[str, str, int]]:
    return {(e["run"], e["src"], e["seq"]) for e in events}


def test_two_ingests_each_store_their_slice_and_answer_a_history_query_together(tmp_path):
    router_at = free_endpoint()
    router = zenoh.open(session_config(listen=[router_at], mode="router"))
    dbs = {site: tmp_path / f"{site}.db" for site in SITES}
    ingests = [IngestService(dbs[site], connect=[router_at], mode="client", key_expr=f"gaps/{site}/**")
               for site in SITES]
    try:
        publishers = [EventPublisher(config=zenoh_config(connect=[router_at], mode="client")) for _ in SITES]
        for publisher, site in zip(publishers, SITES):
            first = site_events(site)[0]
            assert publisher.wait_until_matched(first, 5.0), f"no ingest subscribed to {site}"
        for i in range(PER_SITE):             # the two sites publish at once, interleaved
            for publisher, site in zip(publishers, SITES):
                publisher.publish(site_events(site)[i])
        for publisher in publishers:
            publisher.close()
        for ingest in ingests:
            assert ingest.wait_until_stored(PER_SITE, 10.0)

        for site in SITES:                   # each store holds exactly its slice
            assert stored_ids(dbs[site]) == ids(site_events(site))

        asker = zenoh.open(session_config(connect=[router_at], mode="client"))
        try:
            replies = list(asker.get("gaps/**?_time=[..]", target=zenoh.QueryTarget.ALL,
                                     consolidation=zenoh.ConsolidationMode.NONE, timeout=10))
        finally:
            asker.close()
        assert all(r.ok is not None for r in replies)
        got = [json.loads(r.ok.payload.to_bytes()) for r in replies]
        assert len(got) == 2 * PER_SITE and ids(got) == ids(site_events("site-a") + site_events("site-b"))
        assert len({str(r.replier_id.zid) for r in replies}) == 2   # both ingests answered

        copy = tmp_path / "investigator.db"      # and gaps fetch through the router gets both chains
        report = fetch(copy, FetchOptions("gaps/**", connect=(router_at,), page=50))
        assert (report.stored, report.exit_code, len(report.responders)) == (2 * PER_SITE, 0, 2)
        assert [(c.run, c.match) for c in report.chains] == [("site-a", True), ("site-b", True)]
    finally:
        for ingest in ingests:
            ingest.stop()
        router.close()
