"""A fleet's short runs at the ingest: what the writer keeps of a run (its sources' seqs, its
keys) is let go once its run.end is stored, and memory is given back once the link is quiet."""
from __future__ import annotations

import time

from ingest import IngestService
from ingest import writer as writer_module
from sim_replay.publisher import EventPublisher
from tests.helpers.ingest_testkit import await_match, make_event
from tests.helpers.store_testkit import event


def short_run(run: str) -> list[dict]:
    events = [event(0, run=run, kind="run.start")]
    events += [make_event(f"vehicle/{n}", 0, "entity.state", run=run) for n in range(5)]
    return events + [event(1, run=run, kind="run.end")]


def test_ended_runs_are_let_go_and_memory_given_back_when_quiet(link: tuple[EventPublisher, IngestService],
                                                               monkeypatch) -> None:
    publisher, ingest = link
    given: list[float] = []
    real = writer_module.give_back
    monkeypatch.setattr(writer_module, "give_back", lambda store: (given.append(time.monotonic()), real(store)))
    events = [e for n in range(20) for e in short_run(f"fleet-{n}")]
    events += [make_event("vehicle/1", 0, "entity.state", run="going-on")]
    await_match(publisher, events[0])
    publisher.publish_all(events)
    assert ingest.wait_until_stored(len(events), timeout=20), ingest.stats()
    writer = ingest._writer
    deadline = time.monotonic() + 10
    while not given and time.monotonic() < deadline:
        time.sleep(0.1)
    assert len(given) == 1                                   # once per quiet spell
    assert {run for run, _ in writer._tracker._sources} == {"going-on"}
    assert all(key.startswith("gaps/going-on/") for key in writer._inbox._keys_seen)
    assert writer._tracker.sources(60.0)[0] == 20 * 6 + 1      # still counted as seen
