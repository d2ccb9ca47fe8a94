"""A tick's bulk events, made the fast way, are the events the plain way makes: a tick's entity.states
in one call (Envelopes.make_all) number and time like one call each, and a monitor that looks only at
the squares about it observes exactly the vehicles in its cone, in the snapshot's order."""
from __future__ import annotations

import random

import pytest

from sim_replay.asking import Rulebooks
from sim_replay.faults import Faults
from sim_replay.monitors import Monitor
from sim_replay.senses import Around
from sim_replay.sim_config import FaultRates
from sim_replay.sim_events import Envelopes
from sim_replay.truth import Truth
from sim_replay.watchers import Watchers
from sim_replay.world_state import Snapshot, VehicleState


def test_make_all_numbers_and_times_each_source_as_make_does() -> None:
    one, bulk = Envelopes("r"), Envelopes("r")
    bodies = [("vehicle/1", {"x": 1.0}), ("vehicle/2", {"x": 2.0}), ("vehicle/1", {"x": 3.0})]
    expected = [one.make("vehicle/1", 0.0, "entity.spawn", {}), *(one.make(s, 0.1, "entity.state", b) for s, b in bodies)]
    got = [bulk.make("vehicle/1", 0.0, "entity.spawn", {}), *bulk.make_all(0.1, "entity.state", bodies)]
    assert got == expected
    assert [e["seq"] for e in got] == [0, 1, 0, 2] and bulk.count == one.count == 4
    assert bulk.make("vehicle/2", 0.2, "entity.state", {})["seq"] == 1     # numbering goes on after a bulk call
    assert bulk.make_all(0.3, "entity.state", []) == []


def test_make_all_under_the_lost_event_fault_loses_what_make_loses() -> None:
    lose = lambda src, kind, seq: seq % 2 == 1       # noqa: E731  (every other event of each source)
    one, bulk = Envelopes("r", lose), Envelopes("r", lose)
    bodies = [(f"vehicle/{i % 3}", {"i": i}) for i in range(9)]
    expected = [e for e in (one.make(s, 1.0, "entity.state", b) for s, b in bodies) if e is not None]
    assert bulk.make_all(1.0, "entity.state", bodies) == expected
    assert (bulk.count, bulk.lost) == (one.count, one.lost) == (6, 3)


def _vehicle(i: int, x: float, y: float) -> VehicleState:
    return VehicleState(str(i), "car", x, y, 0.0, 5.0, 0.0, "e", "e", "e_0", 1.0, 0, None, None, None,
                        None, None, None, None, True, False)


def test_a_monitor_observes_every_vehicle_in_its_cone_and_no_other_in_the_snapshots_order() -> None:
    rng = random.Random(4)
    vehicles = sorted((_vehicle(i, rng.uniform(-400, 400), rng.uniform(-400, 400)) for i in range(600)),
                      key=lambda v: v.id)          # SUMO's order: by id
    snap = Snapshot(1, 0.1, tuple(vehicles), (), (), (), (), (), ())
    monitors = (Monitor("near", "j1", 10.0, -20.0, 45.0, 80.0, 90.0),
                Monitor("wide", "j1", 0.0, 0.0, 300.0, 5000.0, 120.0))    # a reach wider than the network
    truth = Truth("r", 0, {})
    watchers = Watchers(monitors, Rulebooks(), Faults(FaultRates(), 0, truth))
    observed: list[tuple[str, str]] = []
    seen = watchers.observe(0.1, Around(snap, _NoJunctions()), {}, {}, {},
                            lambda src, kind, body: observed.append((src, body["vehicle"])))
    for m in monitors:
        inside = [v.id for v in vehicles if m.sees(v.x, v.y)]
        assert inside, f"no vehicle in {m.id}'s cone: the test shows nothing"
        assert [vid for src, vid in observed if src == f"monitor/{m.id}"] == inside
        assert {vid for mid, vid in seen if mid == m.id} == set(inside)


class _NoJunctions:
    """A network whose vehicles approach no junction (Around asks for nothing else)."""

    junctions: dict = {}


def test_entity_states_round_afresh_whenever_sumo_reports_other_numbers() -> None:
    """A vehicle standing still keeps its rounded values; one that moves by less than the rounding,
    or moves again, gets its values rounded afresh, exactly as round() gives them."""
    from sim_replay.sim_config import SimConfig
    from sim_replay.simulation import Simulation
    sim = Simulation(SimConfig(run="r"))
    sim._out, sim.agents = [], {}
    positions = [(10.004, 5.126), (10.004, 5.126), (10.006, 5.126), (10.006, 5.126), (12.5, -3.335)]
    for step, (x, y) in enumerate(positions, start=1):
        v = _vehicle(7, x, y)._replace(speed_mps=x / 7, accel_mps2=-y / 3, heading_deg=x * 9.87)
        sim._states(Snapshot(step, step / 10, (v,), (), (), (), (), (), ()), step / 10)
    bodies = [e["body"] for e in sim._out]
    assert [(b["x"], b["y"], b["heading_deg"], b["speed_mps"], b["accel_mps2"]) for b in bodies] == \
        [(round(x, 2), round(y, 2), round(x * 9.87, 1), round(x / 7, 2), round(-y / 3, 2)) for x, y in positions]
    assert [e["seq"] for e in sim._out] == [0, 1, 2, 3, 4] and sim.by_kind == {"entity.state": 5}
    assert bodies[0] is not bodies[1]           # each event its own body


def test_each_tick_carries_its_events_canonical_bytes_and_a_measurement_not_plain_is_encoded_by_the_reference() -> None:
    """Tick.payloads are what Outlets.put_all publishes as they are: each must be canonical_json's
    bytes of its event, whether _states wrote it with orjson straight away (plain measurements) or
    left it to canonical_json (here an acceleration of 1e300, which orjson would write otherwise,
    and a NaN, which the canonical form refuses rather than writing null)."""
    import math

    from sim_replay.sim_config import SimConfig
    from sim_replay.simulation import Simulation
    from store.canonical import reference_canonical_json
    sim = Simulation(SimConfig(run="r"))
    sim.agents = {}
    vehicles = (_vehicle(7, 10.004, 5.126), _vehicle(8, 3.0, -0.000004)._replace(accel_mps2=1e300))
    sim._states(Snapshot(1, 0.1, vehicles, (), (), (), (), (), ()), 0.1)
    assert sim._written[0] is not None and sim._written[1] is None    # the second is left to canonical_json
    tick = next(sim._batch())
    assert tick.payloads == [reference_canonical_json(ev) for ev in tick] and b"1e+300" in tick.payloads[1]
    sim._states(Snapshot(2, 0.2, (_vehicle(9, math.nan, 1.0),), (), (), (), (), (), ()), 0.2)
    with pytest.raises(ValueError):
        next(sim._batch())


@pytest.mark.parametrize("faults", [FaultRates(), FaultRates(lost_event=0.01, speed_error=0.01)])
def test_a_simulations_ticks_carry_the_canonical_bytes_of_every_event(faults: FaultRates) -> None:
    """A short run of the bundled map, without faults and with them (lost events among them: the
    states are then made one by one): every payload is the reference's bytes of its event, every
    key (Tick.zenoh_keys, kept per vehicle) the key the store gives it, and the events are those
    events() gives."""
    from sim_replay.sim_config import SimConfig
    from sim_replay.simulation import Simulation
    from store.wire import key_for
    from store.canonical import reference_canonical_json
    config = SimConfig(run="w", vehicles=8, duration_s=12.0, seed=4, pedestrians=1, faults=faults)
    ticks = list(Simulation(config).batches())
    assert sum(len(t) for t in ticks) > 500 and all(len(t.payloads) == len(t) for t in ticks)
    assert all(payload == reference_canonical_json(ev) for t in ticks for ev, payload in zip(t, t.payloads))
    assert all(len(t.zenoh_keys) == len(t) for t in ticks)
    assert all(key == key_for(ev) for t in ticks for ev, key in zip(t, t.zenoh_keys))
    assert [ev for t in ticks for ev in t] == list(Simulation(config).events())
