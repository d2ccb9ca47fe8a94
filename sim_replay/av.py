"""Vehicles that ask the rulebook before they act: automated vehicles, and emergency vehicles' crews.

As in the paper, such a vehicle perceives its situation as facts in the core vocabulary, asks
highway_code.le "V can enter the junction" through the engine, and acts on the answer: held at
the line where it may not enter, let go where it may. It publishes what it perceived
(vehicle.perception), the question with its proof (vehicle.trace) and what it decided and did
(vehicle.decision). Python decides nothing about the law here: the ambulance on a call goes
through the red light only when the rulebook says it can (nothing approaching that it would
endanger or force to change speed or course).

Perception goes through the fault model: an ADS may misread the light (for the whole passage) or
miss a road user. What a sensor cannot tell is not stated: "V would force U to change speed or
course" is the vehicle's own prediction (U reaches the junction before V could be through it:
within FORCE_S, or FORCE_FROM_STOP_S when V sets off from a standstill),
"V is too close to the stop line to stop safely" its own braking distance.

`Ads` is the automated driving system's DSSAD story (ads.event, UN R157 §8.2.1): activated at
the start, transition demands at a seeded rate, answered by the user (driver_override: the user
drives, as a careful human, until the ADS is activated again) or not (minimal_risk_manoeuvre:
the vehicle slows down, then the ADS resumes).
"""
from __future__ import annotations

import random
from dataclasses import dataclass

from reasoner.vocabulary import (CAN, HAS_LIGHT, HAS_SIGN, HAS_STOPPED_AT_THE_STOP_LINE, IS_APPROACHING,
                                 IS_DRIVING_ITSELF, IS_OF_TYPE, IS_ON_AN_EMERGENCY_CALL, IS_ON_THE_MAIN_ROAD,
                                 IS_STOPPED, IS_TOO_CLOSE_TO_STOP, WOULD_FORCE)
from sim_replay.approach import Moment, Passage, can_stop
from sim_replay.asking import Asked, Rulebooks
from sim_replay.faults import Faults
from sim_replay.senses import STOPPED_MPS

__all__ = ["ACTION", "Ads", "FORCE_S", "LIGHT_WORDS", "perceive", "ask_to_enter"]

ACTION = "enter the junction"
RULEBOOK = "highway_code.le"
FORCE_S = 5.0            # a road user reaching the junction this soon would have to change speed or course
FORCE_FROM_STOP_S = 8.0  # ... when V still has to set off (about 5 s to clear a junction from rest, and a margin)
SLOW_MPS = 3.0
LIGHT_WORDS = {"red": ("red",), "red_amber": ("red", "amber"), "amber": ("amber",), "green": ("green",), "off": ()}
SIGN_WORDS = {"stop": "stop", "give_way": "give way"}


def perceive(vid: str, kind: str, p: Passage, m: Moment, *, engaged: bool, on_call: bool,
             faults: Faults | None, predicts: bool = True) -> list[str]:
    """The Vehicle Scenario as v senses it at this moment, through the fault model. `predicts`:
    with its own predictions ("too close to stop", "would force U"), as a vehicle that asks the
    rulebook states them; a human driver's recorder records what its sensors saw, without them."""
    v = m.v
    facts = [IS_OF_TYPE.text(vid, kind)]
    if on_call:
        facts.append(IS_ON_AN_EMERGENCY_CALL.text(vid))
    if engaged:
        facts.append(IS_DRIVING_ITSELF.text(vid))
    if p.line == "signal":
        light = m.light or "off"
        if engaged and faults is not None and "misread" not in p.draws:
            p.draws["misread"] = faults.misread_light(vid, light)
        seen = p.draws.get("misread") or light
        facts += [HAS_LIGHT.text(vid, c) for c in LIGHT_WORDS[seen]]
        if predicts and seen == "amber" and p.go is not False and not can_stop(v):
            facts.append(IS_TOO_CLOSE_TO_STOP.text(vid))
    else:
        facts.append(HAS_SIGN.text(vid, SIGN_WORDS[p.line]))
        if p.line == "stop" and p.stopped_at_line:
            facts.append(HAS_STOPPED_AT_THE_STOP_LINE.text(vid))
    if v.speed_mps < STOPPED_MPS:
        facts.append(IS_STOPPED.text(vid))
    for o in sorted(m.others, key=lambda o: o.id):
        if o.id in p.missed:
            continue
        if engaged and faults is not None and o.id not in p.kept:
            if faults.misses(vid, o.id):
                p.missed.add(o.id)
                continue
            p.kept.add(o.id)
        facts += [IS_OF_TYPE.text(o.id, o.type), IS_APPROACHING.text(o.id, vid)]
        if o.main_road:
            facts.append(IS_ON_THE_MAIN_ROAD.text(o.id))
        if predicts and not o.pedestrian and o.eta_s < (FORCE_FROM_STOP_S if v.speed_mps < SLOW_MPS else FORCE_S):
            facts.append(WOULD_FORCE.text(vid, o.id))
    return facts


def ask_to_enter(books: Rulebooks, vid: str, facts: list[str]) -> Asked:
    """highway_code.le: "V can enter the junction", on the vehicle's own facts, with the proof."""
    return books.ask(RULEBOOK, CAN.text(vid, ACTION), facts)


@dataclass
class Ads:
    """An automated driving system's state and its seeded DSSAD events."""

    level: int
    engaged: bool = True
    mode: str = "engaged"          # engaged, demand (waiting for the user), user, mrm
    until_s: float = 0.0
    answered: bool = True

    def tick(self, t_s: float, rng: random.Random, per_s: float) -> list[tuple[str, str]]:
        """The ads.events of this second (event, reason), changing the state as they say."""
        out: list[tuple[str, str]] = []
        if self.mode == "engaged" and rng.random() < per_s:
            self.mode, self.until_s = "demand", t_s + rng.uniform(2.0, 4.0)
            self.answered = rng.random() < 0.7
            out.append(("transition_demand", "end of the operational design domain"))
        elif self.mode == "demand" and t_s >= self.until_s:
            if self.answered:
                self.mode, self.engaged, self.until_s = "user", False, t_s + rng.uniform(20.0, 40.0)
                out.append(("driver_override", "the user took over"))
            else:
                self.mode, self.until_s = "mrm", t_s + 10.0
                out.append(("minimal_risk_manoeuvre", "transition demand not answered"))
        elif self.mode in ("user", "mrm") and t_s >= self.until_s:
            self.mode, self.engaged = "engaged", True
            out.append(("activated", "back within the operational design domain"))
        return out
