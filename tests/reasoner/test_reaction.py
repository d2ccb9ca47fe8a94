"""When a road user's braking cannot have been a reaction to the vehicle (reasoner/reaction.py):
the vehicle was out of its way a reaction time before, or well ahead of it going its way."""

from reasoner.history import VEHICLE_WIDTH_M


def _samples(points, t0=0, dt=200_000_000):
    from reasoner.history import Sample
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


def _track(user, points, t0=0, dt=200_000_000):
    """Samples (x, y, speed, heading) every dt from t0."""
    from reasoner.history import Sample
    from store import EventRef
    return tuple(Sample(t0 + i * dt, x, y, v, h, EventRef("r", f"vehicle/{user}", i, t0 + i * dt, "entity.state"))
                 for i, (x, y, v, h) in enumerate(points))


def _lane(x0, v, n, stop_after=None, decel=0.0):
    """Eastbound along y = 1.75 from x0 at v, 5 Hz; braking at `decel` from sample `stop_after` on."""
    out, x = [], x0
    for i in range(n):
        if stop_after is not None and i > stop_after:
            v = max(0.0, v - decel * 0.2)
        out.append((x, 1.75, v, 0.0))
        x += v * 0.2
    return out


def test_a_vehicle_ahead_that_brakes_in_the_lane_is_not_well_ahead_however_the_other_slowed():
    """U (13.4 m/s) begins to brake hard at 2 s; V is 45 m ahead in its lane at 13 m/s then, going
    its way (well ahead), and brakes to a stop from 3 s. Taken as it really was, U had slowed by
    then and kept its distance; as it would have been unslowed, it would have closed on V: V's
    braking is what U's slowing kept it clear of, so V is not "well ahead" (reaction.well_ahead)."""
    from dataclasses import replace
    from reasoner.history import Braking
    from reasoner.history import Other
    from reasoner.reaction import well_ahead
    u = _track("u", _lane(0.0, 13.4, 60, stop_after=10, decel=4.5))
    v = _track("v", _lane(45.0, 13.0, 60, stop_after=15, decel=6.0))
    braking = Braking(4.5, u[11], u[16])
    on = _track("u", [(u[-1].x + 2.0 * i, 1.75, 10.0, 0.0) for i in range(1, 80)], t0=u[-1].t + 200_000_000)
    other = Other(user="u", src="vehicle/u", samples=u, arm="west", closing=True, main_road=True,
                  closest_m=1.0, braking=braking, stopped=None, light=None, path=u + on)   # its way, read on
    assert not well_ahead(v, other)
    # the same V keeping its speed is well ahead
    steady = _track("v", _lane(45.0, 13.0, 60))
    assert well_ahead(steady, replace(other))
