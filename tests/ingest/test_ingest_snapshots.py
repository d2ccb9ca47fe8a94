"""The ingest keeps state snapshots checked as it appends, so that readers of a growing run do
not have to check its appends themselves (store/snapshots.py, enable_snapshots)."""
from __future__ import annotations

from pathlib import Path

from ingest import IngestService
from tests.helpers.ingest_testkit import RUN, await_match, make_event
from sim_replay.publisher import EventPublisher
from store import Store
from store.state import build_snapshots, state_at


def watermark(db_path: Path) -> int | None:
    with Store(db_path) as store:
        row = store.cache.connection.execute("SELECT chain_len FROM state_watermarks WHERE run = ?", (RUN,)).fetchone()
    return None if row is None else row[0]


def test_the_ingest_checks_snapshots_inside_its_appends(
    link: tuple[EventPublisher, IngestService], db_path: Path
) -> None:
    publisher, ingest = link
    first = [make_event("vehicle/173", seq, "entity.state") for seq in range(30)]
    await_match(publisher, first[0])
    publisher.publish_all(first)
    assert ingest.wait_until_stored(30, timeout=10), ingest.stats()
    assert watermark(db_path) == 30  # raised by the ingest's own append transactions

    with Store(db_path) as reader:
        build_snapshots(reader, RUN, every=10)
    late = make_event("vehicle/9", 0, "entity.state", x=9.0)
    late["t"] = first[5]["t"]  # before most snapshots: they are stale now
    publisher.publish(late)
    assert ingest.wait_until_stored(31, timeout=10), ingest.stats()
    assert watermark(db_path) == 31
    with Store(db_path) as reader:
        stale = reader.cache.connection.execute(
            "SELECT count(*) FROM state_snapshots WHERE run = ? AND t >= ?", (RUN, late["t"])).fetchone()[0]
        assert stale == 0  # dropped by the ingest in the transaction that stored the late event
        end = first[-1]["t"]
        assert state_at(reader, RUN, end) == state_at(reader, RUN, end, use_snapshots=False)
