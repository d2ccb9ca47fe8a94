"""Human drivers: behaviour profiles, and what a driver with a profile does at a stop line.

A human driver does not ask the rulebook. It looks every `reaction_s` and does what its habits
make it do: stop for red and for an amber it can stop for, stop at a Stop line and wait for a gap,
wait at a Give Way line while traffic on the major road is close; unless a habit says otherwise on
this passage (the draw is once per passage, with the profile's propensity): run the amber, run the
red, roll over the Stop line at walking pace, pull out in front of traffic. A speeder drives at a
factor above the limit everywhere. What it does is carried out in the world (hold, release, speed
factor) and recorded in the ground truth with the habit that made it; whether it was lawful is for
the reasoner.
"""
from __future__ import annotations

import random
from dataclasses import dataclass

from sim_replay.approach import Moment, Passage, can_stop
from sim_replay.sim_config import Behaviour

__all__ = ["GAP_S", "Profile", "ROLL_FACTOR", "draw_profile", "human_decision"]

GAP_S = 5.0           # a driver waits while a road user it must let pass is this close in time
GAP_FROM_STOP_S = 8.0 # ... this close, when it has to set off from a standstill
STOP_WAIT_S = 1.5     # a careful driver stands this long at a Stop line before pulling out
ROLL_FACTOR = 0.2     # a Stop-line roller creeps over at this share of the limit (about 6 mph in a 30)


@dataclass(frozen=True)
class Profile:
    """A human driver's habits; `name` lists them ("careful" when none)."""

    name: str
    reaction_s: float
    speed_factor: float = 1.0
    runs_amber: bool = False
    runs_red: bool = False
    rolls_stop: bool = False
    ignores_give_way: bool = False
    recorder: bool = False

    @property
    def habits(self) -> tuple[str, ...]:
        return tuple(h for h, on in (("speeder", self.speed_factor > 1.0), ("amber runner", self.runs_amber),
                                     ("red runner", self.runs_red), ("stop roller", self.rolls_stop),
                                     ("no give way", self.ignores_give_way)) if on)


def draw_profile(rng: random.Random, b: Behaviour) -> Profile:
    """A driver's profile from the behaviour shares (each habit drawn on its own)."""
    reaction = round(rng.uniform(*b.reaction_s), 1)
    speeder = rng.random() < b.speeder
    factor = round(rng.uniform(*b.speeding_factor), 2) if speeder else 1.0
    runs_amber, runs_red = rng.random() < b.amber_runner, rng.random() < b.red_runner
    rolls, ignores = rng.random() < b.stop_roller, rng.random() < b.no_give_way
    recorder = rng.random() < b.recorder
    p = Profile("", reaction, factor, runs_amber, runs_red, rolls, ignores, recorder)
    return Profile(", ".join(p.habits) or "careful", reaction, factor, runs_amber, runs_red, rolls, ignores, recorder)


def _habit(p: Passage, rng: random.Random, name: str, has: bool, propensity: float) -> bool:
    """Whether the driver acts on a habit on this passage (drawn once per passage)."""
    if name not in p.draws:
        p.draws[name] = has and rng.random() < propensity
    return p.draws[name]


BREAKS_A_RULE = ("amber runner", "red runner", "stop roller", "no give way")
"""The habits whose go breaks a rule (human_decision's reasons start with their names)."""


def lawful(why: str) -> bool:
    """Whether a go for this reason is the driver keeping the rules (then it also watches for foes)."""
    return not why.startswith(BREAKS_A_RULE)


def human_decision(profile: Profile, p: Passage, m: Moment, rng: random.Random,
                   propensity: float) -> tuple[bool, str]:
    """Go (True) or hold (False) at this look, and why, in the words the ground truth keeps."""
    v = m.v
    if p.line == "signal":
        light = m.light or "off"
        if light == "green" or light == "off":
            return True, f"{light} light"
        if light == "amber":
            if _habit(p, rng, "runs_amber", profile.runs_amber, propensity):
                return True, "amber runner: went on at amber"
            if p.go is not False and not can_stop(v):     # one already stopping goes on stopping
                return True, "amber: too close to stop"
            return False, "stopping for amber"
        if _habit(p, rng, "runs_red", profile.runs_red, propensity):
            return True, "red runner: went on at red"
        return False, f"stopping for {light.replace('_', ' and ')}"
    gap = GAP_FROM_STOP_S if v.speed_mps < 3.0 else GAP_S
    clear = not any(o.main_road and o.eta_s < gap for o in m.others)
    if p.line == "stop":
        if _habit(p, rng, "rolls_stop", profile.rolls_stop, propensity):
            return True, "stop roller: rolled over the Stop line"
        if p.stopped_since_s is not None and m.t_s - p.stopped_since_s >= STOP_WAIT_S and clear:
            return True, "stopped at the Stop line, road clear"
        return False, "stopping at the Stop line" if not p.stopped_at_line else "waiting at the Stop line for a gap"
    if p.line == "give_way":
        if _habit(p, rng, "ignores_give_way", profile.ignores_give_way, propensity):
            return True, "no give way: pulled out regardless"
        return (True, "Give Way line, road clear") if clear else (False, "giving way to traffic on the major road")
    return True, "no line"
