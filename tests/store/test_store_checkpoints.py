"""Checkpoints: every N events of a run, after run.end and at the end of each append call, each
with the count, the chain head, the Merkle root and frontier, and the previous checkpoint's count."""

import pytest
from tests.helpers.store_testkit import event, rows

from store import Store, merkle
from store import tail_check


def stored_hashes(db_path, run="r1"):
    return [bytes.fromhex(h) for (h,) in rows(db_path, "SELECT hash FROM events WHERE run = ? ORDER BY chain_pos", (run,))]


def recorded(db_path, run="r1"):
    return rows(db_path, "SELECT count, head, merkle_root, frontier, prev_count FROM checkpoints "
                         "WHERE run = ? ORDER BY id", (run,))


def assert_checkpoints_describe_the_chain(db_path, run="r1"):
    hashes = stored_hashes(db_path, run)
    for count, head, root, frontier, _ in recorded(db_path, run):
        assert head == hashes[count - 1].hex()
        assert root == merkle.merkle_root(hashes[:count]).hex()
        assert frontier == merkle.pack(merkle.frontier_of(hashes[:count]))


def test_every_n_events_and_at_the_end_of_the_call(db_path):
    with Store(db_path, checkpoint_every=3) as store:
        store.append([event(i) for i in range(10)])
    assert [(c, prev) for c, _, _, _, prev in recorded(db_path)] == [(3, 0), (6, 3), (9, 6), (10, 9)]
    assert_checkpoints_describe_the_chain(db_path)


def test_counts_are_per_run_across_calls(db_path):
    with Store(db_path, checkpoint_every=4) as store:
        store.append([event(i, run=run) for i in range(3) for run in ("a", "b")])
        store.append([event(i, run="a") for i in range(3, 9)])
    assert [c for c, *_ in recorded(db_path, "a")] == [3, 4, 8, 9]
    assert [c for c, *_ in recorded(db_path, "b")] == [3]
    assert [prev for *_, prev in recorded(db_path, "a")] == [0, 3, 4, 8]
    for run in ("a", "b"):
        assert_checkpoints_describe_the_chain(db_path, run)


def test_run_end_is_checkpointed_where_it_lands(db_path):
    evs = [event(0, kind="run.start"), event(0), event(1), event(1, kind="run.end"), event(2)]
    with Store(db_path) as store:
        store.append(evs)
    assert [c for c, *_ in recorded(db_path)] == [4, 5]
    assert_checkpoints_describe_the_chain(db_path)


def test_a_call_ending_on_a_multiple_of_n_writes_one_checkpoint(db_path):
    with Store(db_path, checkpoint_every=5) as store:
        store.append([event(i) for i in range(5)])
    assert [c for c, *_ in recorded(db_path)] == [5]


def test_duplicates_write_no_checkpoint(db_path):
    with Store(db_path, checkpoint_every=2) as store:
        store.append([event(i) for i in range(3)])
        store.append([event(i) for i in range(3)])
    assert [c for c, *_ in recorded(db_path)] == [2, 3]


def test_reopened_store_continues_from_the_checkpointed_frontier(db_path, monkeypatch):
    with Store(db_path, checkpoint_every=4) as store:
        store.append([event(i) for i in range(7)])

    def no_rebuild(leaves):
        raise AssertionError("the frontier should come from the latest checkpoint")

    with monkeypatch.context() as patched:
        patched.setattr(tail_check.merkle, "frontier_of", no_rebuild)
        with Store(db_path, checkpoint_every=4) as store:
            store.append([event(i) for i in range(7, 13)])
            assert store.verify().ok
    assert [c for c, *_ in recorded(db_path)] == [4, 7, 8, 12, 13]
    assert_checkpoints_describe_the_chain(db_path)


def test_another_connection_appending_is_seen(db_path):
    with Store(db_path, checkpoint_every=3) as first, Store(db_path, checkpoint_every=3) as second:
        first.append([event(0), event(1)])
        second.append([event(2), event(3)])
        first.append([event(4)])
        assert first.verify().ok
    assert [(c, prev) for c, _, _, _, prev in recorded(db_path)] == [(2, 0), (3, 2), (4, 3), (5, 4)]
    assert_checkpoints_describe_the_chain(db_path)


def test_checkpoints_are_listed_with_their_roots(store):
    store.append([event(0), event(1)])
    [checkpoint] = store.checkpoints("r1")
    assert checkpoint["count"] == 2 and checkpoint["prev_count"] == 0
    assert len(checkpoint["merkle_root"]) == 64 and len(checkpoint["head"]) == 64
    assert store.checkpoints("nope") == []


@pytest.mark.parametrize("every", [0, -1, 1.5, True, "10", None])
def test_checkpoint_interval_must_be_a_positive_integer(db_path, every):
    with pytest.raises(ValueError, match="checkpoint_every must be a positive integer"):
        Store(db_path, checkpoint_every=every)


def test_default_interval_is_a_thousand(db_path):
    with Store(db_path) as store:
        assert store.checkpoint_every == 1000
        store.append([event(i) for i in range(2500)])
    assert [c for c, *_ in recorded(db_path)] == [1000, 2000, 2500]
