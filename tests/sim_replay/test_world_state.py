"""Snapshot.near: the neighbourhood question the witness asks of every watched road user each tick
must never miss a neighbour, or a road user that braked behind another would be told apart wrongly."""
from __future__ import annotations

import math

from hypothesis import given, settings
from hypothesis import strategies as st

from sim_replay.world_state import Snapshot, VehicleState


def _vehicle(i: int, x: float, y: float) -> VehicleState:
    return VehicleState(f"v{i}", "car", x, y, 0.0, 5.0, 0.0, "e", "e", "e_0", 1.0, 0, None, None, None,
                        None, None, None, None, True, False)


def _snapshot(points: list[tuple[float, float]]) -> Snapshot:
    vehicles = tuple(_vehicle(i, x, y) for i, (x, y) in enumerate(points))
    return Snapshot(1, 0.1, vehicles, (), (), (), (), (), ())


coordinate = st.floats(min_value=-500.0, max_value=500.0, allow_nan=False)


@settings(max_examples=200, deadline=None)
@given(points=st.lists(st.tuples(coordinate, coordinate), max_size=60), x=coordinate, y=coordinate,
       within=st.floats(min_value=0.0, max_value=2000.0))
def test_near_holds_every_vehicle_within_reach(points, x, y, within) -> None:
    snap = _snapshot(points)
    near = {v.id for v in snap.near(x, y, within)}
    inside = {v.id for v in snap.vehicles if math.hypot(v.x - x, v.y - y) <= within}
    assert inside <= near
    assert len(near) == len({v.id for v in snap.near(x, y, within)})   # each once, asked twice


def test_near_leaves_out_the_far_side_of_the_network() -> None:
    snap = _snapshot([(0.0, 0.0), (10.0, 5.0), (400.0, 400.0)])
    assert {v.id for v in snap.near(0.0, 0.0, 25.0)} == {"v0", "v1"}
