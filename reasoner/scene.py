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
Validator Scenario ("lawful"). The scene is a `Scene` of plain JSON data; every fact carries the event ref
{run, src, seq, t, kind} it came from (a store.EventRef, written with `to_json()` here, at the edge).

Decisions: a time before the run start is allowed and gives an empty scene with a note saying so
(the record held nothing yet); a vehicle is present from its entity.spawn (or its first event, for
a producer that sends none) until its entity.despawn, and a vehicle only monitors have recorded
(no recorder of its own) is present while a monitor has observed it within the last 10 s (the
store's OBSERVATION_WINDOW_S); asking for a vehicle that is not
present at t is an UnknownVehicle error naming the vehicles that are.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import TYPE_CHECKING, Any

from store import EventRef, GapsError, NoSuchRun, State, Store, state_at

from .history import control_at
from .model import Finding
from .history import (Scenario, entity, monitor_scenario, monitors_of, vehicle_action, vehicle_id,
                        vehicle_scenario)
from .when import format_offset, format_time

if TYPE_CHECKING:
    from .investigation import Investigation


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
    """The scene of a run at one moment; the parts are JSON data, each fact with its event ref."""

    run: str
    t: int
    t_iso: str
    run_start: int
    run_start_iso: str
    offset_ns: int
    offset: str
    events: int                       # events of the run up to t
    last: dict[str, Any] | None       # the last of them: {src, seq, t}
    note: str | None                  # before the run, after its end, nothing recorded yet
    rulebooks: list[dict[str, Any]]   # as the run.start recorded them
    started: dict[str, Any] | None    # event refs of run.start and run.end
    ended: dict[str, Any] | None
    signals: list[dict[str, Any]]
    monitors: list[dict[str, Any]]
    vehicles: list[dict[str, Any]]
    road_users: list[dict[str, Any]]

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


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
        _judge(investigation, store, run, vehicles)
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
        last=state.last,
        note=_note(state, start, t),
        rulebooks=_rulebooks(start_piece),
        started=_ref_json(start_piece, run, "run.start") if start_piece else None,
        ended=_ref_json(state.end, run, "run.end") if state.end else None,
        signals=_signals(state),
        monitors=_monitors(state),
        vehicles=[v.json for v in vehicles],
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
    """One vehicle as the scene shows it (JSON), and its Validator Scenario with the facts'
    EventRefs, which the judge reads without parsing the JSON back."""

    json: dict[str, Any]
    validator: Scenario
    monitors: list = field(default_factory=list)
    """What the monitors stated of it, each fact with its event (their Monitor Scenarios')."""
    present: frozenset[str] = frozenset()
    """The other road users present: a fact naming one of them is not about the vehicle."""


def _vehicle(state: State, vehicle: str, t: int, present: set[str] = frozenset()) -> _Shown:
    run = state.run
    record = entity(state, vehicle) or {}
    spawn, now = record.get("spawn"), record.get("state")
    vscen = vehicle_scenario(state, vehicle)
    action = vehicle_action(state, vehicle)
    mscens = [(src, monitor_scenario(state, src, vehicle)) for src in monitors_of(state, vehicle)]
    validator, judged_on = _validator_scenario(record, vscen, [s for _, s in mscens])
    collision = state.collisions.get(vehicle)
    return _Shown({
        "vehicle": vehicle,
        "src": f"vehicle/{vehicle}",
        "type": spawn["body"].get("type") if spawn else None,
        "recorded": bool(record),
        "spawn": _piece(spawn, run, "entity.spawn"),
        "state": _piece(now, run, "entity.state"),
        "control": control_at(record, t),
        "vehicle_scenario": _facts(vscen),
        "vehicle_action": action.to_json() if action else None,
        "monitor_scenarios": [{"monitor": src, "facts": _facts(s)} for src, s in mscens],
        "validator_scenario": {"facts": _facts(validator), "goal": action.goal if action else None,
                               "goal_evidence": action.evidence.to_json() if action else None,
                               "judged_on": judged_on},
        "collision": _ref_json(collision, run, "collision") if collision else None,
    }, validator, [pair for _, sc in mscens for pair in sc.facts], frozenset(present - {vehicle}))


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


def _judge(investigation: Investigation | None, store: Store, run: str, vehicles: list[_Shown]) -> None:
    """Ask the validator rulebook whether each goal holds on its Validator Scenario: "lawful"."""
    from .engine import QuestionError
    from .investigation import Investigation

    inv = investigation or Investigation(store)
    choice = inv.ruleset(run)["validator"]
    for v in vehicles:
        scenario = v.json["validator_scenario"]
        verdict: dict[str, Any] = {"lawful": None, "rulebook": choice.describe() if choice else None,
                                   "unknown_facts": [], "why": None}
        scenario.update(verdict)
        if choice is None:
            scenario["why"] = "no rulebook defines punishable and mitigated violations"
            continue
        if scenario["goal"] is None:
            scenario["why"] = "the vehicle recorded no decision: there is no goal to judge"
            continue
        rb = choice.rulebook
        goal = inv.reader.atom(rb, scenario["goal"])
        if goal is None:
            scenario["why"] = f"no template of {rb.name} fits the goal {scenario['goal']!r}"
            continue
        unknown: list[Finding] = []
        own, atoms = _validator_atoms(inv, run, rb, v, unknown)
        scenario["unknown_facts"] = [f.to_json() for f in unknown]
        try:
            scenario["lawful"] = inv.engine.holds(rb, goal, atoms)
        except QuestionError as exc:
            scenario["why"] = str(exc)
            continue
        among = "among" if scenario["lawful"] else "not among"
        scenario["why"] = f"\"{scenario['goal']}\" is {among} the lawful actions of the Validator Scenario"
        if scenario["judged_on"] == "corrected vehicle scenario":     # both views, and which decides
            try:
                scenario["lawful_on_its_own_view"] = inv.engine.holds(rb, goal, own)
            except QuestionError:
                scenario["lawful_on_its_own_view"] = None


def _validator_atoms(inv: Investigation, run: str, rb: Any, v: _Shown, unknown: list[Finding]) -> tuple[list, list]:
    """The Validator Scenario's facts as the incidents judge them (DESIGN "Reasoning"): the
    vehicle's own view with what the monitors witnessed in its place (reasoner/perception.py's
    `corrected`, as the investigation asks it), so that the scene's "lawful" is the verdict's
    ground and not the vehicle's belief (issue 39: a misread light judged lawful here and
    punishable in the incident). A vehicle with no perception is judged on its spawn and the
    monitors' facts already (_validator_scenario). Returned: the vehicle's own view's atoms, and
    those the scene is judged on."""
    from .le.sentences import constant
    from .perception import corrected, witnessed_functors

    mine = inv.reader.pairs(rb, v.validator.facts, unknown)
    monitor = inv.ruleset(run)["monitor"]
    if v.json["validator_scenario"]["judged_on"] != "vehicle scenario" or monitor is None or not v.monitors:
        return [a for a, _ in mine], [a for a, _ in mine]
    seen = inv.reader.pairs(rb, v.monitors, unknown)
    me = constant([v.json["vehicle"]])
    others = {a for atom, _ in mine + seen for a in atom.args if isinstance(a, (str, int)) and a != me
              and str(a) in v.present}
    out, disputes = corrected(mine, seen, witnessed_functors(monitor.rulebook), me, others)
    if not disputes:                # the monitors saw what the vehicle did: its own view, as shown
        return [a for a, _ in mine], [a for a, _ in out]
    v.json["validator_scenario"]["facts"] = [{"fact": rb.render(a), "evidence": ev.to_json() if ev else None}
                                             for a, ev in out]
    v.json["validator_scenario"]["judged_on"] = "corrected vehicle scenario"
    return [a for a, _ in mine], [a for a, _ in out]


# --- the rest of the scene --------------------------------------------------------------------

def _facts(scenario: Scenario) -> list[dict]:
    return [{"fact": fact, "evidence": evidence.to_json()} for fact, evidence in scenario.facts]


def _ref_json(piece: dict, run: str, kind: str) -> dict[str, Any]:
    """The event ref of a piece of folded state (which lacks the run and kind), as the scene's JSON."""
    return EventRef.of(piece, run, kind).to_json()


def _piece(piece: dict | None, run: str, kind: str) -> dict | None:
    """A folded event as its body and the ref to cite it by."""
    return None if piece is None else {**piece["body"], "evidence": _ref_json(piece, run, kind)}


def _rulebooks(start: dict | None) -> list[dict]:
    books = (start or {}).get("body", {}).get("rulebooks")
    return [b for b in books if isinstance(b, dict)] if isinstance(books, list) else []


def _signals(state: State) -> list[dict]:
    run = state.run
    return [{"junction": junction, "approach": approach, "colour": shown["colour"],
             "since": _ref_json(shown["since"], run, "signal.state"),
             "evidence": _ref_json(shown["last"], run, "signal.state")}
            for junction, approaches in sorted(state.signals.items())
            for approach, shown in sorted(approaches.items())]


def _monitors(state: State) -> list[dict]:
    """Monitors on the map and monitors that have reported, by src."""
    start = state.start
    listed = ((start or {}).get("body", {}).get("map") or {}).get("monitors") if start else None
    on_map = {f"monitor/{m['id']}": m for m in listed or [] if isinstance(m, dict) and isinstance(m.get("id"), str)}
    out = []
    for src in sorted(set(on_map) | set(state.monitors)):
        folded = state.monitors.get(src) or {"observations": {}, "potential_violations": {}}
        out.append({
            "monitor": src,
            "map": on_map.get(src),
            "observed": sorted(folded["observations"], key=_natural),
            "potential_violations": [
                {"vehicle": v, "action": pv["body"].get("action"),
                 "evidence": _ref_json(pv, state.run, "monitor.potential_violation")}
                for v, pv in sorted(folded["potential_violations"].items(), key=lambda kv: _natural(kv[0]))],
        })
    return out


def _road_users(state: State) -> list[dict]:
    """Entities present that are not vehicles (pedestrians, cyclists sent as pedestrians)."""
    run = state.run
    return [{"src": src, "type": record["spawn"]["body"].get("type") if record["spawn"] else None,
             "state": _piece(record["state"], run, "entity.state")}
            for src, record in sorted(state.entities.items())
            if src.startswith("pedestrian/") and record["despawned"] is None]


def _note(state: State, start: int, t: int) -> str | None:
    if state.events == 0:
        return f"before the run's first event ({format_time(start)}): nothing was recorded yet"
    if t < start:
        return f"before the run start ({format_time(start)})"
    if state.end is not None:
        return f"after the run ended ({format_time(state.end['t'])})"
    return None
