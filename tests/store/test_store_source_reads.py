"""The reads a history needs (reasoner/history.py): one source's events in a time window, and the
monitors' observations of one vehicle; both through the store's indexes, both read-only."""
from hypothesis import given, settings
from hypothesis import strategies as st

from store import Store
from tests.helpers.store_testkit import T0, event

MS = 1_000_000


def states(n, *, src="vehicle/173", step_ms=100, start=0, skip=()):
    return [event(seq, src=src, kind="entity.state", t=T0 + seq * step_ms * MS,
                  body={"x": float(seq), "y": 0.0, "speed_mps": 5.0})
            for seq in range(start, start + n) if seq not in skip]


def test_a_window_of_one_source_in_time_order(store):
    store.append(states(50) + states(50, src="vehicle/9"))
    got = store.source_events("r1", "vehicle/173", t_from=T0 + 1000 * MS, t_to=T0 + 1500 * MS)
    assert [e["seq"] for e in got] == list(range(10, 16))
    assert {e["src"] for e in got} == {"vehicle/173"}
    assert [e["seq"] for e in store.source_events("r1", "vehicle/173")] == list(range(50))
    assert store.source_events("r1", "vehicle/none") == []
    assert store.source_events("r1", "vehicle/173", t_from=T0 + 10 ** 12) == []


def test_a_window_filters_kinds_and_steps_over_missing_seqs(store):
    evs = states(30, skip={11, 12, 13})
    evs += [event(30, kind="vehicle.perception", t=T0 + 1150 * MS)]
    store.append(evs)
    got = store.source_events("r1", "vehicle/173", t_from=T0 + 1000 * MS, t_to=T0 + 1600 * MS)
    assert [e["seq"] for e in got] == [10, 30, 14, 15, 16]        # in (t, seq) order: 30 at 1.15 s
    only = store.source_events("r1", "vehicle/173", kinds=["entity.state"], t_from=T0 + 1000 * MS,
                               t_to=T0 + 1600 * MS)
    assert [e["seq"] for e in only] == [10, 14, 15, 16]


def test_an_event_a_little_out_of_time_order_is_found(store):
    """The documented limit of the search: up to SEQ_SLACK (64) places out of time order is found;
    further out is not promised."""
    def late(seq, like):
        return event(seq, kind="entity.state", t=T0 + like * 100 * MS + 1, body={"x": 0.0, "y": 0.0, "speed_mps": 0.0})
    store.append(states(200) + [late(200, 170), late(201, 50)])   # 30 and 151 places out of order
    near = store.source_events("r1", "vehicle/173", t_from=T0 + 16_950 * MS, t_to=T0 + 17_050 * MS)
    assert [e["seq"] for e in near] == [170, 200]
    far = store.source_events("r1", "vehicle/173", t_from=T0 + 4_950 * MS, t_to=T0 + 5_050 * MS)
    assert [e["seq"] for e in far][:1] == [50]


@settings(max_examples=40)
@given(st.lists(st.integers(0, 400), min_size=1, max_size=80, unique=True),
       st.integers(0, 5_000), st.integers(0, 5_000))
def test_the_window_is_exactly_the_events_in_it(tmp_path_factory, seqs, a, b):
    """For a source whose t rises with its seq (gaps anywhere), the window read by bisection
    is exactly what a scan of every event would give."""
    t_from, t_to = T0 + min(a, b) * 10 * MS, T0 + max(a, b) * 10 * MS
    evs = [event(s, kind="entity.state", t=T0 + s * 13 * MS, body={"x": 0.0, "y": 0.0, "speed_mps": 1.0})
           for s in sorted(seqs)]
    with Store(tmp_path_factory.mktemp("w") / "gaps.db") as store:
        store.append(evs)
        got = [e["seq"] for e in store.source_events("r1", "vehicle/173", t_from=t_from, t_to=t_to)]
    assert got == [e["seq"] for e in evs if t_from <= e["t"] <= t_to]


def test_observations_of_one_vehicle(store):
    def obs(seq, vehicle, src="monitor/m1", ms=0):
        return event(seq, src=src, kind="monitor.observation", t=T0 + ms * MS,
                     body={"vehicle": vehicle, "facts": [], "speed_mps": 3.0})
    store.append([obs(0, "173", ms=0), obs(1, "9", ms=100), obs(2, "173", ms=200), obs(0, "173", "monitor/m2", 300),
                  obs(3, "1730", ms=400)])
    assert [(e["src"], e["seq"]) for e in store.observations_of("r1", "173")] == [
        ("monitor/m1", 0), ("monitor/m1", 2), ("monitor/m2", 0)]
    assert [e["seq"] for e in store.observations_of("r1", "173", srcs=["monitor/m1"], t_from=T0 + 100 * MS)] == [2]
    assert store.observations_of("r1", "nobody") == []


def test_reading_changes_nothing(db_path):
    with Store(db_path) as store:
        store.append(states(20))
    before = db_path.read_bytes()
    with Store.open_read_only(db_path) as store:
        assert len(store.source_events("r1", "vehicle/173", t_from=T0, t_to=T0 + 500 * MS)) == 6
        assert store.observations_of("r1", "173") == []
    assert db_path.read_bytes() == before
