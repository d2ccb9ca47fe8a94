"""Perception faults: where the vehicle's scenario and the monitor's disagree, and whether it matters.

DESIGN "Reasoning": where the Vehicle Scenario and the Monitor Scenario disagree on a fact the
verdict depends on (the vehicle saw green, the monitor saw red), the finding is a perception
fault and the verdict is taken on what was observed. Decisions made here:

- The monitor is the witness for what its rulebook looks at: the sentences (functors) in the
  conditions of the monitor rules (the light, stopped, crossed the stop line, speed, the speed
  limit, ...). For those, the Validator Scenario takes the monitor's facts about the vehicle in
  place of the vehicle's own; the monitor saying nothing of one (no "173 is stopped") counts, as
  the monitor rules read it, as its not being so. Everything else about the vehicle (its type, an
  emergency call, what it knows of a pedestrian's path) stays as the vehicle perceived it; what
  the monitor saw of another road user that the vehicle perceived nothing of (its type) is added.
- A disagreement is a fault of the verdict only if it changes it: the verdict on the vehicle's
  own facts is compared with the verdict on the corrected ones. A speed of 29 against 31 under a
  limit of 30 is a perception fault; 21 against 22 is not worth one.
"""
from __future__ import annotations

from typing import Any

from store import EventRef

from .engine import Rulebook
from .facts import walk_atoms
from .le.terms import Atom
from .model import Finding
from .vocabulary import POTENTIALLY_VIOLATES


def witnessed_functors(monitor_rb: Rulebook, goal: str = POTENTIALLY_VIOLATES.functor) -> set[str]:
    """The sentences the monitor rules look at: those in the conditions of the rules for `goal`
    and of the rules those conditions lead to (a rulebook may hold other rules beside them, as
    the paper's does). Sentences a rule concludes are not observations, so they are left out."""
    by_head: dict[str, list] = {}
    for rule in monitor_rb.document.rules:
        by_head.setdefault(rule.head.functor, []).append(rule)
    seen, todo, out = {goal}, [goal], set()
    while todo:
        for rule in by_head.get(todo.pop(), []):
            for atom in walk_atoms(rule.body):
                if atom.functor in by_head:
                    if atom.functor not in seen:
                        seen.add(atom.functor)
                        todo.append(atom.functor)
                else:
                    out.add(atom.functor)
    return out


def _about(atom: Atom, me: Any, others: set) -> bool:
    """Whether a fact is about this vehicle: it names it, or names no road user at all."""
    return me in atom.args or not any(arg in others for arg in atom.args if isinstance(arg, (str, int)))


def corrected(vehicle_facts: list[tuple[Atom, EventRef]], monitor_facts: list[tuple[Atom, EventRef]],
              witnessed: set[str], me: Any, others: set) -> tuple[list[tuple[Atom, EventRef]], list[dict]]:
    """The vehicle's facts with the monitor's in place of those it witnesses; and the disputes:
    per sentence kind where the two differ, what each side recorded."""
    def about(pairs, functor):
        return [(a, ev) for a, ev in pairs if a.functor == functor and _about(a, me, others)]

    out = [(a, ev) for a, ev in vehicle_facts if not (a.functor in witnessed and _about(a, me, others))]
    disputes = []
    for functor in sorted(witnessed):
        mine, seen = about(vehicle_facts, functor), about(monitor_facts, functor)
        if {a for a, _ in mine} != {a for a, _ in seen}:
            disputes.append({"functor": functor, "vehicle": mine, "monitor": seen})
    out += [(a, ev) for a, ev in monitor_facts if a.functor in witnessed and _about(a, me, others)]
    out += _unperceived(vehicle_facts, monitor_facts, witnessed, me, others)
    return out, disputes


def _unperceived(vehicle_facts: list[tuple[Atom, EventRef]], monitor_facts: list[tuple[Atom, EventRef]],
                 witnessed: set[str], me: Any, others: set) -> list[tuple[Atom, EventRef]]:
    """What the monitor saw of other road users that the vehicle perceived nothing of ("p1 is of
    type pedestrian" beside the witnessed "p1 is approaching 253", or "107 is on the main road"
    for a car the vehicle never saw): the monitor witnessed it, the vehicle holds no view of it to
    keep, and the rules may need it (para 5(5) asks who approaches; HC 172 whether they are on the
    main road). Facts naming the vehicle are corrected above, not here."""
    known = {(a.functor, a.args[:1]) for a, _ in vehicle_facts}
    return [(a, ev) for a, ev in monitor_facts if me not in a.args and a.args
            and not (a.functor in witnessed and _about(a, me, others))
            and (a.functor, a.args[:1]) not in known]


def dispute_finding(disputes: list[dict], rb: Rulebook, on_vehicle: str, on_monitor: str) -> Finding:
    """The perception fault finding: what each side said, and what the verdict would have been."""
    said_vehicle = [rb.render(a) for d in disputes for a, _ in d["vehicle"]]
    said_monitor = [rb.render(a) for d in disputes for a, _ in d["monitor"]]
    evidence = [ev for d in disputes for _, ev in (*d["vehicle"], *d["monitor"])]
    unique = tuple({e.key: e for e in evidence}.values())
    return Finding("perception fault",
                   (f"the vehicle perceived {_list(said_vehicle)} where the monitor observed "
                    f"{_list(said_monitor)}; on its own perception the verdict would be {on_vehicle}, "
                    f"on what the monitor observed it is {on_monitor}, and that is the verdict"),
                   unique, vehicle_said=tuple(said_vehicle), monitor_observed=tuple(said_monitor))


def _list(items: list[str]) -> str:
    return "; ".join(f'"{s}"' for s in items) if items else "nothing of this"
