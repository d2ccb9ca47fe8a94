"""sim_replay.outlets: what a producer puts out reaches the ingest and its recording alike, paced
as asked; an ingest that never appears is a clear error, not a silent loss."""
from __future__ import annotations

import time

import pytest
from mcap.reader import make_reader

from ingest.service import IngestService
from sim_replay.outlets import Outlets
from sim_replay.paper import paper_run
from store import Store, canonical_json
from tests.helpers.ingest_testkit import free_endpoint, make_event


def test_every_event_reaches_the_store_and_the_recording_in_the_order_put(tmp_path):
    events = paper_run()
    endpoint = free_endpoint()
    with IngestService(tmp_path / "s.db", listen=[endpoint]) as ingest:
        with Outlets(connect=[endpoint], record=tmp_path / "run.mcap") as out:
            for e in events:
                out.put(e)
        sent = out.summary()
        assert ingest.wait_until_settled(len(events), 30)
    assert (sent.published, sent.recorded, sent.late_in_recording) == (len(events), len(events), 0)
    assert sent.sources == len({e["src"] for e in events}) and sent.recording_bytes > 0
    with Store(tmp_path / "s.db", read_only=True) as store:
        stored = sorted(canonical_json(e) for e in store.events(events[0]["run"]))
    with open(tmp_path / "run.mcap", "rb") as f:
        recorded = sorted(m.data for _, c, m in make_reader(f).iter_messages() if c.topic.startswith("gaps/"))
    assert stored == recorded == sorted(canonical_json(e) for e in events)


def test_a_speed_paces_world_time_against_the_wall_clock(tmp_path):
    # two events 1 s of world time apart, at 4 x real time: the second goes out 0.25 s after the first
    events = [make_event("vehicle/1", 0, "entity.state"), make_event("vehicle/1", 10, "entity.state")]
    assert events[1]["t"] - events[0]["t"] == 1_000_000_000
    with Outlets(record=tmp_path / "r.mcap", speed=4.0) as out:
        started = time.monotonic()
        out.put(events[0])
        out.put(events[1])
        took = time.monotonic() - started
    assert took >= 0.24
    assert out.summary().world_s == 1.0 and out.summary().published == 0 and out.summary().recorded == 2


def test_no_ingest_on_the_endpoint_is_a_clear_error_and_the_recording_is_not_left_half_written(tmp_path):
    with pytest.raises(TimeoutError, match="no ingest subscribed within 0.5 s on connect tcp/127.0.0.1"):
        with Outlets(connect=[free_endpoint()], record=tmp_path / "r.mcap", wait_s=0.5) as out:
            out.put(make_event("vehicle/1", 0, "entity.state"))
    assert not (tmp_path / "r.mcap").exists()


def test_a_speed_must_be_positive():
    with pytest.raises(ValueError, match="speed must be positive"):
        Outlets(speed=0)
