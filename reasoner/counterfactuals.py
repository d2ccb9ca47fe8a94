"""What would have changed the answer: the smallest edits to a scenario's facts, and why-not.

An investigator asks two questions the verdict alone does not answer: "what would have made this
lawful?" and "what could the vehicle itself have done?". Both are searches over the recorded facts:
remove a fact, add a fact that a failed condition asked for, or replace one value (a colour, a type,
a number) by another the rules know, and ask the engine again. Sets of one change are tried first,
then pairs built on the sets that did not yet work, each new layer taking its additions from the
why-not tree of the changed scenario (so "had 173 been an ambulance" leads to "... and on an
emergency call", which the first tree never asked about). A set is kept only if no smaller kept set
is inside it, so every answer is minimal.

Each change is classified: *controlled* when it is the vehicle's own conduct (its motion, where it
stopped, whom it forced to brake), a *circumstance* otherwise (lights, signs, its type, an emergency
call, other road users). Everything stays data: facts are Atoms, questions are parsed with the
rulebook's templates, nothing recorded becomes Prolog text.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping, cast

from store import EventRef, GapsError

from .engine import Engine, Rulebook, enrich
from .facts import walk_atoms
from .le.document import parse_question
from .le.errors import LEError
from .le.terms import Atom, Cond

# The vehicle's own conduct in the core vocabulary (DESIGN "Facts are Logical English sentences")
# and the Highway Code rulebook: sentences whose subject is the vehicle and that it brings about by
# driving. Everything else (the signal, signs, its type, an emergency call, other road users, the
# speed limit) is a circumstance it found.
CONTROLLED = frozenset({
    "is_stopped", "has_crossed_the_stop_line", "is_in_the_junction", "has_stopped_at_the_stop_line",
    "has_speed_of", "would_force_to_change_speed_or_course", "would_endanger",
    "is_too_close_to_the_stop_line_to_stop_safely", "has_crossed_the_first_white_line",
    "is_stopped_in_the_box_junction", "is_turning", "is_turning_left", "is_turning_right",
    "is_taking_up_a_position_to_turn_right", "is_waiting_to_turn_right", "is_crossing_a_dual_carriageway",
    "has_room_to_clear_the_junction_safely", "crossed_the_stop_line_on_light",
    "has_stopped_before_entering_the_major_road",
})

# Slots that name a party rather than a value: their constants are never swapped for others (a
# counterfactual about "another vehicle" is no counterfactual about this one).
ENTITY_SLOTS = frozenset({"vehicle", "road_user", "person", "party", "entity", "other_vehicle"})

MAX_SIZE = 2            # changes per counterfactual: enough for "an ambulance on an emergency call"
BUDGET = 4000           # engine questions per search: a bound, not a target (a search takes ms)


@dataclass(frozen=True)
class Change:
    """One edit of the recorded facts: remove `fact`, add `fact`, or replace `fact` by `new`."""

    kind: str
    fact: Atom
    new: Atom | None = None
    controlled: bool = False


@dataclass
class Counterfactual:
    """A minimal set of changes after which the question's answer flips."""

    changes: tuple[Change, ...]

    @property
    def kind(self) -> str:
        flags = {c.controlled for c in self.changes}
        return "controlled" if flags == {True} else "circumstance" if flags == {False} else "mixed"


@dataclass
class Search:
    """The question a search flips: `goal` on `facts` with `rb`, wanted to hold (`want`) or fail."""

    engine: Engine
    rb: Rulebook
    facts: list[Atom]
    goal: Atom
    want: bool
    vehicle: Any
    fixed: frozenset = frozenset()                  # facts never changed (the potential violation)
    values: dict = field(default_factory=dict)      # slot type -> extra values (DESIGN's colours)
    exclude: dict = field(default_factory=dict)     # slot type -> values never swapped in
    max_size: int = MAX_SIZE
    budget: int = BUDGET
    asked: int = 0

    def run(self) -> list[Counterfactual]:
        if self._holds(self.facts) == self.want:
            return []
        pool = self._value_pool()
        derived = _derived_functors(self.rb)
        found: list[tuple[Change, ...]] = []
        seen: set[frozenset] = set()
        frontier: list[tuple[Change, ...]] = [()]
        for size in range(1, self.max_size + 1):
            grown: list[tuple[Change, ...]] = []
            for base in frontier:
                scenario = apply(self.facts, base)
                for change in self._candidates(scenario, base, pool, derived):
                    combo = base + (change,)
                    key = frozenset(combo)
                    if key in seen or any(set(f) <= key for f in found):
                        continue
                    seen.add(key)
                    if self.asked >= self.budget:
                        return _prefer_concrete(found)
                    if self._holds(apply(self.facts, combo)) == self.want:
                        found.append(combo)
                    elif size < self.max_size:
                        grown.append(combo)
            frontier = grown
        return _prefer_concrete(found)

    # -- the candidates of one scenario ----------------------------------------------------------
    def _candidates(self, scenario: list[Atom], base: tuple[Change, ...], pool: dict,
                    derived: set[str]) -> list[Change]:
        touched = {c.fact for c in base} | {c.new for c in base if c.new is not None}
        out: list[Change] = []
        for fact in scenario:
            if fact in self.fixed or fact in touched:
                continue
            out.append(Change("remove", fact, controlled=self._controlled(fact)))
            for i, slot_type in enumerate(_slot_types(self.rb, fact)):
                if slot_type in ENTITY_SLOTS or slot_type is None:
                    continue
                for value in _nearest_first(pool.get(slot_type, ()), fact.args[i]):
                    if value != fact.args[i] and value not in self.exclude.get(slot_type, ()):
                        new = Atom(fact.functor, fact.args[:i] + (value,) + fact.args[i + 1:])
                        if new not in scenario:
                            out.append(Change("replace", fact, new, self._controlled(fact)))
        present = set(scenario)
        kinds = {self._kind(f) for f in scenario} | {self._kind(c.fact) for c in base}
        for atom in self._asked_for(scenario, derived):
            # a second value for what already has one ("173 is of type ambulance" beside "... car")
            # is a replacement, which is tried as such
            if atom not in present and atom not in touched and self._kind(atom) not in kinds:
                out.append(Change("add", atom, controlled=self._controlled(atom)))
        return out

    def _kind(self, fact: Atom) -> tuple:
        """The functor and the parties of a fact, its values blanked."""
        return (fact.functor,) + tuple(a if t in ENTITY_SLOTS or t is None else None
                                       for t, a in zip(_slot_types(self.rb, fact), fact.args))

    def _asked_for(self, scenario: list[Atom], derived: set[str]) -> list[Atom]:
        """Ground sentences the proof or the why-not tree mentions that a scenario can state (no
        rule concludes them): the conditions whose truth would change the answer."""
        self.asked += 1
        answer = self.engine.ask(self.rb, self.goal, scenario)
        trees = answer.proofs[:1] if answer.holds else ([answer.why_not] if answer.why_not else [])
        out: list[Atom] = []
        for tree in trees:
            for data in _sentences(tree):
                atom = _ground_atom(data)
                if atom is not None and atom.functor not in derived and atom not in out \
                        and self.rb.document.template_for(atom.functor, len(atom.args)) is not None:
                    out.append(atom)
        return out

    def _controlled(self, fact: Atom) -> bool:
        return fact.functor in CONTROLLED and bool(fact.args) and fact.args[0] == self.vehicle

    def _holds(self, facts: list[Atom]) -> bool:
        self.asked += 1
        return self.engine.holds(self.rb, self.goal, facts)

    def _value_pool(self) -> dict[str, list]:
        """The values each slot type takes anywhere in the rulebook (rules and scenarios), in the
        facts, and in `values`: the alternatives a replacement may choose from."""
        pool: dict[str, list] = {}

        def note(atom: Atom) -> None:
            for slot_type, arg in zip(_slot_types(self.rb, atom), atom.args):
                if slot_type and slot_type not in ENTITY_SLOTS and isinstance(arg, (str, int, float)) \
                        and not isinstance(arg, bool) and arg not in pool.setdefault(slot_type, []):
                    pool[slot_type].append(arg)

        doc = self.rb.document
        statements = list(doc.rules) + [r for s in doc.scenarios.values() for r in s.rules]
        for rule in statements:
            for atom in walk_atoms([rule.head, rule.body]):
                note(atom)
        for atom in self.facts:
            note(atom)
        for slot_type, extra in self.values.items():
            for v in extra:
                if v not in pool.setdefault(slot_type, []):
                    pool[slot_type].append(v)
        return pool


def search(engine: Engine, rb: Rulebook, facts: Iterable[Atom], goal: Atom, want: bool, vehicle: Any, *,
           fixed: Iterable[Atom] = (), values: dict | None = None, exclude: dict | None = None,
           max_size: int = MAX_SIZE, budget: int = BUDGET) -> list[Counterfactual]:
    """The minimal change sets (smallest first) after which `goal` holds (`want`) or fails.
    `values` adds alternatives per slot type; `exclude` names values never swapped in."""
    s = Search(engine, rb, list(facts), goal, want, vehicle, frozenset(fixed), dict(values or {}),
               dict(exclude or {}), max_size, budget)
    found = s.run()
    found.sort(key=lambda cf: (len(cf.changes), {"controlled": 0, "circumstance": 1, "mixed": 2}[cf.kind]))
    return found


def apply(facts: list[Atom], changes: Iterable[Change]) -> list[Atom]:
    """The facts after the changes (order kept, additions last)."""
    out = list(facts)
    for c in changes:
        if c.kind == "add":
            out.append(c.fact)
        elif c.kind == "remove":
            out = [f for f in out if f != c.fact]
        else:
            out = [cast(Atom, c.new) if f == c.fact else f for f in out]   # a replacement has its new fact
    return out


# -- why-not ------------------------------------------------------------------------------------

class QuestionUnreadable(GapsError, ValueError):
    """A why-not question no template of the rulebook reads."""


def why_not(engine: Engine, rb: Rulebook, sentence: str, facts: list[Atom],
            evidence: Mapping[str, EventRef] | None = None) -> dict:
    """Ask one sentence ("173 can enter the junction") on the facts: whether it holds and the
    proof or the tree of failed conditions, enriched with the rulebook's words and the evidence.
    The sentence is read with the rulebook's templates into terms; it never reaches Prolog as text."""
    try:
        body = parse_question(rb.document, sentence)
    except LEError as exc:
        raise QuestionUnreadable(f"{rb.name} cannot read {sentence!r}: {exc}") from None
    if len(body) == 1 and isinstance(body[0], Cond) and body[0].atom is not None \
            and _ground_atom([body[0].atom.functor, *body[0].atom.args]) is not None:
        answer = engine.ask(rb, body[0].atom, facts)
        trees = answer.proofs[:1] if answer.holds else ([answer.why_not] if answer.why_not else [])
        return {"question": rb.render(body[0].atom), "holds": answer.holds,
                "trees": [enrich(t, rb, evidence) for t in trees]}
    result = engine.answers(rb, body, facts, explain=True)
    trees = [t for proof in result.proofs[:1] for t in proof] if result.answers else list(result.why_not or [])
    return {"question": sentence.strip().rstrip("."), "holds": bool(result.answers), "answers": result.answers,
            "trees": [enrich(t, rb, evidence) for t in trees]}


# -- helpers ------------------------------------------------------------------------------------

def _prefer_concrete(found: list[tuple[Change, ...]]) -> list[Counterfactual]:
    """Drop "remove F" when "replace F by x" (with the same other changes) also works: "had the
    light been green" says more than "had there been no red light"."""
    keys = [frozenset(f) for f in found]

    def superseded(combo: tuple[Change, ...]) -> bool:
        for c in combo:
            if c.kind != "remove":
                continue
            others = frozenset(combo) - {c}
            for k in keys:
                extra = k - others
                if others <= k and len(extra) == 1 and next(iter(extra)).kind == "replace" \
                        and next(iter(extra)).fact == c.fact:
                    return True
        return False

    return [Counterfactual(combo) for combo in found if not superseded(combo)]


def _nearest_first(values: Iterable, old: Any) -> list:
    """A number's alternatives nearest it first, so that the answer kept is the smallest edit
    ("had 28 been doing 30 mph instead of 38", not the first number a rulebook happens to use);
    other values in the rulebook's order."""
    def number(v: Any) -> bool:
        return isinstance(v, (int, float)) and not isinstance(v, bool)
    values = list(values)
    if not number(old):
        return values
    return sorted(values, key=lambda v: abs(v - old) if number(v) else float("inf"))


def _derived_functors(rb: Rulebook) -> set[str]:
    return {r.head.functor for r in rb.document.rules if r.body}


def _slot_types(rb: Rulebook, atom: Atom) -> list[str | None]:
    template = rb.document.template_for(atom.functor, len(atom.args))
    if template is None:
        return [None] * len(atom.args)
    return [s.type for s in template.slots] + [None] * (len(atom.args) - len(template.slots))


def _sentences(tree: dict) -> Iterable[list]:
    stack = [tree]
    while stack:
        node = stack.pop()
        yield node["sentence"]
        stack.extend(node.get("children", []))


def _ground_atom(data: list) -> Atom | None:
    """An Atom for a proof node's plain sentence whose arguments are all constants, else None."""
    if not data or not isinstance(data[0], str) or data[0].startswith("$"):
        return None
    args = data[1:]
    if all(isinstance(a, (str, int, float)) and not isinstance(a, bool) for a in args):
        return Atom(data[0], tuple(args))
    return None
