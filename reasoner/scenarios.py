"""Reconstructing the paper's scenarios at a moment from the recorded events alone.

Vehicle Scenario: the vehicle's latest perception at or before t plus what its spawn says it
is.  Monitor Scenario: the monitor's latest observation of that vehicle.  Vehicle Action: its
latest decision.  Every fact keeps the event it came from, so explanations can cite evidence.
"""
from __future__ import annotations

from dataclasses import dataclass, field

from store import Store


def ref(event: dict) -> dict:
    """How an explanation points at an event: run, source, sequence number and time."""
    return {"run": event["run"], "src": event["src"], "seq": event["seq"], "t": event["t"],
            "kind": event["kind"]}


@dataclass
class Scenario:
    """Facts as LE sentences, each with the event that recorded it."""

    facts: list[tuple[str, dict]] = field(default_factory=list)

    def add(self, sentences: list[str], event: dict) -> None:
        for s in sentences:
            self.facts.append((s.strip().rstrip("."), ref(event)))

    @property
    def sentences(self) -> list[str]:
        return [s for s, _ in self.facts]


def latest(store: Store, run: str, kind: str, src: str, t: int, where=None) -> dict | None:
    """The last event of a kind from a source at or before t (optionally matching `where`)."""
    found = None
    for ev in store.events(run, kinds=[kind], srcs=[src], t_to=t):
        if where is None or where(ev):
            found = ev
    return found


def spawn_facts(spawn: dict) -> list[str]:
    """What an entity.spawn says about the vehicle, in the core vocabulary of DESIGN."""
    vid = spawn["src"].split("/", 1)[1]
    facts = [f"{vid} is of type {spawn['body']['type']}"]
    if spawn["body"].get("emergency"):
        facts.append(f"{vid} is on an emergency call")
    return facts


def vehicle_scenario(store: Store, run: str, vehicle: str, t: int) -> Scenario:
    src = f"vehicle/{vehicle}"
    scenario = Scenario()
    if spawn := latest(store, run, "entity.spawn", src, t):
        scenario.add(spawn_facts(spawn), spawn)
    if perception := latest(store, run, "vehicle.perception", src, t):
        known = set(scenario.sentences)
        scenario.add([f for f in perception["body"]["facts"] if f.strip().rstrip(".") not in known],
                     perception)
    return scenario


def monitor_scenario(store: Store, run: str, monitor_src: str, vehicle: str, t: int) -> Scenario:
    scenario = Scenario()
    obs = latest(store, run, "monitor.observation", monitor_src, t,
                 where=lambda ev: str(ev["body"]["vehicle"]) == vehicle)
    if obs:
        scenario.add(obs["body"]["facts"], obs)
    return scenario


def vehicle_action(store: Store, run: str, vehicle: str, t: int) -> dict | None:
    return latest(store, run, "vehicle.decision", f"vehicle/{vehicle}", t)
