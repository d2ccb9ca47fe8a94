"""The gap bookkeeping on its own: whatever order seqs arrive in, missing = not yet seen below the highest."""
from __future__ import annotations

from hypothesis import given
from hypothesis import strategies as st

from ingest.gap_tracker import GapTracker


def ranges_of(numbers: set[int]) -> list[list[int]]:
    """Sorted [first, last] runs of consecutive numbers."""
    out: list[list[int]] = []
    for n in sorted(numbers):
        if out and out[-1][1] == n - 1:
            out[-1][1] = n
        else:
            out.append([n, n])
    return out


@given(st.lists(st.integers(min_value=0, max_value=200), max_size=300))
def test_missing_is_complement_of_seen(seqs: list[int]) -> None:
    tracker = GapTracker()
    late = sum(tracker.observe("r", "vehicle/1", seq) for seq in seqs)
    seen = set(seqs)
    missing = set(range(max(seqs, default=-1) + 1)) - seen
    expected = [{"run": "r", "src": "vehicle/1", "missing": ranges_of(missing), "highest": max(seqs)}] if missing else []
    assert tracker.gaps() == expected
    in_order = sum(1 for i, seq in enumerate(seqs) if seq > max(seqs[:i], default=-1))
    assert late == len(seen) - in_order  # every first sighting is either new-highest or late


def test_sources_are_independent() -> None:
    tracker = GapTracker()
    for seq in (0, 1, 2):
        tracker.observe("r", "vehicle/1", seq)
    tracker.observe("r", "vehicle/2", 2)
    tracker.observe("q", "vehicle/1", 1)
    assert [(g["run"], g["src"], g["missing"]) for g in tracker.gaps()] == [
        ("q", "vehicle/1", [[0, 0]]),
        ("r", "vehicle/2", [[0, 1]]),
    ]


@given(st.lists(st.tuples(st.sampled_from(["vehicle/1", "vehicle/2"]), st.integers(min_value=0, max_value=50)),
                max_size=200), st.integers(min_value=1, max_value=40))
def test_a_batch_observed_at_once_is_the_same_as_one_by_one(arrivals: list[tuple[str, int]], batch: int) -> None:
    """What the writer does (a batch under one lock) leaves the same gaps and late counts as events
    observed one at a time."""
    one_by_one, batched = GapTracker(), GapTracker()
    late_one = sum(one_by_one.observe("r", src, seq) for src, seq in arrivals)
    late_batched = sum(batched.observe_all([("r", src, seq) for src, seq in arrivals[i:i + batch]])
                       for i in range(0, len(arrivals), batch))
    assert (late_batched, batched.gaps()) == (late_one, one_by_one.gaps())
    assert batched.highest("r", "vehicle/1") == one_by_one.highest("r", "vehicle/1")


def test_after_a_restart_a_source_goes_on_from_its_highest_seq_stored() -> None:
    """What an earlier ingest stored is not counted missing; a hole above it is."""
    tracker = GapTracker()
    tracker.stored_highest = lambda run, src: 99 if src == "vehicle/1" else None
    assert tracker.highest("r", "vehicle/1") == 99            # stored, nothing heard yet
    assert tracker.observe_all([("r", "vehicle/1", 200), ("r", "vehicle/2", 0)]) == 0
    assert tracker.gaps() == [{"run": "r", "src": "vehicle/1", "missing": [[100, 199]], "highest": 200}]


def test_highest_before_is_where_the_source_stood_at_the_previous_look() -> None:
    tracker = GapTracker()
    assert tracker.highest_before("r", "vehicle/1") is None
    tracker.observe_all([("r", "vehicle/1", 0), ("r", "vehicle/1", 1)])
    assert (tracker.highest_before("r", "vehicle/1"), tracker.highest("r", "vehicle/1")) == (None, 1)
    tracker.new_look()
    assert tracker.highest_before("r", "vehicle/1") == 1      # nothing since that look
    tracker.observe_all([("r", "vehicle/1", 2)])
    assert (tracker.highest_before("r", "vehicle/1"), tracker.highest("r", "vehicle/1")) == (1, 2)
