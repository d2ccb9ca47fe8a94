"""state_of: the parts of the state one act needs, folded from their own sources' events, equal to
the same parts of state_at (the whole run's fold) at every t, whatever the events."""

import tempfile
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st
from tests.helpers.store_testkit import BODIES, T0, event

from store import Store
from store.partial_state import entity_at, entity_since, observation_at, state_of
from store.state import state_at

MS = 1_000_000
VEHICLES = ["vehicle/1", "vehicle/2", "pedestrian/3"]
ENTITY = ["entity.spawn", "entity.despawn", "entity.state", "vehicle.perception", "vehicle.decision",
          "ads.event", "vehicle.trace"]
ADS = ["activated", "deactivated", "transition_demand", "driver_override", "minimal_risk_manoeuvre", "failure",
       "emergency_manoeuvre_start", "emergency_manoeuvre_end"]
WATCHED = ["1", "2", "3", "01", "1 "]   # body.vehicle: a string (the schema refuses any other)

entity_events = st.lists(st.tuples(st.sampled_from(VEHICLES), st.sampled_from(ENTITY), st.integers(0, 400),
                                   st.integers(-3, 3), st.integers(0, 7)), max_size=60)
observations = st.lists(st.tuples(st.sampled_from(["monitor/m1", "monitor/m2"]), st.sampled_from(WATCHED),
                                  st.integers(0, 40_000)), max_size=30)


def build(picks, seen) -> list[dict]:
    """Events with t rising with seq by 100 ms steps, each moved by up to 3 steps either way (a
    producer's clock jitter: a few places out of order), or placed wherever for observations."""
    seqs: dict[str, int] = {}
    out = []
    for src, kind, step, jitter, n in picks:
        seq = seqs[src] = seqs.get(src, -1) + 1
        body = {"event": ADS[n]} if kind == "ads.event" else {**BODIES[kind], "n": n}
        t = T0 + max(0, seq * 100 + jitter * 100 + step) * MS
        out.append(event(seq, src=src, t=t, kind=kind, body=body))
    for src, vehicle, ms in seen:
        seq = seqs[src] = seqs.get(src, -1) + 1
        out.append(event(seq, src=src, t=T0 + ms * MS, kind="monitor.observation",
                         body={"vehicle": vehicle, "facts": [f"{vehicle} has red light"]}))
    return out


@settings(max_examples=120, deadline=None)
@given(picks=entity_events, seen=observations, extra=st.lists(st.integers(-1000, 45_000), max_size=5))
def test_each_part_equals_the_whole_folds(picks, seen, extra):
    events = build(picks, seen)
    with tempfile.TemporaryDirectory() as tmp, Store(Path(tmp) / "s.db") as store:
        store.append(events)
        stamps = sorted({e["t"] for e in events} | {T0 + ms * MS for ms in extra})
        for t in stamps[::max(1, len(stamps) // 12)] + stamps[-1:]:
            whole = state_at(store, "r1", t, use_snapshots=False)
            for src in VEHICLES:
                assert entity_at(store, "r1", src, t) == whole.entities.get(src), (src, t)
            for monitor in ("monitor/m1", "monitor/m2"):
                for key in WATCHED:
                    expected = whole.monitors.get(monitor, {}).get("observations", {}).get(key)
                    assert observation_at(store, "r1", monitor, key, t) == expected, (monitor, key, t)
            part = state_of(store, "r1", t, entities=VEHICLES, observed=[("monitor/m1", "1")])
            assert part.entities == {s: r for s, r in whole.entities.items() if s in VEHICLES}
            for src in VEHICLES:
                since = entity_since(store, "r1", src)
                assert (src in whole.entities) == (since is not None and since <= t)


def test_a_vehicle_respawned_starts_afresh_and_an_unknown_source_is_none(store):
    store.append([event(0, src="vehicle/9", t=T0, kind="entity.spawn"),
                  event(1, src="vehicle/9", t=T0 + 100 * MS, kind="vehicle.perception"),
                  event(2, src="vehicle/9", t=T0 + 200 * MS, kind="entity.despawn"),
                  event(3, src="vehicle/9", t=T0 + 300 * MS, kind="entity.spawn"),
                  event(4, src="vehicle/9", t=T0 + 400 * MS, kind="entity.state")])
    record = entity_at(store, "r1", "vehicle/9", T0 + 500 * MS)
    assert record["spawn"]["seq"] == 3 and record["state"]["seq"] == 4
    assert record["perception"] is None and record["despawned"] is None
    assert entity_at(store, "r1", "vehicle/9", T0 + 250 * MS)["despawned"]["seq"] == 2
    assert entity_at(store, "r1", "vehicle/8", T0 + 500 * MS) is None
    assert entity_at(store, "r1", "vehicle/9", T0 - 1) is None


def test_a_monitor_is_an_entity_from_its_spawn_and_a_signal_that_never_spawned_never_is(store):
    store.append([event(0, src="monitor/m9", t=T0 + 5 * MS, kind="monitor.observation"),
                  event(1, src="monitor/m9", t=T0 + 7 * MS, kind="entity.spawn"),
                  event(0, src="signal/J1", t=T0, kind="signal.state")])
    whole = state_at(store, "r1", T0 + 10 * MS, use_snapshots=False)
    assert "monitor/m9" in whole.entities and "signal/J1" not in whole.entities
    assert entity_since(store, "r1", "monitor/m9") == T0 + 7 * MS
    assert entity_since(store, "r1", "signal/J1") is None
    assert entity_at(store, "r1", "monitor/m9", T0 + 10 * MS) == whole.entities["monitor/m9"]
