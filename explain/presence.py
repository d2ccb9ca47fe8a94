"""Whether a road user was there at the moment a picture shows.

The store's state at t holds each entity's latest entity.state however old it is: a car that
last reported 30 s before the incident and then drove off the map (or stopped sending) still has
that position in the fold. Drawn in the scene, it would sit where it no longer is, e.g. under the
ambulance that reached the same stop line 30 s later. So the picture draws a road user only when
its latest position is fresh (see FRESH_NS); despawned ones are never in the scene at all (the
reasoner's scene leaves them out).
"""
from __future__ import annotations

from store import EventRef

SECOND = 1_000_000_000
FRESH_NS = 2 * SECOND
"""How old a reported position may be and still be drawn as where the road user was at t.

Two seconds: producers report entity.state at 10 Hz (DESIGN) and the paper's replay every
second, so a road user that is there has reported within 1 s even when it is slow, and within 2 s
after a lost report or two; one that has been silent for longer has most likely left or stopped
reporting. At 30 mph a vehicle covers 27 m in 2 s, about the width of a junction: a position
older than that would mislead more than it tells, and it stays in the JSON report for whoever
wants it."""


def presence_at(evidence: EventRef | None, t: int, fresh_ns: int = FRESH_NS) -> tuple[bool, float | None]:
    """`present` (its latest position is at most `fresh_ns` older than t) and `age_s` (how
    long before t that position was reported, None if none), from the position's evidence ref."""
    seen = evidence.t if evidence is not None else None
    if isinstance(seen, bool) or not isinstance(seen, int):
        return False, None
    age = t - seen
    return 0 <= age <= fresh_ns, age / SECOND
