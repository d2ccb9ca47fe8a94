"""Highway Code rule 126's typical stopping distances, and the distance at any speed.

The figures are the Highway Code's ("Typical Stopping Distances", rule 126; transcribed in
docs/legal/road-junctions-170-183.md, section "Stopping distances"): thinking
distance + braking distance = overall stopping distance, for a car in good conditions. They are
the published yardstick for "so close to it that to pull up might cause an accident" (HC 175);
typical figures, not a legal threshold, so a fact derived from them names them.

Between the table's speeds: its thinking distances are exactly 0.3 m per mph (0.67 s of
travel) and its braking distances grow with the square of speed (0.0150-0.0156 m per mph²), so
thinking is interpolated linearly and braking as speed² times the per-mph² figure interpolated
linearly between rows. That reproduces every row exactly and follows the physics between them.
Below 20 mph both use the 20 mph row's figures (0.3 m per mph; 0.015 m per mph²); above 70 mph
the 70 mph row's.
"""
from __future__ import annotations

import bisect

# (mph, thinking m, braking m, overall m): Highway Code rule 126
TABLE = ((20, 6, 6, 12), (30, 9, 14, 23), (40, 12, 24, 36), (50, 15, 38, 53), (60, 18, 55, 73), (70, 21, 75, 96))
SOURCE = "Highway Code rule 126, Typical Stopping Distances (20 mph 12 m, 30 mph 23 m, 40 mph 36 m, 50 mph 53 m, " \
         "60 mph 73 m, 70 mph 96 m)"


def stopping_distance_m(speed_mph: float) -> float:
    """Overall stopping distance (thinking + braking) at a speed, in metres."""
    return thinking_m(speed_mph) + braking_m(speed_mph)


def thinking_m(speed_mph: float) -> float:
    speed = max(0.0, speed_mph)
    return speed * _between(speed, [row[1] / row[0] for row in TABLE])


def braking_m(speed_mph: float) -> float:
    speed = max(0.0, speed_mph)
    return speed * speed * _between(speed, [row[2] / row[0] ** 2 for row in TABLE])


def _between(speed: float, ratios: list[float]) -> float:
    """A per-row ratio at a speed: linear between rows, the end rows' beyond them."""
    speeds = [row[0] for row in TABLE]
    i = bisect.bisect_right(speeds, speed)
    if i == 0:
        return ratios[0]
    if i == len(speeds):
        return ratios[-1]
    f = (speed - speeds[i - 1]) / (speeds[i] - speeds[i - 1])
    return ratios[i - 1] + (ratios[i] - ratios[i - 1]) * f
