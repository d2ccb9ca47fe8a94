"""One run, one producer, at the ingest (issue 37): a producer publishing into a run the store holds
from another producer (a replay of another recording of run X, a second simulation under the same
run id, into a `gaps serve` it cannot see the store of) had its events of the held identities
quarantined as conflicting duplicates and the rest (later seqs, a new source) chained onto the held
run. Now every one of its events is quarantined, "run ... held by another producer", none stored;
the same events again and a resumed run are stored as before. Loopback, explicit endpoints."""
from __future__ import annotations

from pathlib import Path

from store import Store
from tests.helpers.ingest_testkit import RUN, T0, await_match, linked, make_event

HELD = [make_event("vehicle/173", seq) for seq in range(5)]


def _holding(db_path: Path) -> None:
    with Store(db_path) as store:
        store.append(HELD)


def test_another_producers_events_of_a_held_run_are_refused_never_mixed(db_path: Path) -> None:
    _holding(db_path)
    # the same run id and source at other times (another recording), more seqs than are held,
    # and a source the store does not hold: before, 5 conflicting duplicates and 7 events chained on
    other = [make_event("vehicle/173", seq) | {"t": T0 + seq * 100_000_000 + 7_000_000} for seq in range(10)]
    other += [make_event("vehicle/174", seq) for seq in range(2)]
    with linked(db_path, "ingest-listens") as (publisher, ingest):
        for src in ("vehicle/173", "vehicle/174"):
            await_match(publisher, make_event(src, 0))
        publisher.publish_all(other)
        assert ingest.wait_until_settled(len(other), timeout=10), ingest.stats()
        stats = ingest.stats()
    assert (stats["stored"], stats["rejected"]) == (0, len(other)), stats
    with Store.open_read_only(db_path) as store:
        assert store.count(RUN) == len(HELD) and store.sources(RUN) == ["vehicle/173"]
        reasons = {row["reason"] for row in store.quarantined()}
        assert len(reasons) == 1 and f"run {RUN} held by another producer" in reasons.pop()
        assert store.quarantine_count() == len(other) and store.verify().ok


def test_the_same_events_again_and_a_resumed_run_are_stored(db_path: Path) -> None:
    _holding(db_path)
    again = HELD + [make_event("vehicle/173", seq) for seq in range(5, 8)]
    with linked(db_path, "ingest-listens") as (publisher, ingest):
        await_match(publisher, make_event("vehicle/173", 0))
        publisher.publish_all(again)
        assert ingest.wait_until_settled(len(again), timeout=10), ingest.stats()
        stats = ingest.stats()
    assert (stats["stored"], stats["duplicates"], stats["rejected"]) == (3, 5, 0), stats
    with Store.open_read_only(db_path) as store:
        assert store.count(RUN) == 8 and store.quarantine_count() == 0 and store.verify().ok
