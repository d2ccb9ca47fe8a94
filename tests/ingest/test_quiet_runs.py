"""A run that never sends its run.end: once it has been quiet for the writer's run_quiet_s, what
the ingest keeps of it (its sources' seqs, its keys, its chain's end in the store) is let go, as
for an ended run; if it speaks again, its chain goes on from the store, unbroken."""
from __future__ import annotations

import time
from pathlib import Path

from ingest import IngestService
from sim_replay.publisher import EventPublisher
from store import Store
from tests.helpers.ingest_testkit import await_match, linked, make_event
from tests.helpers.store_testkit import event

QUIET_S = 0.4
SOURCES = [f"vehicle/{n}" for n in range(5)]


def states(run: str, seqs: range) -> list[dict]:
    return [make_event(src, seq, "entity.state", run=run) for seq in seqs for src in SOURCES]


def held_runs(ingest: IngestService) -> set[str]:
    """The runs the writer and its store still keep anything of (each seq tracked, each chain's end)."""
    writer = ingest._writer
    tracked = {run for run, _ in writer._tracker._sources} | set(writer._tracker._srcs)
    return tracked | {key.split("/")[1] for key in writer._inbox._keys_seen}


def wait_until(predicate, timeout: float) -> bool:
    deadline = time.monotonic() + timeout
    while not predicate():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.05)
    return True


def test_a_quiet_run_is_let_go_and_its_chain_goes_on_from_the_store_when_it_speaks_again(db_path: Path) -> None:
    with linked(db_path, "pub-listens", run_quiet_s=QUIET_S) as (publisher, ingest):
        quiet = [event(0, run="quiet", kind="run.start")] + states("quiet", range(3))
        await_match(publisher, quiet[0])
        publisher.publish_all(quiet)
        assert ingest.wait_until_stored(len(quiet), timeout=20), ingest.stats()
        assert "quiet" in held_runs(ingest)
        assert wait_until(lambda: "quiet" not in held_runs(ingest), timeout=10)   # no run.end: let go when quiet
        assert ingest.sources(60.0)[0] == len(SOURCES) + 1                       # still counted as seen

        again = states("quiet", range(3, 6)) + [event(1, run="quiet", kind="run.end")]
        publisher.publish_all(again)
        assert ingest.wait_until_stored(len(quiet) + len(again), timeout=20), ingest.stats()
        assert ingest.missing() == (0, 0)                  # it went on from its highest seq stored
        stats = ingest.stats()
        assert (stats["duplicates"], stats["rejected"]) == (0, 0)
    with Store(db_path) as store:
        assert store.count("quiet") == len(quiet) + len(again)
        assert [p for p, in store.connection.execute(
            "SELECT chain_pos FROM events WHERE run = 'quiet' ORDER BY chain_pos")] == list(range(len(quiet) + len(again)))
        assert store.verify().ok                            # one unbroken chain, checkpoints and all
        assert store.gaps("quiet") == []


def test_a_run_still_sending_is_kept(db_path: Path) -> None:
    with linked(db_path, "pub-listens", run_quiet_s=QUIET_S) as (publisher, ingest):
        first = [event(0, run="busy", kind="run.start")]
        await_match(publisher, first[0])
        publisher.publish_all(first)
        for seq in range(8):                                # something every QUIET_S / 4, for 2 x QUIET_S
            publisher.publish_all(states("busy", range(seq, seq + 1)))
            time.sleep(QUIET_S / 4)
            assert "busy" in held_runs(ingest)
        assert ingest.wait_until_stored(1 + 8 * len(SOURCES), timeout=20), ingest.stats()


def test_a_store_lets_go_of_a_quiet_runs_chain_and_goes_on_from_its_last_checkpoint(db_path: Path) -> None:
    with Store(db_path) as store:
        store.append([event(0, run="q", kind="run.start")] + states("q", range(2)))
        assert "q" in store._heads.chains and "q" in store._heads.sources
        store.release_runs(["q"])
        assert "q" not in store._heads.chains and "q" not in store._heads.sources
        assert not [key for key in store._heads.max_seq if key[0] == "q"]
        report = store.append(states("q", range(1, 3)))      # a repeat of seq 1, then seq 2
        assert (report.stored, report.duplicates) == (len(SOURCES), len(SOURCES))
        assert store.verify().ok
