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

`Shaper.keeps_proofs` checks that for a rulebook, so that a first proof (or why-not tree) too can
be worked out once per shape: the engine's search (engine.pl) does only unification, variant and
functor tests on a value it takes from a road user's place unless a rule hands that value to a
built-in (a comparison, arithmetic, a list or an aggregate, which sort and test types: an id may
be a number, its stand-in is not) or to another kind of place; where no rule does, the search
under a consistent renaming takes the same steps in the same order, and its trees are the
renamed trees.
"""
from __future__ import annotations

from typing import Any, Iterable

from .case_memo import key_of
from .engine import Rulebook
from .facts import plain_constants, walk_atoms
from .le.builtins import BUILTIN_FUNCTORS
from .le.templates import Slot
from .le.terms import Atom, Cond, Var

Plan = tuple[str, tuple, tuple[int, ...]] | None
"""An atom's functor, arguments and the places a shape renames (Shaper.plan)."""
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
        self.identity = key_of("shaper", sorted(repr(t) for t in rb.document.templates.values()),
                               sorted(repr(c) for c in self._mentioned))
        """What the shapes made here depend on: the templates (how a sentence parses, which places
        are a road user's) and the constants the rules mention (never renamed); not the rules
        themselves, so a rulebook edited in its rules alone shapes its facts alike."""
        self._places: dict[tuple[str, int], tuple[int, ...]] = {}
        for template in rb.document.templates.values():
            slots = [p for p in template.parts if isinstance(p, Slot)]
            self._places[(template.functor, len(slots))] = tuple(
                i for i, slot in enumerate(slots) if slot.type in ENTITY_SLOTS)
        self.keeps_proofs = all(self._kept_apart(rule) for rule in rb.document.rules)
        """Whether the renamed facts' first proof and why-not tree are the facts' own with the
        names put back (module docstring): no rule puts a variable of a road user's place in
        any other place, built-in or aggregate."""

    def shape(self, atoms: Iterable[Atom], first: Any = None) -> tuple[tuple[Atom, ...], dict] | None:
        """The atoms with every unmentioned constant in a road user's place renamed, in order of
        appearance (`first`, the one asked about, before any), and the renaming; None where no
        shape can be made (a value that is not a plain constant, or one equal to a stand-in)."""
        names: dict = {}
        if first is not None and self._renamable(first):
            names[first] = _STAND_IN.format(0)
        plans = [self.plan(atom) for atom in atoms]
        shaped = self.renamed(plans, names)
        if shaped is None:
            return None
        return tuple(Atom(functor, args) for functor, args in shaped), names

    def plan(self, atom: Atom) -> Plan:
        """What shaping needs of one atom: its functor, its arguments and the places of those a
        shape renames; None where no shape can be made of it (a value that is not a plain
        constant, or one equal to a stand-in). A caller meeting the same atoms again keeps it."""
        places = self._places.get((atom.functor, len(atom.args)), ())
        renamed = []
        for i, arg in enumerate(atom.args):
            kind = type(arg)
            if kind is str and arg.startswith("\x00"):
                return None
            if kind not in (str, int, float):
                return None
            if i in places and kind is not float and self._renamable(arg):
                renamed.append(i)
        return atom.functor, atom.args, tuple(renamed)

    @staticmethod
    def renamed(plans: Iterable[Plan], names: dict | None = None) -> tuple[tuple[str, tuple], ...] | None:
        """Each planned atom as (functor, arguments) with its road users renamed, in order of
        appearance, through `names` (filled in); None where a plan is None. Plain tuples: a key
        made of them is hashed without a call per atom."""
        names = {} if names is None else names
        out = []
        for plan in plans:
            if plan is None:
                return None
            functor, args, renamed = plan
            if renamed:
                moved = list(args)
                for i in renamed:
                    new = names.get(moved[i])
                    if new is None:
                        new = names[moved[i]] = _STAND_IN.format(len(names))
                    moved[i] = new
                args = tuple(moved)
            out.append((functor, args))
        return tuple(out)

    def _renamable(self, value: Any) -> bool:
        return type(value) in (str, int) and value not in self._mentioned

    def _kept_apart(self, rule: Any) -> bool:
        """Whether the rule's variables in road users' places of its sentences appear nowhere else."""
        entity: set = set()
        other: set = set()
        self._sort_atom(rule.head, entity, other)
        for cond in rule.body:
            self._sort_cond(cond, entity, other)
        return not entity & other

    def _sort_atom(self, atom: Atom, entity: set, other: set) -> None:
        user = atom.functor not in BUILTIN_FUNCTORS and atom.functor != "is_a"
        places = self._places.get((atom.functor, len(atom.args)), ()) if user else ()
        for i, arg in enumerate(atom.args):
            if isinstance(arg, Var):
                (entity if i in places else other).add(arg.name)
            else:
                other.update(_variables(arg))

    def _sort_cond(self, cond: Any, entity: set, other: set) -> None:
        if not isinstance(cond, Cond):
            other.update(_variables(cond))
        elif cond.atom is not None:
            self._sort_atom(cond.atom, entity, other)
        elif cond.aggregate is not None:
            other.update(_variables((cond.aggregate.result, cond.aggregate.each)))
            for inner in cond.aggregate.body:
                self._sort_cond(inner, entity, other)
        else:
            blocks = (cond.negated,) if cond.negated is not None else cond.any_of or cond.forall or ()
            for block in blocks:
                for inner in block:
                    self._sort_cond(inner, entity, other)


def _variables(value: Any) -> set:
    """The names of the variables anywhere inside a term (atoms, lists, arithmetic, conditions)."""
    if isinstance(value, Var):
        return {value.name}
    if isinstance(value, (list, tuple)):
        return set().union(*map(_variables, value)) if value else set()
    if hasattr(value, "__dataclass_fields__"):
        return _variables([getattr(value, name) for name in value.__dataclass_fields__])
    return set()
