"""Puts back to back: EventPublisher.publish_all encodes a run of events, then puts them one after
another with nothing between (a put that finds Zenoh's sending thread idle wakes it for one sample);
a despawn ends a run, so a source that speaks again within the same call gets new publishers and
nothing is lost. Outlets.put_all and Simulation.batches carry a tick's events there together."""
from __future__ import annotations

import time

from ingest import IngestService
from sim_replay.outlets import Outlets
from sim_replay.sim_config import SimConfig
from sim_replay.simulation import Simulation
from store import Store, canonical_json
from tests.helpers.ingest_testkit import RUN, T0, await_match, free_endpoint, linked, make_event


def _despawn(src: str, seq: int) -> dict:
    return {"v": 1, "run": RUN, "src": src, "seq": seq, "t": T0 + seq * 100_000_000, "kind": "entity.despawn",
            "body": {"reason": "left the map"}}


def test_a_runs_puts_follow_its_encoding_and_a_despawn_ends_the_run(tmp_path) -> None:
    with linked(tmp_path / "s.db", "pub-listens") as (publisher, ingest):
        calls: list[str] = []
        publisher_for = publisher._publisher_for

        def watched(key: str):
            real = publisher_for(key)
            calls.append(f"find {key.split('/', 2)[2]}")

            class Put:
                def put(self, payload: bytes) -> None:
                    calls.append("put")
                    real.put(payload)
            return Put()

        publisher._publisher_for = watched
        events = [make_event("vehicle/9", 0, "entity.state"), make_event("vehicle/10", 0, "entity.state"),
                  _despawn("vehicle/9", 1), make_event("vehicle/9", 2, "entity.state"),
                  make_event("vehicle/10", 1, "entity.state")]
        await_match(publisher, events[0])
        assert publisher.publish_all(events) == 5
        assert calls == ["find vehicle/9/entity.state", "find vehicle/10/entity.state", "find vehicle/9/entity.despawn",
                         "put", "put", "put",                       # the first run ends with the despawn
                         "find vehicle/9/entity.state", "find vehicle/10/entity.state", "put", "put"]
        assert {key.rsplit("/", 1)[0] for key in publisher.keys} == {f"gaps/{RUN}/vehicle/9", f"gaps/{RUN}/vehicle/10"}
        assert ingest.wait_until_stored(5, timeout=10), ingest.stats()
        assert ingest.stats()["stored"] == 5 and ingest.gaps() == []
        assert len(publisher.cache) == 5


def test_put_all_of_a_simulations_ticks_stores_and_records_what_put_one_by_one_would(tmp_path) -> None:
    sim = Simulation(SimConfig(run="ticks", vehicles=6, duration_s=8.0, seed=2, pedestrians=1))
    batches = list(sim.batches())
    events = [e for batch in batches for e in batch]
    assert len(batches) > 50 and all(batches) and events[0]["kind"] == "run.start" and events[-1]["kind"] == "run.end"
    assert events == list(Simulation(SimConfig(run="ticks", vehicles=6, duration_s=8.0, seed=2,
                                               pedestrians=1)).events())
    endpoint = free_endpoint()
    with IngestService(tmp_path / "s.db", listen=[endpoint]) as ingest:
        with Outlets(connect=[endpoint], record=tmp_path / "run.mcap") as out:
            for batch in batches:
                out.put_all(batch)
        sent = out.summary()
        assert ingest.wait_until_settled(len(events), 30)
    assert (sent.published, sent.recorded) == (len(events), len(events))
    assert sent.sources == len({e["src"] for e in events}) and sent.world_s == 8.0
    with Store(tmp_path / "s.db", read_only=True) as store:
        stored = [canonical_json(e) for e in store.events("ticks")]
    assert sorted(stored) == sorted(canonical_json(e) for e in events)


def test_put_all_at_a_speed_paces_each_event(tmp_path) -> None:
    events = [make_event("vehicle/1", 0, "entity.state"), make_event("vehicle/1", 10, "entity.state")]
    with Outlets(record=tmp_path / "r.mcap", speed=4.0) as out:
        started = time.monotonic()
        out.put_all(events)
        took = time.monotonic() - started
    assert took >= 0.24 and out.summary().recorded == 2
