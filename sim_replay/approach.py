"""One vehicle's passage of one stop line, as its agent sees it: the physics a decision is made on.

A `Passage` begins when a vehicle comes within the decision distance of a stop line (a signal,
Stop or Give Way line; a major road has none) and ends when its front is over the line. It keeps
what the agents and the ground truth need across ticks: whether the vehicle has stood still at
the line, what its agent last decided, and the draws made once per passage (a habit acted on, a
misread light). `Moment` is one tick of it: the vehicle's state, the true light, who is about.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from sim_replay.senses import STOPPED_MPS, Other
from sim_replay.world_state import VehicleState

__all__ = ["AT_LINE_M", "COMFORT_DECEL", "Moment", "Passage", "can_stop"]

AT_LINE_M = 3.0          # standing within this of the line is standing at it
COMFORT_DECEL = 3.5      # m/s²: the braking a driver or an ADS plans a stop with
MARGIN_M = 1.0
MARGIN_S = 0.3          # ... of a quarter second's travel, up to MARGIN_M


def can_stop(v: VehicleState) -> bool:
    """Whether v can still stop before its line braking at COMFORT_DECEL (physics, not law)."""
    if v.to_line_m is None:
        return False
    margin = min(MARGIN_M, v.speed_mps * MARGIN_S)      # a vehicle standing at its line can stay there
    return v.to_line_m >= v.speed_mps * v.speed_mps / (2 * COMFORT_DECEL) + margin


@dataclass(frozen=True)
class Moment:
    """One tick of a passage."""

    t_s: float
    v: VehicleState
    light: str | None              # the colour truly facing its approach (signal lines)
    others: tuple[Other, ...]      # road users about the junction ahead (senses.Around.near)
    stopped_at_line: bool          # it has stood still at the line during this passage


@dataclass
class Passage:
    vehicle: str
    junction: str
    approach: str
    line: str                      # signal, stop, give_way
    began_s: float
    stopped_at_line: bool = False
    stopped_since_s: float | None = None
    go: bool | None = None         # the agent's latest decision: True go, False hold, None not yet
    held: bool = False             # the world holds it at the line
    draws: dict[str, Any] = field(default_factory=dict)   # once-per-passage draws (habit acted on, misread light)
    decision: dict[str, Any] | None = None                # the latest vehicle.decision body
    why: str = ""                  # what made the latest decision
    missed: set[str] = field(default_factory=set)
    kept: set[str] = field(default_factory=set)           # road users it was drawn not to miss

    def observe(self, v: VehicleState, t_s: float) -> None:
        if v.speed_mps < STOPPED_MPS and v.to_line_m is not None and v.to_line_m <= AT_LINE_M:
            self.stopped_at_line = True
            if self.stopped_since_s is None:
                self.stopped_since_s = t_s
        else:
            self.stopped_since_s = None
