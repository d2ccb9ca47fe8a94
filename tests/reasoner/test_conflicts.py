"""The surrogate safety measures of reasoner/conflicts.py against figures worked by hand from their
definitions (docs/history.md, "Conflicts"): two road users crossing at right angles at constant
speeds, sampled at 5 Hz, so that linear interpolation between samples is exact.

V drives east along y = +1.75 at 5 m/s from x = -20 at t = 0; U drives north along x = -1.75. Both
are 2.55 m wide, so the conflict zone is the 2.55 m square about (-1.75, +1.75); a car occupies
it while its centre is within 2.5 m (half its 5 m) of the square: V from x = -5.525 to x = +2.025,
that is from t = 2.895 s to t = 4.405 s."""
from __future__ import annotations

import pytest

from reasoner.conflicts import conflict
from reasoner.history import Sample
from store import EventRef

S = 1_000_000_000


def track(src: str, x0: float, y0: float, vx: float, vy: float, n: int = 60) -> list[Sample]:
    out = []
    for i in range(n):
        t = i * 0.2
        out.append(Sample(round(t * S), x0 + vx * t, y0 + vy * t, abs(vx) + abs(vy), 0.0,
                          EventRef("r", src, i, round(t * S), "entity.state")))
    return out


V = track("vehicle/7", -20.0, 1.75, 5.0, 0.0)


def test_post_encroachment_time_after_the_vehicle_left():
    """U at 10 m/s from y = -60 enters the zone (y = -2.025) at 5.7975 s: PET = 5.7975 - 4.405."""
    c = conflict(V, track("vehicle/u", -1.75, -60.0, 0.0, 10.0), None)
    assert c.area_m2 == pytest.approx(2.55 * 2.55, abs=1e-6)
    assert (c.mine.entered / S, c.mine.left / S) == (pytest.approx(2.895, abs=1e-6), pytest.approx(4.405, abs=1e-6))
    assert c.first == "mine" and c.pet_s == pytest.approx(1.3925, abs=1e-6)


def test_time_to_collision_projected_gap_and_drac_on_a_collision_course():
    """U at 10 m/s from y = -30. At the act (2 s) V would occupy the zone 0.895-2.405 s on and U
    0.7975-1.5525 s on: TTC 0.895 s. From 1 s (U 17.975 m short of the zone at 10 m/s), unslowed
    it arrives at 2.7975 s, inside V's time there: gap 2.7975 - 4.405 = -1.6075 s; to arrive as
    V leaves (3.405 s later) it needs 2 (10 x 3.405 - 17.975) / 3.405² = 2.773 m/s² (DRAC)."""
    c = conflict(V, track("vehicle/u", -1.75, -30.0, 0.0, 10.0), 2 * S, onset=1 * S)
    assert c.pet_s == 0.0
    assert c.ttc_s == pytest.approx(0.895, abs=1e-6)
    assert c.projected_gap_s == pytest.approx(-1.6075, abs=1e-6)
    assert c.onset_to_zone_m == pytest.approx(17.975, abs=1e-6)
    assert c.drac_mps2 == pytest.approx(2 * (10 * 3.405 - 17.975) / 3.405 ** 2, abs=1e-6)


def test_a_vehicle_whose_record_ends_in_the_zone_is_there_with_one_coming_in_before_that_end():
    """V's record ends at 4.0 s, its centre at x = +0.0, still within the zone (it would leave at
    4.405 s): when it left is not in the record. U at 10 m/s from y = -30, 17.975 m short of the
    zone at 1 s, unslowed comes in at 2.7975 s, while V is still there by its own record: a
    collision course, its gap at most 2.7975 - 4.0 = -1.2025 s (the deceleration that would have
    let V go first is not measured). U from y = -60 would come in at 5.7975 s, after the record's
    end: the gap is not in the record. (The paper run's 266 in 279's passage: its record, as read
    there, ended in the lane it shared with 205.)"""
    cut = [s for s in V if s.t <= 4 * S]
    c = conflict(cut, track("vehicle/u", -1.75, -30.0, 0.0, 10.0), None, onset=1 * S)
    assert c.mine.left is None
    assert c.projected_gap_s == pytest.approx(-1.2025, abs=1e-6) and c.drac_mps2 is None
    late = conflict(cut, track("vehicle/u", -1.75, -60.0, 0.0, 10.0), None, onset=1 * S)
    assert late.projected_gap_s is None


def test_paths_that_never_meet_have_no_conflict():
    """U on the far footway, 8 m south of V's lane, walking east: the paths stay apart."""
    walker = track("pedestrian/p", -30.0, -6.25, 1.4, 0.0)
    assert conflict(V, walker, 2 * S, walker=True) is None


def _bent(src: str, points) -> list[Sample]:
    """A path through (t, x, y) points at 5 Hz, linear between them."""
    out = []
    for i in range(len(points) - 1):
        (t0, x0, y0), (t1, x1, y1) = points[i], points[i + 1]
        steps = round((t1 - t0) / 0.2)
        for k in range(steps + (i == len(points) - 2)):
            f = k / steps
            t = t0 + (t1 - t0) * f
            out.append(Sample(round(t * S), x0 + (x1 - x0) * f, y0 + (y1 - y0) * f, 10.0, None,
                              EventRef("r", src, len(out), round(t * S), "entity.state")))
    return out


def test_a_swerve_off_the_line_and_back_measures_its_offset_and_the_gap_kept_to_the_line():
    """U goes north along x = -1.75 at 10 m/s from y = -40 at t = 0: kept to that line it enters
    V's zone (y = -2.025) at 3.7975 s, while V is in it (2.895-4.405 s): PET 0, both in at once. It moves 2 m west between t = 2 and 3 s
    (y = -20 to -10), holds to t = 5, and comes back by t = 6: offset 2 m; it goes on north."""
    from reasoner.conflicts import SWERVE_M, swerve
    u = _bent("vehicle/u", [(0, -1.75, -40), (2, -1.75, -20), (3, -3.75, -10), (5, -3.75, 10), (6, -1.75, 20),
                            (8, -1.75, 40)])
    sw = swerve(V, u, round(2.0 * S), round(7.0 * S))
    assert sw is not None and sw.offset_m == pytest.approx(2.0, abs=1e-6) and sw.offset_m >= SWERVE_M
    assert sw.kept_pet_s == 0.0


def test_a_turn_is_no_swerve_and_a_drift_under_a_metre_is_none():
    """U turns right (east) off x = -1.75 at y = 0: its way afterwards is 90 degrees off its line,
    its own manoeuvre. W drifts 0.8 m sideways and back: under SWERVE_M (1 m)."""
    from reasoner.conflicts import swerve
    turn = _bent("vehicle/u", [(0, -1.75, -40), (4, -1.75, 0), (8, 38.25, 0)])
    assert swerve(V, turn, round(2.0 * S), round(7.0 * S)) is None
    drift = _bent("vehicle/w", [(0, -1.75, -40), (2, -1.75, -20), (3, -2.55, -10), (5, -2.55, 10), (6, -1.75, 20),
                                (8, -1.75, 40)])
    assert swerve(V, drift, round(2.0 * S), round(7.0 * S)) is None


def test_a_departure_wider_than_a_lane_and_a_car_is_another_way_not_a_swerve():
    """U leaves x = -1.75 for a way 20 m to the west and goes on north along it (a fork, or a turn
    the record shows only in part): its way afterwards is parallel to its line, so the turn test
    does not see it, but 20 m is no swerve within the road (SWERVE_MAX_M: a lane's width and a
    car's). The same path bent only 2 m (the swerve test above) is one."""
    from reasoner.conflicts import SWERVE_MAX_M, swerve
    fork = _bent("vehicle/u", [(0, -1.75, -40), (2, -1.75, -20), (3, -21.75, -10), (5, -21.75, 10), (8, -21.75, 40)])
    assert 20.0 > SWERVE_MAX_M
    assert swerve(V, fork, round(2.0 * S), round(7.0 * S)) is None
