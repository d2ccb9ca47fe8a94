"""Reads: a run's events in (t, seq, src) order with filters; run summaries; counts."""

import random
import types

import pytest
from tests.helpers.store_testkit import T0, event

from store import RunSummary


@pytest.fixture
def mixed(store):
    """Run r1 from four sources with colliding timestamps, appended in shuffled order, plus r2."""
    evs = [
        event(0, src="sim/world", t=T0, kind="run.start"),
        event(0, src="signal/J1", t=T0 + 10, kind="signal.state"),
        event(0, src="vehicle/173", t=T0 + 10, kind="entity.spawn"),
        event(1, src="vehicle/173", t=T0 + 20),
        event(0, src="monitor/m1", t=T0 + 20, kind="monitor.observation"),
        event(1, src="signal/J1", t=T0 + 20, kind="signal.state"),
        event(2, src="vehicle/173", t=T0 + 20),
        event(3, src="vehicle/173", t=T0 + 30, kind="vehicle.decision"),
        event(1, src="sim/world", t=T0 + 40, kind="run.end"),
    ]
    shuffled = evs[:]
    random.Random(4).shuffle(shuffled)
    store.append(shuffled)
    store.append([event(0, run="r2", src="vehicle/9", t=T0 - 5)])
    return store, evs


def ids(events):
    return [(ev["t"] - T0, ev["seq"], ev["src"]) for ev in events]


def test_events_come_in_t_seq_src_order(mixed):
    store, evs = mixed
    got = list(store.events("r1"))
    assert ids(got) == sorted(ids(evs))
    assert got == sorted(evs, key=lambda ev: (ev["t"], ev["seq"], ev["src"]))


def test_events_are_streamed(mixed):
    store, _ = mixed
    stream = store.events("r1")
    assert isinstance(stream, types.GeneratorType)
    assert next(stream)["kind"] == "run.start"


def test_filter_by_kind(mixed):
    store, _ = mixed
    got = list(store.events("r1", kinds=["signal.state", "run.end"]))
    assert [ev["kind"] for ev in got] == ["signal.state", "signal.state", "run.end"]


def test_filter_by_source(mixed):
    store, _ = mixed
    assert ids(store.events("r1", srcs={"vehicle/173"})) == [(10, 0, "vehicle/173"), (20, 1, "vehicle/173"),
                                                              (20, 2, "vehicle/173"), (30, 3, "vehicle/173")]


def test_time_window_is_inclusive_at_both_ends(mixed):
    store, _ = mixed
    assert ids(store.events("r1", t_from=T0 + 20, t_to=T0 + 30)) == [
        (20, 0, "monitor/m1"), (20, 1, "signal/J1"), (20, 1, "vehicle/173"), (20, 2, "vehicle/173"),
        (30, 3, "vehicle/173")]
    assert ids(store.events("r1", t_to=T0)) == [(0, 0, "sim/world")]
    assert ids(store.events("r1", t_from=T0 + 40)) == [(40, 1, "sim/world")]


def test_filters_combine(mixed):
    store, _ = mixed
    got = store.events("r1", kinds=["vehicle.perception", "signal.state"], srcs=["vehicle/173"], t_from=T0 + 15)
    assert ids(got) == [(20, 1, "vehicle/173"), (20, 2, "vehicle/173")]


def test_empty_filters_match_nothing(mixed):
    store, _ = mixed
    assert list(store.events("r1", kinds=[])) == []
    assert list(store.events("r1", srcs=())) == []


def test_a_bare_string_filter_is_refused(mixed):
    store, _ = mixed
    with pytest.raises(TypeError):
        store.events("r1", kinds="signal.state")


def test_other_runs_are_not_mixed_in(mixed):
    store, _ = mixed
    assert [ev["run"] for ev in store.events("r2")] == ["r2"]
    assert list(store.events("r3")) == []


def test_runs_summary(mixed):
    store, _ = mixed
    assert store.runs() == [
        RunSummary("r1", 9, T0, T0 + 40, ("monitor/m1", "signal/J1", "sim/world", "vehicle/173")),
        RunSummary("r2", 1, T0 - 5, T0 - 5, ("vehicle/9",)),
    ]
    assert [r.to_json() for r in store.runs()] == [
        {"run": "r1", "events": 9, "first_t": T0, "last_t": T0 + 40,
         "sources": ["monitor/m1", "signal/J1", "sim/world", "vehicle/173"]},
        {"run": "r2", "events": 1, "first_t": T0 - 5, "last_t": T0 - 5, "sources": ["vehicle/9"]},
    ]
    assert list(store.runs()[0].to_json()) == ["run", "events", "first_t", "last_t", "sources"]


def test_runs_of_an_empty_store(store):
    assert store.runs() == []
    assert store.count() == 0


def test_count(mixed):
    store, _ = mixed
    assert (store.count(), store.count("r1"), store.count("r2"), store.count("r3")) == (10, 9, 1, 0)


def test_order_holds_with_several_sources_filtered(mixed):
    store, evs = mixed
    wanted = {"vehicle/173", "signal/J1", "monitor/m1"}
    expected = sorted((ev for ev in evs if ev["src"] in wanted), key=lambda ev: (ev["t"], ev["seq"], ev["src"]))
    assert list(store.events("r1", srcs=wanted)) == expected
