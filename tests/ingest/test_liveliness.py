"""Each source holds a liveliness token from its first event to its despawn; the ingest records
when each appears and disappears, a publisher process killed with SIGKILL included, so that "it
stopped publishing" is recorded rather than guessed."""
from __future__ import annotations

import subprocess
import sys
import textwrap
import time
from pathlib import Path

from ingest import IngestService
from sim_replay.publisher import EventPublisher, zenoh_config
from store import Store
from tests.helpers.ingest_testkit import RUN, await_match, free_endpoint, make_event
from tests.helpers.serve_testkit import ROOT, child_env

WAIT_S = 15.0


def _changes(db: Path, src: str) -> list[tuple[bool, int | None]]:
    with Store.open_read_only(db) as store:
        return [(c.alive, c.last_seq) for c in store.liveliness_changes(RUN, src)]


def _wait_changes(db: Path, src: str, n: int) -> list[tuple[bool, int | None]]:
    deadline = time.monotonic() + WAIT_S
    while len(found := _changes(db, src)) < n and time.monotonic() < deadline:
        time.sleep(0.05)
    return found


def _despawn(src: str, seq: int) -> dict:
    return {**make_event(src, seq, "entity.state"), "kind": "entity.despawn", "body": {"reason": "left the map"}}


def test_tokens_appear_with_a_source_and_go_with_its_despawn(db_path: Path) -> None:
    endpoint = free_endpoint()
    with IngestService(db_path, listen=[endpoint]) as ingest:
        with EventPublisher(config=zenoh_config(connect=[endpoint])) as publisher:
            await_match(publisher, make_event("vehicle/1", 0))
            publisher.publish_all([make_event("vehicle/1", 0), make_event("vehicle/2", 0), _despawn("vehicle/2", 1)])
            assert publisher.live_sources == (f"gaps/{RUN}/vehicle/1",)
            assert ingest.wait_until_stored(3, WAIT_S)
            gone = _wait_changes(db_path, "vehicle/2", 2)
            assert [alive for alive, _ in gone] == [True, False] and gone[-1] == (False, 1)   # after its despawn
            assert [alive for alive, _ in _changes(db_path, "vehicle/1")] == [True]
        assert _wait_changes(db_path, "vehicle/1", 2)[-1] == (False, 0)   # the publisher closed
    with Store.open_read_only(db_path) as store:
        lives = {life.src: life for life in store.lives(RUN)}
        assert not lives["vehicle/1"].alive and lives["vehicle/1"].last_seq == 0
        assert lives["vehicle/2"].disappeared_at >= lives["vehicle/2"].appeared_at


PUBLISHER = textwrap.dedent("""
    import sys, time
    from sim_replay.publisher import EventPublisher, zenoh_config
    from tests.helpers.ingest_testkit import make_event
    publisher = EventPublisher(config=zenoh_config(connect=[sys.argv[1]]))
    assert publisher.wait_until_matched(make_event("vehicle/9", 0), 10)
    publisher.publish_all([make_event("vehicle/9", seq) for seq in range(3)])
    print("published", flush=True)
    time.sleep(60)
""")


def test_a_publisher_killed_with_sigkill_loses_its_token(db_path: Path) -> None:
    endpoint = free_endpoint()
    with IngestService(db_path, listen=[endpoint]) as ingest:
        child = subprocess.Popen([sys.executable, "-c", PUBLISHER, endpoint], cwd=ROOT, env=child_env(),
                                 stdout=subprocess.PIPE, text=True)
        try:
            assert child.stdout.readline().strip() == "published"
            assert ingest.wait_until_stored(3, WAIT_S), ingest.stats()
            assert [alive for alive, _ in _wait_changes(db_path, "vehicle/9", 1)] == [True]
        finally:
            child.kill()
            child.wait()
        found = _wait_changes(db_path, "vehicle/9", 2)
        assert found[-1] == (False, 2), found      # gone after its seq 2, though it never said goodbye
