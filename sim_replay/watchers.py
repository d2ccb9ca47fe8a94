"""Monitors at work: each camera observes the road users inside its cone, and only what a camera can tell.

What a monitor states about a vehicle V it sees (monitor.observation), and why it can:

    V is of type T                 the body it sees; an unmarked police car is a car
    V is on an emergency call      only while V's blue lights flash: a camera sees the lights, not the call
    V has C light                  before V's line, the signal facing V's approach (it sees the heads)
    V crossed the stop line on C   the light showing in the tick it saw V's front pass the line
                                   (a stop-line camera's record); not stated when it did not see it
    V has a S sign                 V is on, or came from, a Stop / Give Way approach
    V has stopped at the stop line it saw V stand still at the Stop line on this passage
    V has crossed the stop line,   V is past its line, inside the junction
    V is in the junction
    V is stopped, V has speed of N its measured speed (through the speed-error fault), in mph
    the speed limit is N           the signed limit of the road V is on
    U is of type T, U is approaching V, U is on the main road
                                   the road users about V's junction, as it sees them

With the observation it asks monitors.le, through the engine, whether V potentially violates
"enter the junction" or "exceed the speed limit" on exactly those sentences, and publishes a
monitor.potential_violation with the proof once per episode (consecutive observations on which
it holds), as reasoner.episodes reads them. Yellow-box acts are not observed yet: "the exit of the
box junction is clear" needs a camera judgement not modelled here.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from operator import attrgetter
from typing import Any

from reasoner.history import MPH_PER_MPS
from reasoner.vocabulary import (CROSSED_THE_STOP_LINE_ON, HAS_CROSSED_THE_STOP_LINE, HAS_LIGHT, HAS_SIGN,
                                 HAS_SPEED_OF, HAS_STOPPED_AT_THE_STOP_LINE, IS_APPROACHING, IS_IN_THE_JUNCTION,
                                 IS_OF_TYPE, IS_ON_AN_EMERGENCY_CALL, IS_ON_THE_MAIN_ROAD, IS_STOPPED,
                                 POTENTIALLY_VIOLATES, SPEED_LIMIT_IS)
from sim_replay.approach import AT_LINE_M
from sim_replay.asking import Rulebooks
from sim_replay.av import LIGHT_WORDS, SIGN_WORDS
from sim_replay.faults import Faults
from sim_replay.monitors import Monitor
from sim_replay.rounding import hundredths
from sim_replay.senses import STOPPED_MPS, Around
from sim_replay.sumo_world import BLUE_LIGHT
from sim_replay.world_state import VehicleState

__all__ = ["ACTIONS", "Line", "Watchers"]

RULEBOOK = "monitors.le"
ACTIONS = ("enter the junction", "exceed the speed limit")
FLASH_S = 1.5               # blue lights flash (SUMO: a second on, a second off): lit this recently is lit
FORGET_S = 5.0              # unseen this long: the next sighting is a new episode
_by_id = attrgetter("id")   # a snapshot's vehicles are in SUMO's order, by id: a monitor observes them in it


@dataclass(frozen=True)
class Line:
    """The line a vehicle is before or came over, and the light it crossed on (signal lines)."""

    junction: str
    approach: str
    kind: str
    crossed_on: str | None = None       # set once it is over the line


@dataclass
class _Sighting:
    last_s: float
    speed_factor: float
    crossing_seen: str | None = None    # the light it saw the vehicle cross on
    stopped_at_line: bool = False
    before_line: bool = False
    blue_at_s: float | None = None      # when it last saw the blue lights lit (they flash)
    active: set[str] = field(default_factory=set)   # actions of an open episode


class Watchers:
    """Every monitor of the run; `observe` is one observation round."""

    def __init__(self, monitors: tuple[Monitor, ...], books: Rulebooks, faults: Faults) -> None:
        self.monitors, self.books, self.faults = monitors, books, faults
        self._seen: dict[tuple[str, str], _Sighting] = {}
        self.potential_violations = 0

    def observe(self, t_s: float, around: Around, lines: dict[str, Line], lights: dict[tuple[str, str], str],
                limits: dict[str, int], emit) -> set[tuple[str, str]]:
        """One round: `emit(src, kind, body)` publishes; returns the (monitor, vehicle) pairs seen.
        Each camera looks only at the road users in the squares about it (Snapshot.near), in the
        snapshot's order: testing every vehicle of the network against every cone each tick was
        two million cone tests a minute at a thousand vehicles, for the few dozen a camera sees."""
        seen: set[tuple[str, str]] = set()
        snap = around.snap
        for m in self.monitors:
            src = f"monitor/{m.id}"
            for v in sorted((v for v in snap.near(m.x, m.y, m.range_m) if m.sees(v.x, v.y)), key=_by_id):
                seen.add((m.id, v.id))
                key = (m.id, v.id)
                s = self._seen.get(key)
                if s is None or t_s - s.last_s > FORGET_S:
                    s = self._seen[key] = _Sighting(t_s, self.faults.speed_factor(m.id, v.id))
                s.last_s = t_s
                if v.signals & BLUE_LIGHT:
                    s.blue_at_s = t_s
                facts = self._facts(m, v, s, around, lines.get(v.id), lights, limits.get(v.id))
                speed = v.speed_mps * s.speed_factor
                emit(src, "monitor.observation", {"vehicle": v.id, "facts": facts, "speed_mps": hundredths(speed),
                                                  "x": hundredths(v.x), "y": hundredths(v.y)})
                self._judge(src, v.id, s, facts, emit)
        return seen

    def _facts(self, m: Monitor, v: VehicleState, s: _Sighting, around: Around, line: Line | None,
               lights: dict[tuple[str, str], str], limit: int | None) -> list[str]:
        vid = v.id
        facts = [IS_OF_TYPE.text(vid, v.type)]
        if s.blue_at_s is not None and s.last_s - s.blue_at_s <= FLASH_S:
            facts.append(IS_ON_AN_EMERGENCY_CALL.text(vid))
        here = line if line is not None and line.junction == m.junction else None   # its line, at this junction
        if here is not None and here.crossed_on is None:      # before its line at this monitor's junction
            s.before_line = True
            if here.kind == "signal":
                facts += [HAS_LIGHT.text(vid, c) for c in LIGHT_WORDS[lights.get((here.junction, here.approach), "off")]]
            else:
                facts.append(HAS_SIGN.text(vid, SIGN_WORDS[here.kind]))
            if v.speed_mps < STOPPED_MPS and v.to_line_m is not None and v.to_line_m <= AT_LINE_M:
                s.stopped_at_line = True
            if here.kind == "stop" and s.stopped_at_line:
                facts.append(HAS_STOPPED_AT_THE_STOP_LINE.text(vid))
        elif here is not None and v.junction == m.junction:   # over its line, in the junction
            # what happened at the line is stated only by a camera that watched the vehicle there
            if s.before_line and s.crossing_seen is None and here.kind == "signal":
                s.crossing_seen = here.crossed_on         # it watched the line as the vehicle passed it
            if here.kind == "signal":
                if s.crossing_seen is not None:
                    facts += [CROSSED_THE_STOP_LINE_ON.text(vid, c) for c in LIGHT_WORDS[s.crossing_seen]]
            elif s.before_line:
                facts.append(HAS_SIGN.text(vid, SIGN_WORDS[here.kind]))
                if here.kind == "stop" and s.stopped_at_line:
                    facts.append(HAS_STOPPED_AT_THE_STOP_LINE.text(vid))
            facts += [HAS_CROSSED_THE_STOP_LINE.text(vid), IS_IN_THE_JUNCTION.text(vid)]
        if here is not None and here.crossed_on is None or (here is not None and v.junction == m.junction):
            for o in sorted(around.about(m.junction, vid, here.approach), key=lambda o: o.id):
                facts += [IS_OF_TYPE.text(o.id, o.type), IS_APPROACHING.text(o.id, vid)]
                if o.main_road:
                    facts.append(IS_ON_THE_MAIN_ROAD.text(o.id))
        speed = v.speed_mps * s.speed_factor
        if speed < STOPPED_MPS:
            facts.append(IS_STOPPED.text(vid))
        facts.append(HAS_SPEED_OF.text(vid, round(speed * MPH_PER_MPS)))
        if limit is not None:
            facts.append(SPEED_LIMIT_IS.text(limit))
        return facts

    def _judge(self, src: str, vid: str, s: _Sighting, facts: list[str], emit) -> None:
        for action in ACTIONS:
            question = POTENTIALLY_VIOLATES.text(vid, action)
            if not self.books.holds(RULEBOOK, question, facts, vid):
                s.active.discard(action)
                continue
            if action in s.active:
                continue
            s.active.add(action)
            asked = self.books.ask(RULEBOOK, question, facts)
            self.potential_violations += 1
            body: dict[str, Any] = {"vehicle": vid, "action": action, "facts": facts,
                                    "rulebook": self.books.sha256(RULEBOOK)}
            if asked.proof is not None:
                body["proof"] = asked.proof
            emit(src, "monitor.potential_violation", body)

