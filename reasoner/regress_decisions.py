"""The vehicles' recorded decisions, asked again under two rulebooks.

A `vehicle.decision` records the question an automated vehicle asked before it acted ("173 can
enter the junction"), on its Vehicle Scenario: what its spawn says and its latest
`vehicle.perception` at or before the decision (DESIGN "Reasoning"). Regression asks the same
question on the same facts of the baseline's vehicle-stage rulebook and of the new one: a
decision the new rules would forbid (or allow) is a change, with the changed rules its two proofs
went through. The events are read once per run, in (t, seq, src) order, three kinds only.

The baseline's answers under the rulebooks in force are kept with the run's measurements
(reasoner/case_memo.py: sealed, under the chain and the code), each with the sha256 of the rulebook
that gave it and the decision itself with its Vehicle Scenario (the sentences and the events they
cite): a later regression takes the kept answer where it asks the same vehicle-stage rulebook, and
asks its new rulebook on the kept scenario, reading nothing of the run again (on the hour, reading
the decisions and each one's perception by its key was a quarter of a warm regression).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Iterator

from store import EventRef, Store

from .case_memo import CaseMemo, key_of
from .engine import Engine, Rulebook
from .facts import FactReader
from .le.terms import Atom
from .regress_reasons import Trees
from .scenarios import Scenario, spawn_facts, vehicle_id
from .shapes import Plan, Shaper
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


class Shapes:
    """Yes-or-no answers remembered by the shape of the question and facts (reasoner/shapes.py),
    for rulebooks whose answers keep under renaming road users (`Shaper.keeps_proofs`, checked on
    the rules): a run's decisions are a few questions asked by thousands of vehicles. And, before
    any parsing, by the very sentences: the answer depends on the rulebook and the sentences
    alone (each parsed the same way every time), and a vehicle may ask the same question on
    the same view again (town-4m: 70 of its 873 decisions), so such a repeat costs a look-up
    instead of parsing and shaping its facts. What shaping needs of a sentence (its
    parse, the places a shape renames) is kept by its text: a vehicle's sentences come back in
    each of its decisions."""

    LIMIT = 100_000

    def __init__(self) -> None:
        self._shapers: dict[str, Shaper] = {}
        self._plans: dict[str, dict[str, Plan | bool]] = {}     # rulebook -> sentence -> plan (False: unread)
        self._found: dict[tuple, bool] = {}
        self._said: dict[tuple, bool | None] = {}

    def permitted(self, engine: Engine, reader: FactReader, rb: Rulebook, decision: RecordedDecision) -> bool | None:
        """The decision's goal asked of the rulebook on its Vehicle Scenario, as `ask` answers it
        without proofs (None: the goal is no sentence of the rulebook)."""
        key = (rb.sha256, decision.goal, *(text for text, _ in decision.facts))
        try:
            return self._said[key]
        except KeyError:
            pass
        except TypeError:       # a recorded "sentence" that is no text (a list, an object): not remembered
            key = None
        found = self._asked(engine, reader, rb, decision)
        if key is not None:
            if len(self._said) >= self.LIMIT:
                self._said.clear()
            self._said[key] = found
        return found

    def _asked(self, engine: Engine, reader: FactReader, rb: Rulebook, decision: RecordedDecision) -> bool | None:
        goal = reader.atom(rb, decision.goal)
        if goal is None:
            return None
        shaper = self._shapers.get(rb.sha256)
        if shaper is None:
            shaper = self._shapers[rb.sha256] = Shaper(rb)
        shaped = self._shape(reader, shaper, rb, [decision.goal, *(text for text, _ in decision.facts)]) \
            if shaper.keeps_proofs else None
        if shaped is None:
            return engine.holds(rb, goal, reader.atoms(rb, list(decision.facts), []))
        key = (rb.sha256, *shaped)
        found = self._found.get(key)
        if found is None:
            if len(self._found) >= self.LIMIT:
                self._found.clear()
            atoms = [Atom(functor, args) for functor, args in shaped]
            found = self._found[key] = engine.holds(rb, atoms[0], atoms[1:])
        return found

    def _shape(self, reader: FactReader, shaper: Shaper, rb: Rulebook, texts: list) -> tuple | None:
        """The sentences' shape (Shaper.renamed of each one's plan; a sentence the rulebook
        cannot read is left out, as `FactReader.atoms` leaves it out), or None."""
        plans = self._plans.get(rb.sha256)
        if plans is None or len(plans) >= self.LIMIT:
            plans = self._plans[rb.sha256] = {}
        planned = []
        for text in texts:
            if type(text) is not str:
                continue                # no sentence: FactReader.atom reads none
            plan = plans.get(text)
            if plan is None:
                atom = reader.atom(rb, text)
                plan = plans[text] = False if atom is None else (shaper.plan(atom) or True)
            if plan is True:
                return None             # a sentence no shape can be made of
            if plan is not False:
                planned.append(plan)
        return shaper.renamed(planned)


def ask(engine: Engine, reader: FactReader, choice: Choice | None, decision: RecordedDecision,
        proofs: bool = False, shapes: Shapes | None = None) -> Asked:
    """The decision's goal asked of the choice's rulebook on the Vehicle Scenario (`shapes`: a
    yes or no remembered by shape)."""
    if choice is None or not isinstance(decision.goal, str):
        return Asked(None if choice is None else choice.rulebook, None)
    rb = choice.rulebook
    if not proofs and shapes is not None:
        return Asked(rb, shapes.permitted(engine, reader, rb, decision))
    goal = reader.atom(rb, decision.goal)
    if goal is None:
        return Asked(rb, None)
    facts = reader.atoms(rb, list(decision.facts), [])
    if not proofs:
        return Asked(rb, engine.holds(rb, goal, facts))
    answer = engine.ask(rb, goal, facts)
    trees = answer.proofs[:1] or ([answer.why_not] if answer.why_not else [])
    return Asked(rb, answer.holds, Trees(rb.sha256, tuple(trees)))


KEPT_CHUNK = 2_000                      # decisions per kept entry (an entry is at most 4 MB)


@dataclass(frozen=True)
class KeptDecision:
    """A decision as kept: what names and chooses it, and the baseline's answer with the rulebook
    that gave it (None: none was asked)."""

    decision: RecordedDecision          # with its Vehicle Scenario, to be asked of a new rulebook
    rulebook: str | None
    permitted: bool | None


def kept_decisions(memo: CaseMemo) -> list[KeptDecision] | None:
    """The run's kept decisions, in time order, or None (never kept, or a part of them is not)."""
    head = memo.get("decisions", key_of("decisions"), plain=True)
    if not isinstance(head, int):
        return None
    out: list[KeptDecision] = []
    for n in range(head):
        chunk = memo.get("decisions", key_of("decisions", n), plain=True)
        if chunk is None:
            return None
        out += [KeptDecision(RecordedDecision(memo.run, src, seq, t, vehicle, goal, action, permitted, proceeds,
                                              rulebook, _unkept_facts(memo.run, refs, facts)), sha, answer)
                for src, seq, t, vehicle, goal, action, permitted, proceeds, rulebook, refs, facts, sha, answer
                in chunk]
    return out


def keep_decisions(memo: CaseMemo, asked: list[tuple[RecordedDecision, Asked]]) -> None:
    """Keep the baseline's answers (written with the memo's other fresh entries, at its save)."""
    rows = [[d.src, d.seq, d.t, d.vehicle, d.goal, d.action, d.permitted, d.proceeds, d.rulebook,
             *_kept_facts(d.facts), a.rulebook.sha256 if a.rulebook is not None else None, a.permitted]
            for d, a in asked]
    chunks = [rows[i:i + KEPT_CHUNK] for i in range(0, len(rows), KEPT_CHUNK)]
    for n, chunk in enumerate(chunks):
        memo.put("decisions", key_of("decisions", n), chunk, plain=True)
    memo.put("decisions", key_of("decisions"), len(chunks), plain=True)


def _kept_facts(facts: tuple[tuple[Any, EventRef], ...]) -> tuple[list, list]:
    """A Vehicle Scenario as plain data: the events it cites, once each ([src, seq, t, kind]),
    and each sentence with the place of its event among them (a decision's facts cite two
    events, its spawn and its perception)."""
    refs: dict[EventRef, int] = {}
    for _, ref in facts:
        refs.setdefault(ref, len(refs))
    return [[r.src, r.seq, r.t, r.kind] for r in refs], [[text, refs[ref]] for text, ref in facts]


def _unkept_facts(run: str, refs: list, facts: list) -> tuple[tuple[Any, EventRef], ...]:
    """The Vehicle Scenario `_kept_facts` gave."""
    cited = [EventRef(run, src, seq, t, kind) for src, seq, t, kind in refs]
    return tuple((text, cited[n]) for text, n in facts)
