"""Two paths through a junction come within a vehicle's width of each other, or not (reasoner/others.py):
the pruned search answers as measuring every pair of segments does."""

from hypothesis import given, settings, strategies as st

from reasoner.others import VEHICLE_WIDTH_M, _segment_gap, polylines_within

coord = st.floats(-60, 60, allow_nan=False, allow_infinity=False)
polyline = st.lists(st.tuples(coord, coord), min_size=2, max_size=12)


def smallest_gap(a, b):
    return min(_segment_gap(p, q, r, s) for p, q in zip(a, a[1:]) for r, s in zip(b, b[1:]))


@settings(max_examples=400, deadline=None)
@given(polyline, polyline, st.sampled_from([0.5, VEHICLE_WIDTH_M, 10.0]))
def test_the_pruned_search_answers_as_every_pair_does(a, b, distance):
    assert polylines_within(a, b, distance) == (smallest_gap(a, b) < distance)


def test_crossing_paths_and_parallel_lanes():
    # two paths crossing at the centre: a conflict point
    assert polylines_within([(-20, 0), (0, 0), (20, 0)], [(0, -20), (0, 20)], VEHICLE_WIDTH_M)
    # lanes 3.5 m apart, side by side through the junction: no conflict point
    assert not polylines_within([(-20, 0), (20, 0)], [(-20, 3.5), (20, 3.5)], VEHICLE_WIDTH_M)
    # 2 m apart: closer than a vehicle is wide
    assert polylines_within([(-20, 0), (20, 0)], [(20, 2.0), (-20, 2.0)], VEHICLE_WIDTH_M)
    # exactly a vehicle's width apart is not closer than it
    assert not polylines_within([(0, 0), (10, 0)], [(0, VEHICLE_WIDTH_M), (10, VEHICLE_WIDTH_M)], VEHICLE_WIDTH_M)


def _samples(points, t0=0, dt=200_000_000):
    from reasoner.motion import Sample
    from store import EventRef
    return [Sample(t0 + i * dt, x, y, 10.0, None, EventRef("r", "vehicle/v", i, t0 + i * dt, "entity.state"))
            for i, (x, y) in enumerate(points)]


def test_a_vehicle_crossing_the_others_way_is_cleared_at_its_first_position_a_width_beyond_it():
    from reasoner.reaction import cleared_at
    way = _samples([(1.75, y) for y in range(40, -41, -4)])          # down the main road, x = 1.75
    mine = _samples([(x, 1.75) for x in range(-12, 13, 2)])          # across it, 2 m a sample
    # last within 2.55 m of x = 1.75 at x = 4 (2.25 m off); first seen clear at x = 6, the 10th sample
    assert cleared_at(mine, way, VEHICLE_WIDTH_M) == 9 * 200_000_000


def test_a_vehicle_that_merges_into_the_others_lane_ahead_of_it_is_never_cleared():
    from reasoner.reaction import cleared_at
    way = _samples([(1.75, y) for y in range(40, -41, -4)])
    # out of the west arm, then turning into the main road's southbound lane ahead of the other
    mine = _samples([(-12, 1.75), (-6, 1.75), (-1, 1.0), (1.5, -3), (1.75, -8), (1.75, -14), (1.75, -20)])
    assert cleared_at(mine, way, VEHICLE_WIDTH_M) is None


def test_a_vehicle_that_never_came_near_the_others_way_has_nothing_to_clear():
    from reasoner.reaction import cleared_at
    way = _samples([(1.75, y) for y in range(40, 10, -4)])            # stops 10 m short of the centre
    mine = _samples([(x, -1.75) for x in range(12, -13, -2)])         # eastbound lane, far side
    assert cleared_at(mine, way, VEHICLE_WIDTH_M) is None


def test_the_deceleration_needed_to_keep_the_two_second_gap_behind_a_vehicle_ahead():
    from reasoner.reaction import needed_deceleration
    # 13.4 m/s behind one at 7.9 m/s 26.5 m ahead: room 26.5 - 8 - 2 × 7.9 = 2.7 m to lose 5.5 m/s
    assert abs(needed_deceleration(13.4, 7.9, 26.5) - 5.5 ** 2 / (2 * 2.7)) < 1e-9
    assert needed_deceleration(13.4, 14.0, 60.0) == 0.0          # pulling away, with room
    assert needed_deceleration(13.4, 14.0, 30.0) == float("inf")  # pulling away, but already too close
