"""The paper's scenarios at a moment, read off the store's state at that time.

`store.state_at(store, run, t)` folds the record up to t into a `store.State`; this module cuts
from it what the reasoner asks about (DESIGN "Reasoning"):

    Vehicle Scenario   V's latest vehicle.perception at or before t, with what its spawn says
                       (a default: its latest entity.state's `emergency` overrides the spawn's)
    Vehicle Action     V's latest vehicle.decision (goal, action, permitted, proceeds)
    Monitor Scenario   the facts of a monitor's latest observation of V

Every fact keeps the event that recorded it as a store.EventRef, so an explanation can cite its
evidence; the JSON of a scene or an incident writes it with `to_json()` at the edge.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from store import EventRef, State

from ..model import Decision
from ..vocabulary import IS_OF_TYPE, IS_ON_AN_EMERGENCY_CALL


@dataclass
class Scenario:
    """Facts as LE sentences (no final full stop), each with the event that recorded it."""

    facts: list[tuple[Any, EventRef]] = field(default_factory=list)

    def add(self, sentences: Any, evidence: EventRef) -> None:
        known = set(self.sentences)
        for s in sentences if isinstance(sentences, list) else []:
            text = s.strip().rstrip(".").strip() if isinstance(s, str) else s
            if text not in known:
                known.add(text)
                self.facts.append((text, evidence))

    @property
    def sentences(self) -> list:
        return [s for s, _ in self.facts]

    def without(self, sentences: frozenset[str] | set[str]) -> Scenario:
        """The scenario less these sentences (stated predictions the measurements overrule:
        Measurement.overruled); itself when there are none to leave out."""
        if not sentences or not any(s in sentences for s, _ in self.facts):
            return self
        return Scenario([(s, r) for s, r in self.facts if s not in sentences])

    @property
    def evidence(self) -> dict[str, EventRef]:
        """sentence -> event ref, for citing facts in proof trees."""
        return {s: r for s, r in self.facts if isinstance(s, str)}


def vehicle_id(src: str) -> str:
    return src.split("/", 1)[1] if "/" in src else src


def spawn_facts(vehicle: str, body: dict) -> list[str]:
    """What an entity.spawn says about the vehicle, in DESIGN's core vocabulary."""
    facts = []
    if isinstance(body.get("type"), str):
        facts.append(IS_OF_TYPE.text(vehicle, body["type"]))
    if body.get("emergency") is True:
        facts.append(IS_ON_AN_EMERGENCY_CALL.text(vehicle))
    return facts


def status_facts(vehicle: str, record: dict | None) -> list[str]:
    """What the spawn says of the vehicle, as a default the latest record before the moment
    overrides (DESIGN "Weighing": status at the act): a call stood down since the spawn
    (`emergency: false` in its latest entity.state) is no longer "on an emergency call"."""
    record = record or {}
    spawn = (record.get("spawn") or {}).get("body")
    if not isinstance(spawn, dict):
        return []
    facts = spawn_facts(vehicle, spawn)
    latest = (record.get("state") or {}).get("body")
    if isinstance(latest, dict) and latest.get("emergency") is False:
        facts = [f for f in facts if f != IS_ON_AN_EMERGENCY_CALL.text(vehicle)]
    return facts


def entity(state: State, vehicle: str) -> dict | None:
    return state.entities.get(f"vehicle/{vehicle}")


def vehicle_scenario(state: State, vehicle: str) -> Scenario:
    """Spawn facts, then the latest perception's (a fact stated by both cites the spawn)."""
    scenario = Scenario()
    record = entity(state, vehicle) or {}
    run = state.run
    if spawn := record.get("spawn"):
        scenario.add(status_facts(vehicle, record), EventRef.of(spawn, run, "entity.spawn"))
    if perception := record.get("perception"):
        scenario.add(perception["body"].get("facts"), EventRef.of(perception, run, "vehicle.perception"))
    return scenario


def has_perception(state: State, vehicle: str) -> bool:
    return bool((entity(state, vehicle) or {}).get("perception"))


def vehicle_action(state: State, vehicle: str) -> Decision | None:
    """The latest decision (goal, action, permitted, proceeds, rulebook) and the event it is."""
    decision = (entity(state, vehicle) or {}).get("decision")
    if not decision:
        return None
    body = decision["body"]
    return Decision(body.get("goal"), body.get("action"), body.get("permitted"), body.get("proceeds"),
                    body.get("rulebook"), EventRef.of(decision, state.run, "vehicle.decision"))


def observation(state: State, monitor_src: str, vehicle: str) -> dict | None:
    monitor = state.monitors.get(monitor_src)
    return None if monitor is None else monitor["observations"].get(vehicle)


def monitor_scenario(state: State, monitor_src: str, vehicle: str) -> Scenario:
    scenario = Scenario()
    if obs := observation(state, monitor_src, vehicle):
        scenario.add(obs["body"].get("facts"), EventRef.of(obs, state.run, "monitor.observation"))
    return scenario


def monitors_of(state: State, vehicle: str) -> list[str]:
    """The monitors that have observed V by the time of the state."""
    return sorted(src for src, m in state.monitors.items() if vehicle in m["observations"])
