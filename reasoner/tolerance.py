"""How far a figure read off the record may be from the truth: the uncertainty a margin carries
and a stated fact is weighed against (DESIGN "Margins", "Weighing"; docs/history.md gives the
reasoning).

    moment_between(a, b, t, speed)      ± seconds of a moment interpolated between samples a, b
    place_between(a, b, t)              ± metres of a position interpolated between them
    speed_between(a, b)                 ± m/s of a speed interpolated between them
    beyond_stopping(change)             metres beyond rule 126's stopping distance when a light
                                        changed, and ± of that

Three sources, added (a bound, not a standard deviation: a court asks whether the act is proved,
not how likely it is):
- interpolation over the sampling interval: a moment found between two samples lies somewhere
  in their interval, so it is known to within the longer of its two distances to them (the
  motion between samples is not recorded; linear interpolation is exact only at steady speed),
  and a position at a moment to within the travel to the farther of them;
- the sensors' tolerance: POSITION_TOLERANCE_M on a position, SPEED_TOLERANCE_MPS on a speed.
  No record in DESIGN's catalogue states its sensors' tolerance, so these are the tolerances a
  producer is held to: a lane-level position (a tenth of a metre: under a tenth of a lane) and
  a speed to a tenth of a metre per second (0.22 mph);
- a moment on a signal's clock: its report is the change (DESIGN signal.state), so none.
"""
from __future__ import annotations

from .motion import MPH_PER_MPS, Sample
from .passage import AtChange
from .stopping import stopping_distance_m

SECOND = 1_000_000_000
POSITION_TOLERANCE_M = 0.1
SPEED_TOLERANCE_MPS = 0.1


def moment_between(a: Sample, b: Sample, t: int, speed_mps: float | None) -> float:
    """± s of a moment t interpolated between a and b (a line crossed between them): the farther
    of the two samples in time, and the time a position tolerance takes at the speed then."""
    spread = max(t - a.t, b.t - t, 0) / SECOND
    sensor = POSITION_TOLERANCE_M / speed_mps if speed_mps and speed_mps > POSITION_TOLERANCE_M else 0.0
    return spread + sensor


def place_between(a: Sample, b: Sample, t: int) -> float:
    """± m of the position at t interpolated between a and b, along the way: the farther of the
    two measured positions from the interpolated one, and the sensors' tolerance."""
    if a is b or not (a.placed and b.placed) or b.t == a.t:
        return POSITION_TOLERANCE_M
    f = (t - a.t) / (b.t - a.t)
    travel = ((b.x - a.x) ** 2 + (b.y - a.y) ** 2) ** 0.5
    return max(f, 1.0 - f) * travel + POSITION_TOLERANCE_M


def speed_between(a: Sample, b: Sample) -> float:
    """± m/s of a speed interpolated between a and b: it lay between the two measured speeds
    (no faster or slower in between is recorded), so to within their difference, and the
    sensors' tolerance."""
    if a is b or a.speed_mps is None or b.speed_mps is None:
        return SPEED_TOLERANCE_MPS
    return abs(b.speed_mps - a.speed_mps) + SPEED_TOLERANCE_MPS


def beyond_stopping(change: AtChange) -> tuple[float, float] | None:
    """How far beyond rule 126's stopping distance the vehicle was when the light changed
    (negative: nearer than it), and ± of that: the position's (`place_between`) and the
    stopping distance's over the speed's range (`speed_between`). None without a place or a
    speed then."""
    if change.to_line_m is None or change.speed_mps is None:
        return None
    placed = [s for s in change.used if s.placed]
    timed = [s for s in change.used if s.speed_mps is not None]
    u_place = place_between(placed[0], placed[-1], change.light.t) if placed else POSITION_TOLERANCE_M
    u_speed = speed_between(timed[0], timed[-1]) if timed else SPEED_TOLERANCE_MPS
    needed = stopping_distance_m(change.speed_mps * MPH_PER_MPS)
    spread = max(abs(stopping_distance_m(max(0.0, change.speed_mps + d) * MPH_PER_MPS) - needed)
                 for d in (-u_speed, u_speed))
    return change.to_line_m - needed, u_place + spread


def deceleration_between(a: Sample, b: Sample) -> float:
    """± m/s² of a deceleration read as the drop in speed between two samples over the time
    between them (motion.peak_deceleration): each speed is known to ± SPEED_TOLERANCE_MPS, so the
    drop to twice that, spread over the span. The samples' times are the record's own (no
    interpolation), and the span is what the sampling gives: a whole number of sampling intervals
    of at least motion.MIN_DECEL_SPAN_S (at 2 Hz, 1 s or 1.5 s; at 10 Hz, 1 s or 1.1 s), so a
    braking read from sparse or irregular samples carries the uncertainty of its own span. The
    average over the span is itself a lower bound of the hardest second within it (a mean never
    exceeds the largest of the parts), so no more is owed to the motion between the samples."""
    span = (b.t - a.t) / SECOND
    return 2 * SPEED_TOLERANCE_MPS / span if span > 0 else float("inf")
