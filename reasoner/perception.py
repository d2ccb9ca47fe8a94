"""Perception faults: where the vehicle's scenario and the monitor's disagree, and whether it matters.

DESIGN "Reasoning": where the Vehicle Scenario and the Monitor Scenario disagree on a fact the
verdict depends on (the vehicle saw green, the monitor saw red), the finding is a perception
fault and the verdict is taken on what was observed. Decisions made here:

- The monitor is the witness for what its rulebook looks at about the vehicle: the sentences
  (functors) in the conditions of the monitor rules that name the vehicle or no road user (the
  light, stopped, crossed the stop line, speed, the speed limit, ...). For those, the Validator
  Scenario takes the monitor's facts about the vehicle in place of the vehicle's own; the monitor
  saying nothing of one (no "173 is stopped") counts, as the monitor rules read it, as its not
  being so. Everything else about the vehicle (its type, an emergency call, what it knows of a
  pedestrian's path) stays as the vehicle perceived it; what the monitor saw of another road user
  that the vehicle perceived nothing of (its type) is added.
- Open texture is witnessed by nobody at a moment: "V would force U to change speed or course",
  "V would endanger P", "V is too close to the stop line to stop safely" (vocabulary.OPEN_TEXTURE)
  are judgements, measured by the history or stated by a vehicle as its own prediction. A monitor
  rule may look at one (HC 171's "so as to ... cause the driver of another vehicle to change its
  speed or course"), but the camera's silence on it does not overrule the vehicle's prediction:
  the vehicle's stays, and what the monitor stated of it is added beside it.
- A disagreement is a fault of the verdict only if it changes it: the verdict on the vehicle's
  own facts is compared with the verdict on the corrected ones. A speed of 29 against 31 under a
  limit of 30 is a perception fault; 21 against 22 is not worth one.
"""
from __future__ import annotations

from typing import Any

from store import EventRef

from .engine import Rulebook
from .facts import walk_atoms
from .le.terms import Atom, Var
from .model import Finding
from .vocabulary import OPEN_TEXTURE, POTENTIALLY_VIOLATES

OPEN_TEXTURE_FUNCTORS = frozenset(s.functor for s in OPEN_TEXTURE)


ROAD_USER_SLOTS = frozenset({"vehicle", "road_user", "person"})   # template slot types that name a road user


def witnessed_functors(monitor_rb: Rulebook, goal: str = POTENTIALLY_VIOLATES.functor) -> set[str]:
    """The sentences about the vehicle the monitor rules look at: those in the conditions of the
    rules for `goal` (the vehicle is its first slot) and of the rules those conditions lead to (a
    rulebook may hold other rules beside them, as the paper's does), that name the vehicle or no
    road user at all ("the speed limit is N"). A condition about another road user ("the person
    is of type pedestrian") makes the monitor no witness of the vehicle's own type. Sentences a
    rule concludes are not observations, and open texture (vocabulary.OPEN_TEXTURE: "would
    force", "would endanger", "too close to stop") is no camera's observation either: both are
    left out."""
    by_head: dict[str, list] = {}
    for rule in monitor_rb.document.rules:
        by_head.setdefault(rule.head.functor, []).append(rule)
    templates = monitor_rb.document
    seen: set[tuple[str, int | None]] = {(goal, 0)}     # (functor, the vehicle's slot in it, if any)
    todo: list[tuple[str, int | None]] = [(goal, 0)]
    out = set()
    while todo:
        functor, position = todo.pop()
        for rule in by_head.get(functor, []):
            me = rule.head.args[position] if position is not None and position < len(rule.head.args) else None
            for atom in walk_atoms(rule.body):
                if not _about_the_vehicle(atom, me, templates):
                    continue
                if atom.functor in by_head:
                    key = (atom.functor, atom.args.index(me) if me is not None and me in atom.args else None)
                    if key not in seen:
                        seen.add(key)
                        todo.append(key)
                else:
                    out.add(atom.functor)
    return out - OPEN_TEXTURE_FUNCTORS


def _about_the_vehicle(atom: Atom, me: Any, document: Any) -> bool:
    """Whether a rule's condition speaks of the vehicle (the variable `me`): it names it, or it
    names no road user at all (no variable in a slot the template types as a road user)."""
    if me is not None and me in atom.args:
        return True
    template = document.template_for(atom.functor, len(atom.args))
    slots = template.slots if template is not None else []
    return not any(isinstance(arg, Var) and slot.type in ROAD_USER_SLOTS for arg, slot in zip(atom.args, slots))


def _about(atom: Atom, me: Any, others: set) -> bool:
    """Whether a fact is about this vehicle: it names it, or names no road user at all."""
    return me in atom.args or not any(arg in others for arg in atom.args if isinstance(arg, (str, int)))


def corrected(vehicle_facts: list[tuple[Atom, EventRef]], monitor_facts: list[tuple[Atom, EventRef]],
              witnessed: set[str], me: Any, others: set) -> tuple[list[tuple[Atom, EventRef]], list[dict]]:
    """The vehicle's facts with the monitor's in place of those it witnesses; and the disputes:
    per sentence kind where the two differ, what each side recorded."""
    def about(pairs) -> dict[str, list[tuple[Atom, EventRef]]]:
        """The witnessed facts about the vehicle, by functor (each list in the facts' order)."""
        found: dict[str, list[tuple[Atom, EventRef]]] = {}
        for a, ev in pairs:
            if a.functor in witnessed and _about(a, me, others):
                found.setdefault(a.functor, []).append((a, ev))
        return found

    out = [(a, ev) for a, ev in vehicle_facts if not (a.functor in witnessed and _about(a, me, others))]
    disputes = []
    by_vehicle, by_monitor = about(vehicle_facts), about(monitor_facts)
    for functor in sorted(witnessed):
        mine, seen = by_vehicle.get(functor, []), by_monitor.get(functor, [])
        if {a for a, _ in mine} != {a for a, _ in seen}:
            disputes.append({"functor": functor, "vehicle": mine, "monitor": seen})
    out += [(a, ev) for a, ev in monitor_facts if a.functor in witnessed and _about(a, me, others)]
    have = {a for a, _ in out}
    out += [(a, ev) for a, ev in monitor_facts if a.functor in OPEN_TEXTURE_FUNCTORS and me in a.args
            and a not in have]
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
