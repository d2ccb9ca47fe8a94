"""The parts of a scene (reasoner/scene.py) as values: what explain/ reads by attribute and
`gaps scene --json` prints through `to_json()`.

Each part cites its event as a store.EventRef. What a producer recorded in a body (an
entity.state's position, a spawn's type) stays as it was sent, in `body`, and a monitor's map entry
is the store's reading of it (store.read_run_map), which keeps the entry as sent for the JSON: the scene shows the record, it does not clean it. The JSON of every part keeps the
keys and their order that the scene printed when its parts were dicts, so that `gaps scene
--json` and the reports built on it stay the same to the byte.
"""
from __future__ import annotations

import copy
from dataclasses import dataclass
from typing import Any, Mapping

from store import EventRef
from store.run_map import MapMonitor

from .model import Control, Decision, Finding, RulebookChoice


def _ref(ref: EventRef | None) -> dict[str, Any] | None:
    return None if ref is None else ref.to_json()


@dataclass(frozen=True)
class RunRulebook:
    """A rulebook the run.start recorded, as it was recorded: its name and sha256 as sent (a
    producer may send anything), and the whole entry for the JSON (the scene shows the record)."""

    name: Any
    sha256: Any
    entry: Mapping[str, Any]

    @classmethod
    def of(cls, entry: Mapping[str, Any]) -> RunRulebook:
        return cls(entry.get("name"), entry.get("sha256"), entry)

    def to_json(self) -> dict[str, Any]:
        return copy.deepcopy(dict(self.entry))


@dataclass(frozen=True)
class Reported:
    """A folded event as the scene shows it: its body as recorded, and the event to cite."""

    body: Mapping[str, Any]
    evidence: EventRef

    def field(self, name: str) -> Any:
        """A field of the body as recorded (anything a producer sent, or None)."""
        return self.body.get(name)

    def to_json(self) -> dict[str, Any]:
        return {**self.body, "evidence": self.evidence.to_json()}


@dataclass(frozen=True)
class SceneFact:
    """A fact of a scenario (an LE sentence as recorded) and the event it came from."""

    fact: Any
    evidence: EventRef | None

    def to_json(self) -> dict[str, Any]:
        return {"fact": self.fact, "evidence": _ref(self.evidence)}


@dataclass(frozen=True)
class SignalShown:
    """The colour one approach of a junction showed, since which report, and its latest report."""

    junction: str
    approach: str
    colour: str
    since: EventRef
    evidence: EventRef

    def to_json(self) -> dict[str, Any]:
        return {"junction": self.junction, "approach": self.approach, "colour": self.colour,
                "since": self.since.to_json(), "evidence": self.evidence.to_json()}


@dataclass(frozen=True)
class PotentialViolation:
    """A monitor's monitor.potential_violation about one vehicle (its latest)."""

    vehicle: str
    action: Any
    evidence: EventRef

    def to_json(self) -> dict[str, Any]:
        return {"vehicle": self.vehicle, "action": self.action, "evidence": self.evidence.to_json()}


@dataclass(frozen=True)
class MonitorShown:
    """A monitor: its entry in the run's map (store.read_run_map; None: not on the map), the
    vehicles it observed in the last 10 s and its potential violations."""

    monitor: str
    entry: MapMonitor | None
    observed: tuple[str, ...]
    potential_violations: tuple[PotentialViolation, ...]

    def placed(self, name: str) -> Any:
        """A field of its map entry as recorded (None off the map or where the entry has none)."""
        return None if self.entry is None else self.entry.raw.get(name)

    def to_json(self) -> dict[str, Any]:
        return {"monitor": self.monitor, "map": self.entry.raw if self.entry else None, "observed": list(self.observed),
                "potential_violations": [pv.to_json() for pv in self.potential_violations]}


@dataclass(frozen=True)
class MonitorScenarioShown:
    """What one monitor stated of a vehicle."""

    monitor: str
    facts: tuple[SceneFact, ...]

    def to_json(self) -> dict[str, Any]:
        return {"monitor": self.monitor, "facts": [f.to_json() for f in self.facts]}


@dataclass(frozen=True)
class Lawfulness:
    """The validator rulebook's answer on a Validator Scenario: `lawful` None where it was not
    decided, and `why`. `own_view_asked`: the scenario was corrected by the monitors, so the
    vehicle's own view was judged too (`lawful_on_its_own_view`)."""

    lawful: bool | None
    rulebook: RulebookChoice | None
    unknown_facts: tuple[Finding, ...]
    why: str | None
    own_view_asked: bool = False
    lawful_on_its_own_view: bool | None = None

    def to_json(self) -> dict[str, Any]:
        out = {"lawful": self.lawful, "rulebook": self.rulebook.to_json() if self.rulebook else None,
               "unknown_facts": [f.to_json() for f in self.unknown_facts], "why": self.why}
        if self.own_view_asked:
            out["lawful_on_its_own_view"] = self.lawful_on_its_own_view
        return out


@dataclass(frozen=True)
class ValidatorShown:
    """The Validator Scenario: its facts, the goal of the Vehicle Action, what the facts are
    (`judged_on`), and the validator's answer when it was asked (`judged`)."""

    facts: tuple[SceneFact, ...]
    goal: Any
    goal_evidence: EventRef | None
    judged_on: str
    judged: Lawfulness | None = None

    def to_json(self) -> dict[str, Any]:
        out = {"facts": [f.to_json() for f in self.facts], "goal": self.goal,
               "goal_evidence": _ref(self.goal_evidence), "judged_on": self.judged_on}
        return out if self.judged is None else {**out, **self.judged.to_json()}


@dataclass(frozen=True)
class VehicleShown:
    """One vehicle present: its spawn and latest state as recorded, who was in control, its
    scenarios and Vehicle Action, and a collision it was in."""

    vehicle: str
    type: Any
    recorded: bool
    spawn: Reported | None
    state: Reported | None
    control: Control
    vehicle_scenario: tuple[SceneFact, ...]
    vehicle_action: Decision | None
    monitor_scenarios: tuple[MonitorScenarioShown, ...]
    validator_scenario: ValidatorShown
    collision: EventRef | None

    @property
    def src(self) -> str:
        return f"vehicle/{self.vehicle}"

    def to_json(self) -> dict[str, Any]:
        return {"vehicle": self.vehicle, "src": self.src, "type": self.type, "recorded": self.recorded,
                "spawn": self.spawn.to_json() if self.spawn else None,
                "state": self.state.to_json() if self.state else None,
                "control": self.control.to_json(),
                "vehicle_scenario": [f.to_json() for f in self.vehicle_scenario],
                "vehicle_action": self.vehicle_action.to_json() if self.vehicle_action else None,
                "monitor_scenarios": [m.to_json() for m in self.monitor_scenarios],
                "validator_scenario": self.validator_scenario.to_json(),
                "collision": _ref(self.collision)}


@dataclass(frozen=True)
class RoadUserShown:
    """A road user present that is not a vehicle (a pedestrian, a cyclist sent as one)."""

    src: str
    type: Any
    state: Reported | None

    def to_json(self) -> dict[str, Any]:
        return {"src": self.src, "type": self.type, "state": self.state.to_json() if self.state else None}
