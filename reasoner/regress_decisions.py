"""The vehicles' recorded decisions, asked again under two rulebooks.

A `vehicle.decision` records the question an automated vehicle asked before it acted ("173 can
enter the junction"), on its Vehicle Scenario: what its spawn says and its latest
`vehicle.perception` at or before the decision (DESIGN "Reasoning"). Regression asks the same
question on the same facts of the baseline's vehicle-stage rulebook and of the new one: a
decision the new rules would forbid (or allow) is a change, with the changed rules its two proofs
went through. The events are read once per run, in (t, seq, src) order, three kinds only.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterator

from store import EventRef, Store

from .engine import Engine, Rulebook
from .facts import FactReader
from .regress_reasons import Trees
from .scenarios import Scenario, spawn_facts, vehicle_id
from .stages import Choice, RuleSet

KINDS = ("entity.spawn", "vehicle.perception", "vehicle.decision")


@dataclass(frozen=True)
class RecordedDecision:
    """One vehicle.decision with the Vehicle Scenario it was taken on."""

    run: str
    src: str
    seq: int
    t: int
    vehicle: str
    goal: Any
    action: Any
    permitted: Any                      # what the vehicle recorded
    proceeds: Any
    rulebook: Any                       # the sha256 it says it decided with
    facts: tuple[tuple[Any, EventRef], ...]

    @property
    def id(self) -> str:
        return f"{self.src}:{self.seq}"


@dataclass(frozen=True)
class Asked:
    """A decision's question answered by one rulebook, with the proof (or why-not) trees."""

    rulebook: Rulebook | None
    permitted: bool | None              # None: no rulebook, or the goal is no sentence of it
    proof: Trees | None = None


def recorded_decisions(store: Store, run: str) -> Iterator[RecordedDecision]:
    """Every decision of the run, in time order, with spawn facts and the latest perception."""
    spawns: dict[str, dict] = {}
    seen: dict[str, dict] = {}
    for event in store.events(run, kinds=KINDS):
        kind, src = event["kind"], event["src"]
        if kind == "entity.spawn":
            spawns[src] = event
        elif kind == "vehicle.perception":
            seen[src] = event
        else:
            yield _decision(run, event, spawns.get(src), seen.get(src))


def _decision(run: str, event: dict, spawn: dict | None, perception: dict | None) -> RecordedDecision:
    vehicle = vehicle_id(event["src"])
    scenario = Scenario()
    if spawn is not None:
        scenario.add(spawn_facts(vehicle, spawn["body"]), EventRef.of(spawn, run, "entity.spawn"))
    if perception is not None:
        scenario.add(perception["body"].get("facts"), EventRef.of(perception, run, "vehicle.perception"))
    body = event["body"]
    return RecordedDecision(run, event["src"], event["seq"], event["t"], vehicle, body.get("goal"),
                            body.get("action"), body.get("permitted"), body.get("proceeds"), body.get("rulebook"),
                            tuple(scenario.facts))


def vehicle_choice(rs: RuleSet, decision: RecordedDecision) -> Choice | None:
    """The rulebook a side asks the decision of: a given one for the vehicle stage, else the one
    the vehicle says it decided with (if the run recorded it), else the stage's choice; as the
    investigation checks a decision (findings.decision_fault)."""
    stage = rs["vehicle"]
    if stage is not None and stage.source == "given":
        return stage
    return rs.vehicle_rulebook(decision.rulebook if isinstance(decision.rulebook, str) else None)


def ask(engine: Engine, reader: FactReader, choice: Choice | None, decision: RecordedDecision,
        proofs: bool = False) -> Asked:
    """The decision's goal asked of the choice's rulebook on the Vehicle Scenario."""
    if choice is None or not isinstance(decision.goal, str):
        return Asked(None if choice is None else choice.rulebook, None)
    rb = choice.rulebook
    goal = reader.atom(rb, decision.goal)
    if goal is None:
        return Asked(rb, None)
    facts = reader.atoms(rb, list(decision.facts), [])
    if not proofs:
        return Asked(rb, engine.holds(rb, goal, facts))
    answer = engine.ask(rb, goal, facts)
    trees = answer.proofs[:1] or ([answer.why_not] if answer.why_not else [])
    return Asked(rb, answer.holds, Trees(rb.sha256, tuple(trees)))
