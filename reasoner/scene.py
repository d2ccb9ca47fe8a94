"""The scene at a moment: everything the record says about a run at time t, with its evidence.

`gaps scene --run R --at T` answers an investigator's first question, "what was going on at
10.0 s?", from one `store.state_at` call (a snapshot and a short fold, so it stays fast on
runs of millions of events) and the reasoner's readings of that state (DESIGN "Reasoning"):

    vehicles     per vehicle present at t: spawn, latest entity.state, who was in control, and
                 the Vehicle Scenario, Vehicle Action, Monitor Scenarios and Validator Scenario
    signals      per junction and approach: the colour shown and since which event
    monitors     per monitor: its map entry and the vehicles it observed in the last 10 s
    rulebooks    the rulebooks the run recorded in its run.start

Nothing here asks Prolog unless asked to judge (`judge=True`, the default when one vehicle is
asked for): then the validator rulebook says whether the goal of the Vehicle Action holds on the
Validator Scenario ("lawful"). The scene is a `Scene` of typed parts (reasoner/scene_parts.py);
every fact carries the store.EventRef {run, src, seq, t, kind} it came from, and `to_json()`
writes the whole as JSON at the edge.

Decisions: a time before the run start is allowed and gives an empty scene with a note saying so
(the record held nothing yet); a vehicle is present from its entity.spawn (or its first event, for
a producer that sends none) until its entity.despawn, and a vehicle only monitors have recorded
(no recorder of its own) is present while a monitor has observed it within the last 10 s (the
store's OBSERVATION_WINDOW_S); asking for a vehicle that is not
present at t is an UnknownVehicle error naming the vehicles that are.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING, Any

from store import EventRef, GapsError, NoSuchRun, State, Store, state_at
from store.run_map import read_run_map

from .history import control_at
from .model import Cited, Control, Finding, RulebookChoice
from .history import (Scenario, entity, monitor_scenario, monitors_of, vehicle_action, vehicle_id,
                        vehicle_scenario)
from .scene_parts import (Lawfulness, MonitorScenarioShown, MonitorShown, PotentialViolation, Reported, RoadUserShown,
                          RunRulebook, SceneFact, SignalShown, ValidatorShown, VehicleShown)
from .when import format_offset, format_time

if TYPE_CHECKING:
    from .investigation import Investigation


# What other rooms take from here (tests/architecture/test_walls.py): the scene at a moment and the
# parts of it explain reads (explain/scene_text.py, report_data.py); `reasoner` hands out Scene too
__all__ = ["Reported", "Scene", "SceneFact", "ValidatorShown", "VehicleShown", "scene"]

MONITORS = frozenset({"monitors"})      # of the run map, the scene shows only the monitors' entries


class SceneError(GapsError, ValueError):
    """A question about a scene that names nothing in the record."""


class UnknownVehicle(SceneError):
    """A vehicle not present at the moment asked; the message names the ones that are."""


def run_start(store: Store, run: str) -> int:
    """When the run started (ns): its run.start event, else its first event (Store.run_start)."""
    start = store.run_start(run)
    if start is None:
        raise NoSuchRun(run, store.run_names())
    return start


@dataclass(frozen=True)
class Scene:
    """The scene of a run at one moment; its parts are values (scene_parts.py), each fact with its
    event ref."""

    run: str
    t: int
    t_iso: str
    run_start: int
    run_start_iso: str
    offset_ns: int
    offset: str
    events: int                       # events of the run up to t
    last: Cited | None                # the last of them
    note: str | None                  # before the run, after its end, nothing recorded yet
    rulebooks: tuple[RunRulebook, ...]  # as the run.start recorded them
    started: EventRef | None          # run.start and run.end
    ended: EventRef | None
    signals: tuple[SignalShown, ...]
    monitors: tuple[MonitorShown, ...]
    vehicles: tuple[VehicleShown, ...]
    road_users: tuple[RoadUserShown, ...]

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "t": self.t, "t_iso": self.t_iso, "run_start": self.run_start,
                "run_start_iso": self.run_start_iso, "offset_ns": self.offset_ns, "offset": self.offset,
                "events": self.events, "last": self.last.to_json() if self.last else None, "note": self.note,
                "rulebooks": [b.to_json() for b in self.rulebooks],
                "started": self.started.to_json() if self.started else None,
                "ended": self.ended.to_json() if self.ended else None,
                "signals": [s.to_json() for s in self.signals], "monitors": [m.to_json() for m in self.monitors],
                "vehicles": [v.to_json() for v in self.vehicles],
                "road_users": [u.to_json() for u in self.road_users]}


def scene(store: Store, run: str, t: int, vehicle: str | None = None, judge: bool | None = None,
          investigation: Investigation | None = None) -> Scene:
    """The scene of `run` at t (ns). `vehicle`: only that vehicle (UnknownVehicle if it is not
    present at t). `judge` (default: whether a vehicle was asked for): also ask the validator
    rulebook whether each Vehicle Action's goal is lawful, with `investigation`'s rulebooks
    (reasoner.investigation.Investigation; one is made if not given)."""
    start = run_start(store, run)
    state = state_at(store, run, t)
    present = _present(state)
    if vehicle is not None and vehicle not in present:
        raise UnknownVehicle(_not_present(state, vehicle, present, t))
    shown = [vehicle] if vehicle is not None else sorted(present, key=_natural)
    named = present | {src.split("/", 1)[1] for src in state.entities if "/" in src}
    vehicles = [_vehicle(state, v, t, named) for v in shown]
    if judge if judge is not None else vehicle is not None:
        vehicles = _judge(investigation, store, run, vehicles)
    start_piece = state.start
    return Scene(
        run=run,
        t=t,
        t_iso=format_time(t),
        run_start=start,
        run_start_iso=format_time(start),
        offset_ns=t - start,
        offset=format_offset(t - start),
        events=state.events,
        last=Cited.of(state.last),
        note=_note(state, start, t),
        rulebooks=_rulebooks(start_piece),
        started=EventRef.of(start_piece, run, "run.start") if start_piece else None,
        ended=EventRef.of(state.end, run, "run.end") if state.end else None,
        signals=_signals(state),
        monitors=_monitors(state),
        vehicles=tuple(v.part for v in vehicles),
        road_users=_road_users(state),
    )


# --- who is there -----------------------------------------------------------------------------

def _present(state: State) -> set[str]:
    """Vehicle ids present at the state's time: with an entity record not despawned, or known
    only from monitors' observations."""
    ids = {vehicle_id(src) for src, record in state.entities.items()
           if src.startswith("vehicle/") and record["despawned"] is None}
    recorded = {vehicle_id(src) for src in state.entities if src.startswith("vehicle/")}
    for monitor in state.monitors.values():
        ids.update(v for v in monitor["observations"] if v not in recorded)
    return ids


def _not_present(state: State, vehicle: str, present: set[str], t: int) -> str:
    record = entity(state, vehicle)
    names = ", ".join(sorted(present, key=_natural)[:30]) or "none"
    if record is not None and record["despawned"] is not None:
        gone = record["despawned"]
        why = f"vehicle {vehicle!r} left the run at {format_time(gone['t'])} (entity.despawn, seq {gone['seq']})"
    else:
        why = f"no vehicle {vehicle!r} in run {state.run!r} at {format_time(t)}"
    return f"{why}; vehicles present then: {names}"


def _natural(vehicle: str) -> tuple:
    """Vehicle 9 before vehicle 10."""
    return (0, int(vehicle), "") if vehicle.isdigit() else (1, 0, vehicle)


# --- one vehicle ------------------------------------------------------------------------------

@dataclass(frozen=True)
class _Shown:
    """One vehicle as the scene shows it, and its Validator Scenario with the facts' EventRefs,
    which the judge reads as the rulebook's atoms."""

    part: VehicleShown
    validator: Scenario
    monitors: list = field(default_factory=list)
    """What the monitors stated of it, each fact with its event (their Monitor Scenarios')."""
    present: frozenset[str] = frozenset()
    """The other road users present: a fact naming one of them is not about the vehicle."""


def _vehicle(state: State, vehicle: str, t: int, present: set[str] | frozenset[str] = frozenset()) -> _Shown:
    run = state.run
    record = entity(state, vehicle) or {}
    spawn, now = record.get("spawn"), record.get("state")
    vscen = vehicle_scenario(state, vehicle)
    action = vehicle_action(state, vehicle)
    mscens = [(src, monitor_scenario(state, src, vehicle)) for src in monitors_of(state, vehicle)]
    validator, judged_on = _validator_scenario(record, vscen, [s for _, s in mscens])
    collision = state.collisions.get(vehicle)
    part = VehicleShown(
        vehicle=vehicle,
        type=spawn["body"].get("type") if spawn else None,
        recorded=bool(record),
        spawn=_piece(spawn, run, "entity.spawn"),
        state=_piece(now, run, "entity.state"),
        control=Control.from_json(control_at(record, t)),
        vehicle_scenario=_facts(vscen),
        vehicle_action=action,
        monitor_scenarios=tuple(MonitorScenarioShown(src, _facts(s)) for src, s in mscens),
        validator_scenario=ValidatorShown(_facts(validator), action.goal if action else None,
                                          action.evidence if action else None, judged_on),
        collision=EventRef.of(collision, run, "collision") if collision else None)
    return _Shown(part, validator, [pair for _, sc in mscens for pair in sc.facts], frozenset(present - {vehicle}))


def _validator_scenario(record: dict, vscen: Scenario, monitors: list[Scenario]) -> tuple[Scenario, str]:
    """The facts of the Validator Scenario and what they are (DESIGN "Reasoning"): the Vehicle
    Scenario; for a vehicle that recorded no perception, what its spawn and the monitors recorded
    about it."""
    if record.get("perception"):
        return vscen, "vehicle scenario"
    merged = Scenario(list(vscen.facts))
    for scenario in monitors:
        for fact, evidence in scenario.facts:
            merged.add([fact], evidence)
    return merged, "monitor scenario" if monitors else "spawn only"


def _judge(investigation: Investigation | None, store: Store, run: str, vehicles: list[_Shown]) -> list[_Shown]:
    """Ask the validator rulebook whether each goal holds on its Validator Scenario: "lawful"."""
    from .investigation import Investigation

    inv = investigation or Investigation(store)
    choice = inv.ruleset(run)["validator"]
    book = RulebookChoice(**choice.describe()) if choice else None
    out = []
    for v in vehicles:
        scenario = _judged(inv, run, choice, book, v)
        out.append(replace(v, part=replace(v.part, validator_scenario=scenario)))
    return out


def _judged(inv: Investigation, run: str, choice: Any, book: RulebookChoice | None, v: _Shown) -> ValidatorShown:
    """One vehicle's Validator Scenario with the validator's answer (and its facts as corrected by
    the monitors, where they were)."""
    from .engine import QuestionError

    scenario = v.part.validator_scenario
    if choice is None:
        return replace(scenario, judged=Lawfulness(None, book, (), "no rulebook defines punishable and mitigated violations"))
    if scenario.goal is None:
        return replace(scenario, judged=Lawfulness(None, book, (), "the vehicle recorded no decision: there is no goal to judge"))
    rb = choice.rulebook
    goal = inv.reader.atom(rb, scenario.goal)
    if goal is None:
        return replace(scenario, judged=Lawfulness(None, book, (), f"no template of {rb.name} fits the goal {scenario.goal!r}"))
    unknown: list[Finding] = []
    own, atoms, scenario = _validator_atoms(inv, run, rb, v, unknown)
    try:
        lawful = inv.engine.holds(rb, goal, atoms)
    except QuestionError as exc:
        return replace(scenario, judged=Lawfulness(None, book, tuple(unknown), str(exc)))
    among = "among" if lawful else "not among"
    why = f"\"{scenario.goal}\" is {among} the lawful actions of the Validator Scenario"
    if scenario.judged_on != "corrected vehicle scenario":
        return replace(scenario, judged=Lawfulness(lawful, book, tuple(unknown), why))
    try:                                                        # both views, and which decides
        own_view: bool | None = inv.engine.holds(rb, goal, own)
    except QuestionError:
        own_view = None
    return replace(scenario, judged=Lawfulness(lawful, book, tuple(unknown), why, True, own_view))


def _validator_atoms(inv: Investigation, run: str, rb: Any, v: _Shown, unknown: list[Finding]
                     ) -> tuple[list, list, ValidatorShown]:
    """The Validator Scenario's facts as the incidents judge them (DESIGN "Reasoning"): the
    vehicle's own view with what the monitors witnessed in its place (reasoner/perception.py's
    `corrected`, as the investigation asks it), so that the scene's "lawful" is the verdict's
    ground and not the vehicle's belief (issue 39: a misread light judged lawful here and
    punishable in the incident). A vehicle with no perception is judged on its spawn and the
    monitors' facts already (_validator_scenario). Returned: the vehicle's own view's atoms,
    those the scene is judged on, and the Validator Scenario as shown (corrected, where it was)."""
    from .le.sentences import constant
    from .perception import corrected, witnessed_functors

    shown = v.part.validator_scenario
    mine = inv.reader.pairs(rb, v.validator.facts, unknown)
    monitor = inv.ruleset(run)["monitor"]
    if shown.judged_on != "vehicle scenario" or monitor is None or not v.monitors:
        return [a for a, _ in mine], [a for a, _ in mine], shown
    seen = inv.reader.pairs(rb, v.monitors, unknown)
    me = constant([v.part.vehicle])
    others = {a for atom, _ in mine + seen for a in atom.args if isinstance(a, (str, int)) and a != me
              and str(a) in v.present}
    out, disputes = corrected(mine, seen, witnessed_functors(monitor.rulebook), me, others)
    if not disputes:                # the monitors saw what the vehicle did: its own view, as shown
        return [a for a, _ in mine], [a for a, _ in out], shown
    facts = tuple(SceneFact(rb.render(a), ev if ev else None) for a, ev in out)
    return [a for a, _ in mine], [a for a, _ in out], replace(shown, facts=facts, judged_on="corrected vehicle scenario")


# --- the rest of the scene --------------------------------------------------------------------

def _facts(scenario: Scenario) -> tuple[SceneFact, ...]:
    return tuple(SceneFact(fact, evidence) for fact, evidence in scenario.facts)


def _ref(piece: dict, run: str, kind: str) -> EventRef:
    """The event ref of a piece of folded state (which lacks the run and kind)."""
    return EventRef.of(piece, run, kind)


def _piece(piece: dict | None, run: str, kind: str) -> Reported | None:
    """A folded event as its body and the ref to cite it by."""
    return None if piece is None else Reported(piece["body"], _ref(piece, run, kind))


def _rulebooks(start: dict | None) -> tuple[RunRulebook, ...]:
    books = (start or {}).get("body", {}).get("rulebooks")
    return tuple(RunRulebook.of(b) for b in books if isinstance(b, dict)) if isinstance(books, list) else ()


def _signals(state: State) -> tuple[SignalShown, ...]:
    run = state.run
    return tuple(SignalShown(junction, approach, shown["colour"], _ref(shown["since"], run, "signal.state"),
                             _ref(shown["last"], run, "signal.state"))
                 for junction, approaches in sorted(state.signals.items())
                 for approach, shown in sorted(approaches.items()))


def _monitors(state: State) -> tuple[MonitorShown, ...]:
    """Monitors on the map and monitors that have reported, by src."""
    on_map = {f"monitor/{m.ident}": m for m in read_run_map(state.start, MONITORS).monitors if m.ident is not None}
    out = []
    for src in sorted(set(on_map) | set(state.monitors)):
        folded = state.monitors.get(src) or {"observations": {}, "potential_violations": {}}
        out.append(MonitorShown(
            src, on_map.get(src), tuple(sorted(folded["observations"], key=_natural)),
            tuple(PotentialViolation(v, pv["body"].get("action"), _ref(pv, state.run, "monitor.potential_violation"))
                  for v, pv in sorted(folded["potential_violations"].items(), key=lambda kv: _natural(kv[0])))))
    return tuple(out)


def _road_users(state: State) -> tuple[RoadUserShown, ...]:
    """Entities present that are not vehicles (pedestrians, cyclists sent as pedestrians)."""
    run = state.run
    return tuple(RoadUserShown(src, record["spawn"]["body"].get("type") if record["spawn"] else None,
                               _piece(record["state"], run, "entity.state"))
                 for src, record in sorted(state.entities.items())
                 if src.startswith("pedestrian/") and record["despawned"] is None)


def _note(state: State, start: int, t: int) -> str | None:
    if state.events == 0:
        return f"before the run's first event ({format_time(start)}): nothing was recorded yet"
    if t < start:
        return f"before the run start ({format_time(start)})"
    if state.end is not None:
        return f"after the run ended ({format_time(state.end['t'])})"
    return None
