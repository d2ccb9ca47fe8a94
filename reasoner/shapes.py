"""The shape of some facts: the facts with the road users a rulebook never names renamed, so that
one answer serves every situation of that shape.

A rulebook's rules treat alike every constant they never mention: renaming such constants
consistently (one new name per old one, none shared with another constant of the facts) gives the
same answers, with the new names in them. The monitors observe thousands of vehicles in a handful
of situations, and the simulation's vehicles ask the same few questions: asked once per shape,
the rulebook is asked a few thousand times instead of a million.

Only constants in a road user's place are renamed: a slot whose type (`*a vehicle*`, `*a road
user*`, ...) is in ENTITY_SLOTS. A vehicle's id is often a number, and a number may also be a
speed or a limit ("30 has speed of 30", "the speed limit is 30"): renaming by the slot, not by the
word, keeps the speed a speed. (Renaming the words once shared one answer between vehicle 25 at
25 mph and vehicle 35 at 35 mph under a 30 mph limit.) A rule that joined a road user's place
with a number's would see the two apart after renaming; no rule of ours does, and none should.
"""
from __future__ import annotations

from typing import Any, Iterable

from .engine import Rulebook
from .facts import plain_constants, walk_atoms
from .le.templates import Slot
from .le.terms import Atom

ENTITY_SLOTS = frozenset({"vehicle", "road_user", "person", "pedestrian", "cyclist", "entity", "other_entity"})
"""Slot types (as the LE parser names them: words joined by "_") whose values are road users."""
_STAND_IN = "\x00road user {}"   # no sentence a producer writes parses to one (checked all the same)


def rule_constants(rb: Rulebook) -> set:
    """Every constant the rulebook's rules mention (a shape keeps these)."""
    out: set = set()
    for rule in rb.document.rules:
        for atom in walk_atoms([rule.head, rule.body]):
            out |= plain_constants(atom.args)
    return out


class Shaper:
    """Shapes of facts for one rulebook."""

    def __init__(self, rb: Rulebook) -> None:
        self._mentioned = rule_constants(rb)
        self._places: dict[tuple[str, int], tuple[int, ...]] = {}
        for template in rb.document.templates.values():
            slots = [p for p in template.parts if isinstance(p, Slot)]
            self._places[(template.functor, len(slots))] = tuple(
                i for i, slot in enumerate(slots) if slot.type in ENTITY_SLOTS)

    def shape(self, atoms: Iterable[Atom], first: Any = None) -> tuple[tuple[Atom, ...], dict] | None:
        """The atoms with every unmentioned constant in a road user's place renamed, in order of
        appearance (`first`, the one asked about, before any), and the renaming; None where no
        shape can be made (a value that is not a plain constant, or one equal to a stand-in)."""
        names: dict = {}
        if first is not None and self._renamable(first):
            names[first] = _STAND_IN.format(0)
        out = []
        for atom in atoms:
            places = self._places.get((atom.functor, len(atom.args)), ())
            args = list(atom.args)
            for i, arg in enumerate(args):
                kind = type(arg)
                if kind is str and arg.startswith("\x00"):
                    return None
                if kind not in (str, int, float):
                    return None
                if i in places and kind is not float and self._renamable(arg):
                    new = names.get(arg)
                    if new is None:
                        new = names[arg] = _STAND_IN.format(len(names))
                    args[i] = new
            out.append(Atom(atom.functor, tuple(args)) if places else atom)
        return tuple(out), names

    def _renamable(self, value: Any) -> bool:
        return type(value) in (str, int) and value not in self._mentioned
