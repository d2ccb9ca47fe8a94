"""Two paths through a junction come within a vehicle's width of each other, or not (reasoner/others.py):
the pruned search answers as measuring every pair of segments does."""

from hypothesis import given, settings, strategies as st

from reasoner.history.others import VEHICLE_WIDTH_M, _segment_gap, polylines_within

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
