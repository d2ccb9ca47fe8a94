"""The reads the reasoner asks of the store by name (run start, sequence gaps, one event's time,
a source's next report), so that no room outside store/ runs SQL."""
from tests.helpers.store_testkit import T0, event

MS = 1_000_000


def test_run_start_is_the_run_start_event_else_the_first_event(store):
    assert store.run_start("r1") is None
    store.append([event(0, t=T0 + 5 * MS), event(1, t=T0 + 9 * MS)])
    assert store.run_start("r1") == T0 + 5 * MS
    store.append([event(0, kind="run.start", t=T0 + 7 * MS)])  # recorded late, still the start
    assert store.run_start("r1") == T0 + 7 * MS
    assert store.run_names() == ["r1"] and store.sources("r1") == ["sim/world", "vehicle/173"]


def test_sequence_gaps_per_source(store):
    store.append([event(seq) for seq in (0, 1, 2)] + [event(seq, src="vehicle/9") for seq in (0, 3, 4, 7)])
    assert store.has_sequence_gaps("r1")
    assert store.sequence_gaps("r1", "vehicle/173") == []
    assert store.sequence_gaps("r1", "vehicle/9") == [(1, 2), (5, 6)]
    assert store.sequence_gaps("r1", "vehicle/none") == []


def test_a_complete_run_has_no_sequence_gaps(store):
    store.append([event(seq) for seq in range(5)] + [event(seq, src="vehicle/9") for seq in range(3)])
    assert not store.has_sequence_gaps("r1")
    assert not store.has_sequence_gaps("no-such-run")


def test_the_time_of_one_event_and_a_sources_next_report(store):
    store.append([event(seq, t=T0 + seq * 10 * MS) for seq in range(5)])
    assert store.t_of("r1", "vehicle/173", 3) == T0 + 30 * MS
    assert store.t_of("r1", "vehicle/173", 9) is None and store.t_of("r1", "vehicle/173", -1) is None
    assert store.next_t("r1", "vehicle/173", T0 + 10 * MS, T0 + 40 * MS) == T0 + 20 * MS
    assert store.next_t("r1", "vehicle/173", T0 + 40 * MS, T0 + 90 * MS) is None
