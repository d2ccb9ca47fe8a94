"""One vehicle's agent as the simulation keeps it: who drives it, its habits or its ADS, its passage.

The simulation loop (sim_replay.simulation) owns these; the ground truth's witness
(sim_replay.witness) reads who was driving and why. Nothing here decides anything.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from sim_replay import av, drivers
from sim_replay.approach import Passage
from sim_replay.demand import Departure

__all__ = ["Agent"]


@dataclass
class Agent:
    """One vehicle's driver (or ADS) and what the simulation keeps about it."""

    d: Departure
    rng: Any
    profile: drivers.Profile
    asks: bool                              # asks the rulebook (automated, emergency crews)
    recorder: bool
    ads: av.Ads | None = None
    on_call: bool = False
    recorder_stops_s: float | None = None
    passage: Passage | None = None
    asked_facts: tuple[str, ...] = ()
    speed_factor: float = 1.0
    route: tuple[str, ...] = ()

    @property
    def id(self) -> str:
        return self.d.id

    @property
    def driver(self) -> str:
        return "autonomous" if self.ads is not None else "human"

    def driving(self) -> str:
        """Who drives now, as the ground truth says it."""
        if self.ads is None:
            return "human"
        return "autonomous" if self.ads.engaged else "user"
