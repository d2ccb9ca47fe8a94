"""A road user's way measured point by point through a grid of its segments (reasoner/reaction.py
`_Way`) finds what measuring every segment finds (`_on_way`, below), to the bit: the same segment, the
same distance along the way, the same direction, on ways with jumps, repeated points, points on
cell borders, and points that are not finite."""
import math
import random

from hypothesis import given, settings
from hypothesis import strategies as st

from reasoner.history import project
from reasoner.reaction import _Hit, _Way

_coord = st.floats(min_value=-200.0, max_value=200.0, allow_nan=False)


def _on_way(point, way, distance):
    """The reference: every segment measured, in the way's order (what reasoner/reaction.py did
    before the grid)."""
    x, y = point
    best = None
    along = 0.0
    for r, s in zip(way, way[1:]):
        length = math.dist(r, s)
        if min(r[0], s[0]) - distance < x < max(r[0], s[0]) + distance \
                and min(r[1], s[1]) - distance < y < max(r[1], s[1]) + distance:
            gap, f = project(point, r, s)
            if gap < distance and (best is None or gap < best[0]):
                unit = ((s[0] - r[0]) / length, (s[1] - r[1]) / length) if length else (0.0, 0.0)
                best = (gap, along + f * length, unit)
        along += length
    return None if best is None else _Hit(best[1], best[2])


def _walk(rng: random.Random, n: int) -> list[tuple[float, float]]:
    x, y, out = rng.uniform(-100, 100), rng.uniform(-100, 100), []
    for _ in range(n):
        jump = rng.random() < 0.03
        x += rng.gauss(0, 300 if jump else 3)
        y += rng.gauss(0, 3)
        out.append(out[-1] if out and rng.random() < 0.1 else (x, y))
    return out


def test_the_grid_finds_what_every_segment_finds_on_random_ways():
    rng = random.Random(16)
    hits = 0
    for _ in range(1500):
        way = _walk(rng, rng.randint(0, 80))
        distance = rng.choice([2.55, 0.5, 10.0, 8.0])
        grid = _Way(way, distance)
        for _ in range(20):
            if way and rng.random() < 0.6:
                a, b = rng.choice(way), rng.choice(way)
                point = (a[0] + rng.gauss(0, 2), b[1] + rng.gauss(0, 2))
            else:
                point = (rng.uniform(-150, 150), rng.uniform(-150, 150))
            found = grid.hit(point)
            assert found == _on_way(point, way, distance)
            hits += found is not None
    assert hits > 1000       # most of them near the way: the test measures hits, not only misses


def test_points_on_cell_borders_and_not_finite():
    way = [(0.0, 0.0), (8.0, 0.0), (16.0, 8.0), (16.0, 16.0), (1e300, 16.0), (-8.0, -8.0)]
    grid = _Way(way, 2.55)
    points = [(x, y) for x in (-8.0, -2.55, 0.0, 2.55, 8.0, 13.45, 16.0, 24.0) for y in (-2.55, 0.0, 8.0, 16.0)]
    points += [(math.inf, 0.0), (0.0, -math.inf), (math.nan, 1.0), (1e300, 16.0)]
    for point in points:
        assert grid.hit(point) == _on_way(point, way, 2.55), point


@settings(max_examples=300, deadline=None)
@given(st.lists(st.tuples(_coord, _coord), max_size=30), st.tuples(_coord, _coord),
       st.sampled_from([0.5, 2.55, 8.0]))
def test_any_way_and_point(way, point, distance):
    assert _Way(way, distance).hit(point) == _on_way(point, way, distance)
