"""One run, one producer, at the ingest (issue 37): a producer publishing into a run the store holds
from another producer (a replay of another recording of run X, a second simulation under the same
run id, into a `gaps serve` it cannot see the store of) had its events of the held identities
quarantined as conflicting duplicates and the rest (later seqs, a new source) chained onto the held
run. Now its run.start, differing from the held one, marks the run as held by another producer and
every one of its events is quarantined with that reason, none stored; the same events again and a
resumed run are stored as before, and a lone conflicting event leaves the run going on.
Loopback, explicit endpoints, scouting off (ingest_testkit)."""
from __future__ import annotations

from pathlib import Path

from store import Store
from tests.helpers.ingest_testkit import await_match, linked
from tests.helpers.store_testkit import T0, event

RUN = "r1"
HELD = [event(0, kind="run.start", body={"seed": 7})] + [event(seq) for seq in range(5)]


def _holding(db_path: Path) -> None:
    with Store(db_path) as store:
        store.append(HELD)


def _published(db_path: Path, events: list[dict]) -> dict:
    with linked(db_path, "ingest-listens") as (publisher, ingest):
        for first in {e["src"]: e for e in reversed(events)}.values():
            await_match(publisher, first)
        publisher.publish_all(events)
        assert ingest.wait_until_settled(len(events), timeout=10), ingest.stats()
        return ingest.stats()


def test_another_producers_run_under_a_held_id_is_refused_never_mixed(db_path: Path) -> None:
    _holding(db_path)
    # run r1 again from another simulation (seed 8): its run.start, the held source at other
    # times and more seqs than are held, a source the store does not hold. Before: 6 conflicting
    # duplicates quarantined, 7 events chained onto the held run
    other = [event(0, kind="run.start", body={"seed": 8})]
    other += [event(seq, t=T0 + seq * 100_000_000 + 7_000_000) for seq in range(10)]
    other += [event(seq, src="vehicle/174") for seq in range(2)]
    stats = _published(db_path, other)
    assert (stats["stored"], stats["rejected"]) == (0, len(other)), stats
    with Store.open_read_only(db_path) as store:
        assert store.count(RUN) == len(HELD) and "vehicle/174" not in store.sources(RUN)
        reasons = {row["reason"] for row in store.quarantined()}
        assert len(reasons) == 1 and reasons.pop().startswith(f"run {RUN} held by another producer: its run.start")
        assert store.quarantine_count() == len(other) and store.verify().ok


def test_the_same_events_again_and_a_resumed_run_are_stored(db_path: Path) -> None:
    _holding(db_path)
    stats = _published(db_path, HELD + [event(seq) for seq in range(5, 8)])
    assert (stats["stored"], stats["duplicates"], stats["rejected"]) == (3, 6, 0), stats
    with Store.open_read_only(db_path) as store:
        assert store.count(RUN) == 9 and store.quarantine_count() == 0 and store.verify().ok


def test_a_lone_conflicting_event_is_quarantined_and_the_run_goes_on(db_path: Path) -> None:
    _holding(db_path)
    stats = _published(db_path, [event(4, t=T0 + 1)] + [event(seq) for seq in range(5, 8)])
    assert (stats["stored"], stats["rejected"]) == (3, 1), stats
    with Store.open_read_only(db_path) as store:
        assert [row["reason"] for row in store.quarantined()] == ["conflicting duplicate of r1/vehicle/173/4"]
