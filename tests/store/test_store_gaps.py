"""Sequence gaps per (run, src), computed from the seqs stored."""

from tests.helpers.store_testkit import event


def test_no_gaps(store):
    store.append([event(i) for i in range(5)] + [event(i, src="vehicle/9") for i in range(2)])
    assert store.gaps() == []


def test_gaps_in_the_middle_and_at_the_start(store):
    store.append([event(i) for i in (0, 1, 4, 5, 9)])
    store.append([event(i, kind="signal.state") for i in (3, 4)])
    assert store.gaps() == [
        {"run": "r1", "src": "signal/J1", "missing": [[0, 2]], "highest": 4},
        {"run": "r1", "src": "vehicle/173", "missing": [[2, 3], [6, 8]], "highest": 9},
    ]


def test_per_run_and_filtered_by_run(store):
    store.append([event(0, run="a"), event(2, run="a"), event(1, run="b"), event(0, run="c")])
    everything = store.gaps()
    assert [(g["run"], g["missing"]) for g in everything] == [("a", [[1, 1]]), ("b", [[0, 0]])]
    assert store.gaps("b") == [{"run": "b", "src": "vehicle/173", "missing": [[0, 0]], "highest": 1}]
    assert store.gaps("c") == []
    assert store.gaps("unknown") == []


def test_a_filled_gap_disappears(store):
    store.append([event(0), event(2)])
    assert store.gaps()[0]["missing"] == [[1, 1]]
    store.append([event(1)])
    assert store.gaps() == []


def test_a_source_that_stopped_early_shows_no_gap(store):
    """What a source never sent after its last stored event cannot be told from what was lost."""
    store.append([event(0), event(1), event(0, src="vehicle/9")])
    assert store.gaps() == []


def test_large_seqs(store):
    assert store.append([event(0), event(2**62, t=0)]).stored == 2
    assert store.gaps() == [{"run": "r1", "src": "vehicle/173", "missing": [[1, 2**62 - 1]], "highest": 2**62}]
