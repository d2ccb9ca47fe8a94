"""A road user that the second limb does not reach, with the figures that decide it (issue 35).

A Stop or Give Way line kept lawfully (TSRGD 2016 Sch 9 Pt 7 para 1, HC 171 and 172), or a red
light crossed on a call (Sch 14 Pt 1 para 5(5)), still has to be cleared of the second limb: no
road user was caused to change speed or course to avoid an accident with the vehicle, and no
person was likely to be endangered. An explanation that says only "V would force U ...: not
recorded" gives a court nothing to weigh. This value gives U's measured figures (where it was,
how fast, how hard it braked and that braking's uncertainty, the time gap where their paths meet)
and the reason the record gives that V did not force or endanger it. reasoner/second_limb.py
works it out from the passage. The explanation renders it (explain/). It crosses rooms, so it is
a plain frozen value with `to_json`.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from store import EventRef

__all__ = ["Unforced"]


@dataclass(frozen=True)
class Unforced:
    """Road user `user`, about `vehicle`'s act, neither forced nor endangered by it.

    `reason` is one of REASONS' keys, and `words` says it with the figures. The figures are those
    the record measured, or None where it has none: its distance from the junction's centre and
    speed at the act, its hardest braking counted while the vehicle passed (± its uncertainty),
    the post-encroachment time where their paths meet (`first`: "mine" where the vehicle was in
    the zone first), and the gap it would have had there unslowed."""

    vehicle: str
    user: str
    type: str | None
    reason: str
    words: str
    distance_m: float | None = None
    speed_mps: float | None = None
    decel_mps2: float | None = None
    decel_uncertainty_mps2: float | None = None
    pet_s: float | None = None
    first: str | None = None
    projected_gap_s: float | None = None
    evidence: tuple[EventRef, ...] = ()

    @property
    def sentences(self) -> tuple[str, ...]:
        """The second limb's sentences about this road user that the record answers "no" to."""
        return (f"{self.vehicle} would force {self.user} to change speed or course",
                f"{self.vehicle} would endanger {self.user}")

    def to_json(self) -> dict[str, Any]:
        return {"vehicle": self.vehicle, "user": self.user, "type": self.type, "reason": self.reason,
                "words": self.words, "distance_m": self.distance_m, "speed_mps": self.speed_mps,
                "decel_mps2": self.decel_mps2, "decel_uncertainty_mps2": self.decel_uncertainty_mps2,
                "pet_s": self.pet_s, "first": self.first, "projected_gap_s": self.projected_gap_s,
                "evidence": [r.to_json() for r in self.evidence]}


REASONS = {
    "walking clear": "a pedestrian or cyclist not in or entering the vehicle's path within the window",
    "own control": "its own light, Stop or Give Way line, or the road user it followed",
    "no change": "it changed neither speed nor course as the law counts them",
    "paths apart": "its path never came within a vehicle's width of the vehicle's",
    "after clearing": "it began to slow more than a perception-reaction time after the vehicle was out of its way",
    "well ahead": "the vehicle was well ahead of it on its way, going its way",
    "clear of the zone": "unslowed, it would still have passed the conflict zone well apart from the vehicle",
    "through first": "it had gone through the conflict zone ahead of the vehicle before it changed speed or course",
    "leader": "it slowed behind its own leader",
    "nearer conflict": "it slowed for another road user whose conflict came first on its way",
    "stood on": "it stopped only after the vehicle had left their conflict zone and stood on beyond a "
                "perception-reaction time after",
    "joined behind": "it went through the conflict zone ahead of the vehicle, which joined its way behind it",
    "own turn": "it slowed for a turn of its own, and unslowed would have come to the conflict zone only after the "
                "vehicle had left it",
    "turned ahead": "it slowed for a turn of its own and went through the conflict zone ahead of the vehicle, which "
                    "came in behind it",
    "in doubt": "its braking does not exceed the threshold by more than its uncertainty",
    "other": "something else the record shows explains it",
}
