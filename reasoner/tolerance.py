"""How far a figure read off the record may be from the truth: the uncertainty a margin carries
and a stated fact is weighed against (DESIGN "Margins", "Weighing"; docs/history.md gives the
reasoning).

    moment_between(a, b, t, speed)      ± seconds of a moment interpolated between samples a, b
    place_between(a, b, t)              ± metres of a position interpolated between them
    speed_between(a, b)                 ± m/s of a speed interpolated between them
    beyond_stopping(change)             metres beyond rule 126's stopping distance when a light
                                        changed, and ± of that
    sensor_of(passage, sample)          the tolerance the sample's source states, else the defaults
    deceleration(braking, sensor)       ± m/s² of a deceleration averaged between two samples
    lowest_between(a, b, sensor)        the slowest a road user can have been between two samples
    still_between(standstill, series)   ± s of a standstill's duration (it may have begun and ended
                                        anywhere between its first and last sample and their neighbours)

Three sources, added (a bound, not a standard deviation: a court asks whether the act is proved,
not how likely it is):
- interpolation over the sampling interval: a moment found between two samples lies somewhere
  in their interval, so it is known to within the longer of its two distances to them (the
  motion between samples is not recorded; linear interpolation is exact only at steady speed),
  and a position at a moment to within the travel to the farther of them;
- the sensors' tolerance: what the producer states for the source (DESIGN "Kinds": `tolerance`
  on an entity.spawn, for the road user's own states; on a monitor's entry in the map, for its
  observations; reasoner/sensors.py), else the defaults POSITION_TOLERANCE_M on a position and
  SPEED_TOLERANCE_MPS on a speed: a lane-level position (a tenth of a metre: under a tenth of a
  lane) and a speed to a tenth of a metre per second (0.22 mph). Every margin says which it used;
- a moment on a signal's clock: its report is the change (DESIGN signal.state), so none.
"""
from __future__ import annotations

from .history import MAX_DECEL_MPS2, MPH_PER_MPS, Braking, Sample
from .history import AtChange, Passage, Standstill
from .history import DEFAULT, POSITION_TOLERANCE_M, SPEED_TOLERANCE_MPS, Sensor
from .stopping import stopping_distance_m

SECOND = 1_000_000_000
__all__ = ["POSITION_TOLERANCE_M", "SPEED_TOLERANCE_MPS", "DEFAULT", "Sensor"]


def moment_between(a: Sample, b: Sample, t: int, speed_mps: float | None, sensor: Sensor = DEFAULT) -> float:
    """± s of a moment t interpolated between a and b (a line crossed between them): the farther
    of the two samples in time, and the time a position tolerance takes at the speed then."""
    spread = max(t - a.t, b.t - t, 0) / SECOND
    tol = sensor.position_m
    return spread + (tol / speed_mps if speed_mps and speed_mps > tol else 0.0)


def place_between(a: Sample, b: Sample, t: int, sensor: Sensor = DEFAULT) -> float:
    """± m of the position at t interpolated between a and b, along the way: the farther of the
    two measured positions from the interpolated one, and the sensors' tolerance."""
    if a is b or a.x is None or a.y is None or b.x is None or b.y is None or b.t == a.t:    # (not both placed)
        return sensor.position_m
    f = (t - a.t) / (b.t - a.t)
    travel = ((b.x - a.x) ** 2 + (b.y - a.y) ** 2) ** 0.5
    return max(f, 1.0 - f) * travel + sensor.position_m


def speed_between(a: Sample, b: Sample, sensor: Sensor = DEFAULT) -> float:
    """± m/s of a speed interpolated between a and b: it lay between the two measured speeds
    (no faster or slower in between is recorded), so to within their difference, and the
    sensors' tolerance."""
    if a is b or a.speed_mps is None or b.speed_mps is None:
        return sensor.speed_mps
    return abs(b.speed_mps - a.speed_mps) + sensor.speed_mps


def sensor_of(p: Passage | None, sample: Sample | None) -> Sensor:
    """The tolerance the sample's source states (the passage's `sensors`), else the defaults."""
    if p is None or sample is None:
        return DEFAULT
    return next((sensor for src, sensor in p.sensors if src == sample.ref.src), DEFAULT)


def deceleration(braking: Braking, sensor: Sensor = DEFAULT) -> float:
    """± m/s² of a deceleration averaged between two samples Δt apart: each speed may be off by
    the speed tolerance, so the drop by twice that, over Δt (2·tol/Δt); the moments are the
    producer's clock, taken as exact. The average over Δt is what the record shows: a harder
    peak inside it is not recorded, and is not assumed."""
    span = (braking.last.t - braking.first.t) / SECOND
    return 2 * sensor.speed_mps / span if span > 0 else float("inf")


def lowest_between(a: Sample, b: Sample, sensor: Sensor = DEFAULT) -> float:
    """The slowest (m/s) a road user seen at a's and b's speeds can have been between them:
    braking from a and pulling away to b at MAX_DECEL_MPS2 each ((va + vb - 4 m/s² × Δt) / 2, not
    below 0: a stop hides between them at 0), each speed taken as low as its tolerance allows."""
    if a.speed_mps is None or b.speed_mps is None:
        return 0.0
    va, vb = max(0.0, a.speed_mps - sensor.speed_mps), max(0.0, b.speed_mps - sensor.speed_mps)
    if a is b:
        return va
    dip = (va + vb - MAX_DECEL_MPS2 * (b.t - a.t) / SECOND) / 2
    return max(0.0, min(va, vb, dip))


def still_between(s: Standstill, series: tuple[Sample, ...]) -> float:
    """± s of a standstill's duration (its first to its last still sample, a lower bound): it may
    have begun as early as the sample before the first and ended as late as the one after the
    last, so up to those two intervals longer."""
    timed = [x.t for x in series if x.speed_mps is not None]
    before = max((t for t in timed if t < s.first.t), default=s.first.t)
    after = min((t for t in timed if t > s.last.t), default=s.last.t)
    return (s.first.t - before + after - s.last.t) / SECOND


def beyond_stopping(change: AtChange, sensor: Sensor = DEFAULT) -> tuple[float, float] | None:
    """How far beyond rule 126's stopping distance the vehicle was when the light changed
    (negative: nearer than it), and ± of that: the position's (`place_between`) and the
    stopping distance's over the speed's range (`speed_between`). None without a place or a
    speed then."""
    if change.to_line_m is None or change.speed_mps is None:
        return None
    placed = [s for s in change.used if s.placed]
    timed = [s for s in change.used if s.speed_mps is not None]
    u_place = place_between(placed[0], placed[-1], change.light.t, sensor) if placed else sensor.position_m
    u_speed = speed_between(timed[0], timed[-1], sensor) if timed else sensor.speed_mps
    needed = stopping_distance_m(change.speed_mps * MPH_PER_MPS)
    spread = max(abs(stopping_distance_m(max(0.0, change.speed_mps + d) * MPH_PER_MPS) - needed)
                 for d in (-u_speed, u_speed))
    return change.to_line_m - needed, u_place + spread

