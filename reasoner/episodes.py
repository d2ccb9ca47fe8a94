"""Potential violations re-derived off line from what the monitors observed, as episodes.

A monitor observes a vehicle many times a second; the monitor rules hold on every observation
from the moment it passes the red light until it is through. One incident is one *episode*: the
consecutive observations of a vehicle by a monitor on which the rules derive the same action,
ended by an observation on which they do not, or by EPISODE_GAP_S without an observation.
Recorded potential violations are matched to the episode they fall in (within MATCH_S), so a
recorded one that no observation supports, and an episode nobody recorded, both show.

Re-deriving means asking the monitor rulebook once per observation. Most observations differ
from others only in which road users they are about, so answers are cached by the observation's
*shape* (shapes.py): its facts with the road users the rulebook never names renamed.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Iterator

from .engine import Engine, Rulebook
from .facts import FactReader
from .le.render import arg_text
from .le.sentences import constant
from .le.terms import Cond, Var
from .shapes import Shaper
from .vocabulary import POTENTIALLY_VIOLATES

SECOND = 1_000_000_000
EPISODE_GAP_S = 5
MATCH_S = 2
_EXACT_LIMIT = 500_000


@dataclass
class Episode:
    monitor: str
    vehicle: str
    action: str
    observations: list[dict] = field(default_factory=list)   # the observation events, in order
    recorded: list[dict] = field(default_factory=list)       # the matched potential violations

    @property
    def first(self) -> dict:
        return self.observations[0]

    @property
    def last(self) -> dict:
        return self.observations[-1]

    def observation_at(self, t: int) -> dict:
        """The observation the monitor had at t: the last at or before it, else the first."""
        found = self.first
        for obs in self.observations:
            if obs["t"] > t:
                break
            found = obs
        return found


class Rederiver:
    """Asks a monitor rulebook which actions each observation shows a vehicle potentially violating."""

    def __init__(self, engine: Engine, rb: Rulebook, reader: FactReader) -> None:
        self.engine, self.rb, self.reader = engine, rb, reader
        self._shaper = Shaper(rb)
        self._question = [Cond(atom=POTENTIALLY_VIOLATES.atom(Var("vehicle"), Var("action")))]
        self._cache: dict[tuple, frozenset[str]] = {}
        self._exact: dict[tuple, frozenset[str]] = {}    # (vehicle, *facts): most observations repeat
        self.asked = 0

    def actions(self, vehicle: str, facts: Any) -> frozenset[str]:
        if type(facts) is not list:
            return frozenset()
        try:
            exact = (vehicle, *facts)
            found = self._exact.get(exact)
        except TypeError:           # a fact that is not a string (an object, a list)
            exact, found = None, None
        if found is None:
            found = self._by_shape(vehicle, facts)
            if exact is not None:
                if len(self._exact) >= _EXACT_LIMIT:
                    self._exact.clear()
                self._exact[exact] = found
        return found

    def _by_shape(self, vehicle: str, facts: list) -> frozenset[str]:
        """The answer for the observation's shape (shapes.py), asked when it is new; an
        observation no shape can be made of is asked about as it is."""
        atoms = [a for a in (self.reader.atom(self.rb, s) for s in facts) if a is not None]
        me = constant(vehicle.split(" "))
        shaped = self._shaper.shape(atoms, me)
        if shaped is None:
            return self._ask(me, atoms)
        key, names = shaped
        found = self._cache.get(key)
        if found is None:
            found = self._cache[key] = self._ask(names.get(me, me), list(key))
        return found

    def _ask(self, me: Any, atoms: list) -> frozenset[str]:
        self.asked += 1
        if not atoms:
            return frozenset()
        result = self.engine.answers(self.rb, self._question, atoms, texts=False)
        return frozenset(arg_text(b[0][2]) for b in result.bindings if b[0][1] == me)


def episodes(observations: Iterable[dict], rederiver: Rederiver) -> Iterator[Episode]:
    """The episodes of a run's observations, given in (t, seq, src) order, as they close."""
    open_: dict[tuple[str, str], dict[str, Episode]] = {}
    actions = rederiver.actions
    for obs in observations:
        body = obs["body"]
        vehicle = body.get("vehicle")
        if type(vehicle) is not str:
            if not isinstance(vehicle, int) or isinstance(vehicle, bool):
                continue
            vehicle = str(vehicle)
        derived = actions(vehicle, body.get("facts"))
        key = (obs["src"], vehicle)
        current = open_.get(key)
        if not current:
            if not derived:
                continue        # the common case: nothing open, nothing derived
            current = open_[key] = {}
        for action in list(current):
            episode = current[action]
            if action not in derived or obs["t"] - episode.last["t"] > EPISODE_GAP_S * SECOND:
                yield current.pop(action)
        for action in derived:
            opened = current.get(action)
            if opened is None:
                opened = current[action] = Episode(obs["src"], vehicle, action)
            opened.observations.append(obs)
    for current in open_.values():
        yield from current.values()


def match(episode_list: list[Episode], recorded: Iterable[dict]) -> list[tuple[dict, Episode | None]]:
    """Each recorded potential violation with the episode it falls in (None: none does)."""
    index: dict[tuple[str, str, str], list[Episode]] = {}
    for ep in episode_list:
        index.setdefault((ep.monitor, ep.vehicle, ep.action), []).append(ep)
    out = []
    for pv in recorded:
        body = pv["body"]
        key = (pv["src"], str(body.get("vehicle")), str(body.get("action")))
        best, distance = None, None
        for ep in index.get(key, []):
            lo, hi = ep.first["t"] - MATCH_S * SECOND, ep.last["t"] + MATCH_S * SECOND
            if lo <= pv["t"] <= hi:
                d = 0 if ep.first["t"] <= pv["t"] <= ep.last["t"] else min(abs(pv["t"] - ep.first["t"]),
                                                                             abs(pv["t"] - ep.last["t"]))
                if distance is None or d < distance:
                    best, distance = ep, d
        if best is not None:
            best.recorded.append(pv)
        out.append((pv, best))
    return out
