"""Injected faults, each with a rate and its own seeded stream, each recorded in the ground truth.

A fault is drawn where it would happen (a light read, a road user perceived, a speed measured, an
event published, a recorder running), from a random.Random of its own seeded by the run's seed
and the fault's name: turning one fault on does not change when another happens, and the same
seed gives the same faults. The simulation asks; this module only draws and records.
"""
from __future__ import annotations

import random

from sim_replay.sim_config import LOSSY_KINDS, FaultRates
from sim_replay.truth import InjectedFault, Truth

__all__ = ["Faults", "WRONG_COLOUR", "stream"]

# what an ADS that misreads a light sees instead: the colour that lets it go, or stops it
WRONG_COLOUR = {"red": "green", "red_amber": "green", "amber": "green", "green": "red"}
SPEED_ERROR = (1.12, 1.3)         # a camera's speed reading this many times the true speed


def stream(seed: int, name: str) -> random.Random:
    """A random stream of its own for one purpose of one run (str seeds are hashed stably)."""
    return random.Random(f"{seed}:{name}")


class Faults:
    def __init__(self, rates: FaultRates, seed: int, truth: Truth) -> None:
        self.rates, self.truth = rates, truth
        self._rng = {name: stream(seed, f"fault:{name}") for name in
                     ("misperceived_light", "missed_road_user", "speed_error", "lost_event", "recorder_stops")}
        self.t_s = 0.0                # the world's time, set by the simulation each step

    def _draw(self, name: str) -> bool:
        rate = getattr(self.rates, name)
        return rate > 0 and self._rng[name].random() < rate

    def misread_light(self, vehicle: str, colour: str) -> str | None:
        """The colour an automated vehicle sees instead, for a whole passage, or None."""
        if colour not in WRONG_COLOUR or not self._draw("misperceived_light"):
            return None
        wrong = WRONG_COLOUR[colour]
        self.truth.fault(InjectedFault("misperceived_light", self.t_s, f"vehicle/{vehicle}",
                                       {"light": colour, "perceived": wrong}))
        return wrong

    def misses(self, vehicle: str, other: str) -> bool:
        """Whether a vehicle's perception leaves out a road user approaching it (for the passage)."""
        if not self._draw("missed_road_user"):
            return False
        self.truth.fault(InjectedFault("missed_road_user", self.t_s, f"vehicle/{vehicle}", {"missed": other}))
        return True

    def speed_factor(self, monitor: str, vehicle: str) -> float:
        """1.0, or the factor by which a monitor's speed readings of a vehicle are wrong this sighting."""
        if not self._draw("speed_error"):
            return 1.0
        factor = round(self._rng["speed_error"].uniform(*SPEED_ERROR), 3)
        self.truth.fault(InjectedFault("speed_error", self.t_s, f"monitor/{monitor}",
                                       {"vehicle": vehicle, "factor": factor}))
        return factor

    def lose(self, src: str, kind: str, seq: int) -> bool:
        """Whether an event is lost on its way (only the kinds a lost event would not stop the run for)."""
        if kind not in LOSSY_KINDS or not self._draw("lost_event"):
            return False
        self.truth.fault(InjectedFault("lost_event", self.t_s, src, {"kind": kind, "seq": seq}))
        return True

    def recorder_stop(self, vehicle: str, start_s: float, end_s: float) -> float | None:
        """When a vehicle's recorder stops publishing (world seconds), or None."""
        if not self._draw("recorder_stops"):
            return None
        at = round(self._rng["recorder_stops"].uniform(start_s, max(start_s, end_s)), 1)
        self.truth.fault(InjectedFault("recorder_stops", at, f"vehicle/{vehicle}", {}))
        return at
