"""A replay at full speed puts each event's stored text as it is (the canonical bytes its hash
covers) with the puts back to back, rather than parsing, encoding again and putting one at a
time: the replay's own CPU went on those (issue 16's replay rate). What arrives is the same."""
from __future__ import annotations

import pytest

import sim_replay.publisher as publisher_module
from ingest.service import IngestService
from sim_replay.paper import RUN, paper_run
from sim_replay.publisher import EventPublisher
from sim_replay.replay import replay
from store import Store
from store.keys import KeyFolder, Signer
from tests.helpers.ingest_testkit import free_endpoint


def _encoding_forbidden(event):
    raise AssertionError("a full-speed replay encoded an event again")


def test_a_full_speed_replay_puts_the_stored_bytes_back_to_back(tmp_path, monkeypatch):
    events = paper_run()
    with Store(tmp_path / "source.db", durable=False) as source:
        source.append(events)
        stored = [row.event.encode() for row in source.history(RUN)]
        runs: list[int] = []
        put_run = EventPublisher._put_run
        monkeypatch.setattr(EventPublisher, "_put_run", lambda self, run: (runs.append(len(run)), put_run(self, run)))
        monkeypatch.setattr(publisher_module, "canonical_json", _encoding_forbidden)
        endpoint = free_endpoint()
        with IngestService(tmp_path / "live.db", listen=[endpoint]) as ingest:
            [sent] = replay(source, [RUN], connect=[endpoint], speed=None)
            assert ingest.wait_until_settled(len(events), 30)
    assert sent.events == len(events) and sum(runs) == len(events)
    assert max(runs) > 1, "each event was put on its own"
    with Store(tmp_path / "live.db", read_only=True) as live:
        assert [row.event.encode() for row in live.history(RUN)] == stored


def test_a_signing_publisher_takes_no_bytes_written_before_it_signed(tmp_path):
    event = paper_run()[0]
    with EventPublisher(signer=Signer(KeyFolder(tmp_path / "keys"), create=True)) as publisher:
        with pytest.raises(ValueError, match="a signing publisher encodes each event itself"):
            publisher.publish_all([event], [b"{}"])
