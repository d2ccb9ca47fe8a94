"""The seconds around a moment as timelines: a vehicle's speed as it reported it and as monitors
observed it, and the colour each signal approach of a junction showed, handed to explain/ to
draw (the report's timeline, explain/svg_timeline.py).

The timelines are the record as it was sent, read from one state at the window's opening
(store.state_at: the values in force then) and the events within it. A speed that is not a
finite number is left out; a colour is kept as the signal sent it (the picture says what it
cannot name), and a signal approach is keyed as the store's state keys it (its text, "*" where
the report names none), so that the opening values and the changes after them meet.

The verdicts read signals through reasoner/signals.py, which keeps only DESIGN's colours and
merges a junction-wide signal into every approach; a timeline shows each approach's own reports.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

from store import State, Store, state_at
from store.run_map import finite_number

# What other rooms take from here (tests/architecture/test_walls.py): the timeline around a moment and
# the values it is made of, which the report draws (explain/report_data.py)
__all__ = ["ApproachPhases", "ObservedSpeed", "Phase", "SpeedSample", "Timeline", "timeline"]

SECOND = 1_000_000_000
BEFORE_NS = 20 * SECOND      # a timeline starts this long before the moment ...
AFTER_NS = 5 * SECOND        # ... and ends this long after it


@dataclass(frozen=True)
class SpeedSample:
    """A speed the vehicle reported itself (entity.state `seq`)."""

    t: int
    speed_mps: float
    seq: int

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "speed_mps": self.speed_mps, "seq": self.seq}


@dataclass(frozen=True)
class ObservedSpeed:
    """A speed a monitor observed of the vehicle (its monitor.observation `seq`)."""

    t: int
    speed_mps: float
    monitor: str
    seq: int

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "speed_mps": self.speed_mps, "monitor": self.monitor, "seq": self.seq}


@dataclass(frozen=True)
class Phase:
    """A signal approach showed `colour` (as sent) from t: the opening value, or a change."""

    t: int
    colour: Any

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "colour": self.colour}


@dataclass(frozen=True)
class ApproachPhases:
    """One signal approach's colours over the window, in time order."""

    approach: str
    phases: tuple[Phase, ...]


@dataclass(frozen=True)
class Timeline:
    """The window [t_from, t_to] around t: the vehicle's speeds and its junction's signals."""

    t: int
    t_from: int
    t_to: int
    vehicle: str
    junction: str | None
    speed: tuple[SpeedSample, ...]
    observed_speed: tuple[ObservedSpeed, ...]
    signals: tuple[ApproachPhases, ...]

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "t_from": self.t_from, "t_to": self.t_to, "vehicle": self.vehicle,
                "junction": self.junction, "speed": [s.to_json() for s in self.speed],
                "observed_speed": [s.to_json() for s in self.observed_speed],
                "signals": {a.approach: [p.to_json() for p in a.phases] for a in self.signals}}


def timeline(store: Store, run: str, t: int, vehicle: str, junction: str | None,
             before_ns: int = BEFORE_NS, after_ns: int = AFTER_NS) -> Timeline:
    """The vehicle's speed (its own entity.state, and what monitors observed) and the colour of
    each signal approach of `junction`, from `before_ns` before t to `after_ns` after, with the
    values in force when the window opens."""
    t_from, t_to = t - before_ns, t + after_ns
    opening = state_at(store, run, t_from)
    return Timeline(t, t_from, t_to, vehicle, junction, _own(store, run, vehicle, opening, t_from, t_to),
                    _observed(store, run, vehicle, t_from, t_to),
                    _signals(store, run, junction, opening, t_from, t_to) if junction is not None else ())


def _own(store: Store, run: str, vehicle: str, opening: State, t_from: int, t_to: int) -> tuple[SpeedSample, ...]:
    """The speeds the vehicle reported: the one in force at t_from, then each in the window."""
    src = f"vehicle/{vehicle}"
    own: list[SpeedSample] = []
    first = (opening.entities.get(src) or {}).get("state") or {}
    speed = finite_number(first["body"].get("speed_mps")) if first else None
    if speed is not None:
        own.append(SpeedSample(first["t"], speed, first["seq"]))
    for ev in store.events(run, kinds=["entity.state"], srcs=[src], t_from=t_from, t_to=t_to):
        speed = finite_number(ev["body"].get("speed_mps"))
        if speed is not None and not (own and own[-1].seq == ev["seq"]):
            own.append(SpeedSample(ev["t"], speed, ev["seq"]))
    return tuple(own)


def _observed(store: Store, run: str, vehicle: str, t_from: int, t_to: int) -> tuple[ObservedSpeed, ...]:
    out = []
    for ev in store.events(run, kinds=["monitor.observation"], t_from=t_from, t_to=t_to):
        speed = finite_number(ev["body"].get("speed_mps"))
        if ev["body"].get("vehicle") == vehicle and speed is not None:
            out.append(ObservedSpeed(ev["t"], speed, ev["src"], ev["seq"]))
    return tuple(out)


def _signals(store: Store, run: str, junction: str, opening: State, t_from: int, t_to: int
             ) -> tuple[ApproachPhases, ...]:
    """Each approach's colour at t_from (its latest report then), then each change in the window."""
    phases: dict[str, list[Phase]] = {}
    for approach, shown in sorted((opening.signals.get(junction) or {}).items()):
        phases[approach] = [Phase(shown["last"]["t"], shown["colour"])]
    for ev in store.events(run, kinds=["signal.state"], t_from=t_from, t_to=t_to):
        body = ev["body"]
        if body.get("junction") == junction:
            changes = phases.setdefault(_as_key(body.get("approach", "*")), [])
            if not changes or changes[-1].colour != body.get("colour"):
                changes.append(Phase(ev["t"], body.get("colour")))
    return tuple(ApproachPhases(approach, tuple(found)) for approach, found in phases.items())


def _as_key(value: Any) -> str:
    """A body value as the state fold keys it (store/state.py), so the two readings meet."""
    return value if isinstance(value, str) else json.dumps(value, sort_keys=True)
