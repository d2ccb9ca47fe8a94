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
from itertools import chain
from collections.abc import Sequence
from typing import Any, Iterable, Iterator

from store import EventRef, Store, parse_json

from ..case_memo import CaseMemo, key_of, plain_text
from ..engine import Engine, QuestionError, Rulebook
from ..facts import FactReader
from ..le.terms import Atom
from .reasons import Trees
from ..history import Scenario, spawn_facts, vehicle_id
from ..shapes import Plan, Shaper
from ..stages import Choice, RuleSet

KINDS = ("entity.spawn", "vehicle.perception", "vehicle.decision")


@dataclass(slots=True)
class RecordedDecision:
    """One vehicle.decision with the Vehicle Scenario it was taken on. (Slotted and not frozen:
    a regression makes one per kept decision, 50,489 on the hour, and a frozen dataclass's
    __init__ costs a setattr call per field.)"""

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
    facts: Sequence[tuple[Any, EventRef]]      # a tuple, or KeptFacts (made when first read)
    id: str                             # src:seq, made once (a regression reads it thrice a decision)


@dataclass(slots=True)
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
                            tuple(scenario.facts), f"{event['src']}:{event['seq']}")


def vehicle_choice(rs: RuleSet, decision: RecordedDecision) -> Choice | None:
    """The rulebook a side asks the decision of: a given one for the vehicle stage, else the one
    the vehicle says it decided with (if the run recorded it), else the stage's choice; as the
    investigation checks a decision (findings.decision_fault)."""
    stage = rs["vehicle"]
    if stage is not None and stage.source == "given":
        return stage
    return rs.vehicle_rulebook(decision.rulebook if isinstance(decision.rulebook, str) else None)


GOALLESS, UNSHAPED = -1, -2
"""A decision's form under a rulebook, beside a shape: its goal is no sentence of the rulebook (no
answer), or no shape can be made of its sentences (asked as they are)."""
Form = tuple | int


class Shapes:
    """Yes-or-no answers remembered by the shape of the question and facts (reasoner/shapes.py),
    for rulebooks whose answers keep under renaming road users (`Shaper.keeps_proofs`, checked on
    the rules): a run's decisions are a few questions asked by thousands of vehicles. And, before
    any parsing, by the very sentences: the answer depends on the rulebook and the sentences
    alone (each parsed the same way every time), and a vehicle may ask the same question on
    the same view again (town-4m: 70 of its 873 decisions), so such a repeat costs a look-up
    instead of parsing and shaping its facts. What shaping needs of a sentence (its
    parse, the places a shape renames) is kept by its text: a vehicle's sentences come back in
    each of its decisions.

    Attached to a run's memo (`attach`), each decision's form (its shape, or GOALLESS, UNSHAPED)
    is kept in the run's sealed cache under the shaper's identity (the templates and the
    constants the rules mention, `Shaper.identity`; not the answers, not the rules): the next
    regression of the run with a rulebook shaping alike asks each distinct shape of its
    rulebook without parsing or shaping a sentence (on the hour, 50,489 decisions: 49,503
    distinct sentences parsed and shaped each call, a fifth of a warm regression)."""

    LIMIT = 100_000

    def __init__(self) -> None:
        self._shapers: dict[str, Shaper] = {}
        self._plans: dict[str, dict[str, Plan | bool]] = {}     # rulebook -> sentence -> plan (False: unread)
        self._found: dict[tuple, bool] = {}
        self._said: dict[tuple, tuple[bool | None, Form]] = {}
        self._memo: CaseMemo | None = None
        self._kept: dict[str, KeptForms | None] = {}            # shaper identity -> forms read from the memo
        self._fresh: dict[str, dict[str, Form]] = {}            # shaper identity -> decision id -> form

    def attach(self, memo: CaseMemo) -> None:
        """Read the forms the run's memo kept, and keep the new ones there (`keep`)."""
        self._memo, self._kept, self._fresh = memo, {}, {}

    def keep(self) -> bool:
        """Put the forms worked out since `attach` into the memo, with those it had kept (written
        at its save); whether there were any."""
        if self._memo is None:
            return False
        for identity, fresh in self._fresh.items():
            kept = self._kept.get(identity)
            self._memo.put("shapes", identity, KeptForms.data({**(kept.forms() if kept else {}), **fresh}),
                           plain=True)
        wrote, self._fresh = bool(self._fresh), {}
        return wrote

    def permitted(self, engine: Engine, reader: FactReader, rb: Rulebook, decision: RecordedDecision) -> bool | None:
        """The decision's goal asked of the rulebook on its Vehicle Scenario, as `ask` answers it
        without proofs (None: the goal is no sentence of the rulebook)."""
        shaper = self._shaper(rb)
        kept = self._kept_forms(shaper) if self._memo is not None and shaper.keeps_proofs else None
        form = kept.form_of(decision.id) if kept is not None else None
        if kept is not None and form is not None and form != UNSHAPED:
            return kept.permitted(engine, rb, form)
        key = (rb.sha256, decision.goal, *(text for text, _ in decision.facts))
        try:
            found, asked = self._said[key]
        except (KeyError, TypeError):   # TypeError: a recorded "sentence" that is no text: not remembered
            found, asked = self._asked(engine, reader, rb, decision)
            try:
                if len(self._said) >= self.LIMIT:
                    self._said.clear()
                self._said[key] = found, asked
            except TypeError:
                pass
        if form is None:                # an unshaped one kept is kept already
            self._record(shaper, decision, asked)
        return found

    def ask_kept(self, engine: Engine, wanted: Iterable[tuple[Rulebook, RecordedDecision]]) -> None:
        """Ask at once, one Prolog call per rulebook (Engine.holds_each), every kept shape that
        `permitted` will ask for these decisions (the decisions a regression is about to ask of
        each rulebook), so that `permitted` finds its answer (or the QuestionError it raises
        there). The answers are this object's, as `permitted`'s own are: never kept."""
        if self._memo is None:
            return
        places: dict[str, tuple[Rulebook, KeptForms | None, list[int]]] = {}
        for rb, decision in wanted:
            entry = places.get(rb.sha256)
            if entry is None:
                shaper = self._shaper(rb)
                entry = places[rb.sha256] = (rb, self._kept_forms(shaper) if shaper.keeps_proofs else None, [])
            kept = entry[1]
            if kept is not None:
                form = kept.form_of(decision.id)
                if form is not None:
                    entry[2].append(form)
        for rb, kept, forms in places.values():
            if kept is not None:
                kept.ask_all(engine, rb, forms)

    def _shaper(self, rb: Rulebook) -> Shaper:
        shaper = self._shapers.get(rb.sha256)
        if shaper is None:
            shaper = self._shapers[rb.sha256] = Shaper(rb)
        return shaper

    def _kept_forms(self, shaper: Shaper) -> KeptForms | None:
        if shaper.identity not in self._kept:
            data = self._memo.get("shapes", shaper.identity, plain=True) if self._memo is not None else None
            self._kept[shaper.identity] = KeptForms.read(data)
        return self._kept[shaper.identity]

    def _record(self, shaper: Shaper, decision: RecordedDecision, form: Form) -> None:
        if self._memo is not None and shaper.keeps_proofs:
            self._fresh.setdefault(shaper.identity, {})[decision.id] = form

    def _asked(self, engine: Engine, reader: FactReader, rb: Rulebook,
               decision: RecordedDecision) -> tuple[bool | None, Form]:
        goal = reader.atom(rb, decision.goal)
        if goal is None:
            return None, GOALLESS
        shaper = self._shaper(rb)
        shaped = self._shape(reader, shaper, rb, [decision.goal, *(text for text, _ in decision.facts)]) \
            if shaper.keeps_proofs else None
        if shaped is None:
            return engine.holds(rb, goal, reader.atoms(rb, list(decision.facts), [])), UNSHAPED
        key = (rb.sha256, *shaped)
        found = self._found.get(key)
        if found is None:
            if len(self._found) >= self.LIMIT:
                self._found.clear()
            atoms = [Atom(functor, args) for functor, args in shaped]
            found = self._found[key] = engine.holds(rb, atoms[0], atoms[1:])
        return found, shaped

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


class KeptForms:
    """The forms of a run's decisions under one shaper identity, as kept: each distinct atom of
    the shapes once, each distinct shape as the places of its atoms, each decision's form as the
    place of its shape (or GOALLESS, UNSHAPED). Each shape is asked of a rulebook once, those a
    regression needs all in one call (`ask_all`)."""

    def __init__(self, atoms: list[Atom], shapes: list[list[int]], of: dict[str, int]) -> None:
        self._atoms, self._shapes, self._of = atoms, shapes, of
        self._answers: dict[tuple[str, int], bool | QuestionError] = {}

    @staticmethod
    def data(forms: dict[str, Form]) -> dict:
        """Plain data for a decision id -> form mapping (what `read` reads back)."""
        atoms: dict[tuple, int] = {}
        shapes: dict[tuple, int] = {}
        of: dict[str, int] = {}
        for ident, form in forms.items():
            if isinstance(form, int):
                of[ident] = form
                continue
            places = tuple(atoms.setdefault(pair, len(atoms)) for pair in form)
            of[ident] = shapes.setdefault(places, len(shapes))
        return {"atoms": [[functor, list(args)] for functor, args in atoms],
                "shapes": [list(places) for places in shapes], "of": of}

    @classmethod
    def read(cls, data: Any) -> KeptForms | None:
        """The kept forms, or None (none kept, or not what `data` writes)."""
        if not isinstance(data, dict):
            return None
        try:
            atoms = [Atom(functor, tuple(args)) for functor, args in data["atoms"]]
            shapes, of = data["shapes"], data["of"]
            places, forms = list(chain.from_iterable(shapes)), list(of.values())
            # checked by type and range over whole columns (a run's tens of thousands of decisions)
            if not (set(map(type, shapes)) <= {list} and set(map(type, places)) <= {int}
                    and set(map(type, forms)) <= {int} and set(map(type, of)) <= {str}):
                return None
            if places and (min(places) < 0 or max(places) >= len(atoms)) or \
                    forms and (min(forms) < min(GOALLESS, UNSHAPED) or max(forms) >= len(shapes)):
                return None
        except (AttributeError, KeyError, TypeError, ValueError):
            return None
        return cls(atoms, shapes, of)

    def forms(self) -> dict[str, Form]:
        """Decision id -> form, as `data` was given it."""
        return {ident: n if n < 0 else tuple((self._atoms[i].functor, self._atoms[i].args) for i in self._shapes[n])
                for ident, n in self._of.items()}

    def form_of(self, ident: str) -> int | None:
        """The place of the decision's shape, GOALLESS or UNSHAPED; None: it has no kept form."""
        return self._of.get(ident)

    def permitted(self, engine: Engine, rb: Rulebook, n: int) -> bool | None:
        """The answer for a kept form (`form_of`, not UNSHAPED): each shape asked once (if
        `ask_all` did not ask it already)."""
        if n == GOALLESS:
            return None
        key = (rb.sha256, n)
        found = self._answers.get(key)
        if found is None:
            atoms = [self._atoms[i] for i in self._shapes[n]]
            found = self._answers[key] = engine.holds(rb, atoms[0], atoms[1:])
        elif type(found) is not bool:
            raise QuestionError(*found.args)    # where one by one its question raised it
        return found

    def ask_all(self, engine: Engine, rb: Rulebook, forms: Iterable[int]) -> None:
        """Ask the rulebook each of these forms' shapes not asked yet, in one call: each
        distinct atom of them sent once (Engine.holds_each), each answer what `permitted` then
        gives (a question's error kept to be raised there)."""
        todo = [n for n in dict.fromkeys(forms) if n >= 0 and (rb.sha256, n) not in self._answers]
        if not todo:
            return
        shapes = [self._shapes[n] for n in todo]
        used = sorted(set(chain.from_iterable(shapes)))
        if len(used) < len(self._atoms):     # the atoms of these shapes alone, renumbered
            place = {i: k for k, i in enumerate(used)}
            shapes = [[place[i] for i in shape] for shape in shapes]
        answers = engine.holds_each(rb, [self._atoms[i] for i in used], shapes)
        for n, answer in zip(todo, answers, strict=True):
            self._answers[rb.sha256, n] = answer


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


@dataclass(slots=True)
class KeptDecision:
    """A decision as kept: what names and chooses it, and the baseline's answer with the rulebook
    that gave it (None: none was asked)."""

    decision: RecordedDecision          # with its Vehicle Scenario, to be asked of a new rulebook
    rulebook: str | None
    permitted: bool | None


def kept_decisions(memo: CaseMemo) -> list[KeptDecision] | None:
    """The run's kept decisions, in time order, or None (never kept, or a part of them is not).
    Each one's Vehicle Scenario is kept apart from it and read when first asked for (a
    regression that finds the decision's shape kept never asks: on the hour, reading the 50,489
    scenarios was a tenth of a warm regression); its seal is checked here all the same."""
    head = memo.get("decisions", key_of("decisions"), plain=True)
    if not isinstance(head, int):
        return None
    out: list[KeptDecision] = []
    for n in range(head):
        chunk = memo.get("decisions", key_of("decisions", n), plain=True)
        facts = memo.text("decisions", key_of("decision facts", n))
        if chunk is None or facts is None:
            return None
        scenarios = _Scenarios(memo.run, facts, len(chunk))
        out += [KeptDecision(RecordedDecision(memo.run, src, seq, t, vehicle, goal, action, permitted, proceeds,
                                              rulebook, KeptFacts(scenarios, i, refs), f"{src}:{seq}"), sha, answer)
                for i, (src, seq, t, vehicle, goal, action, permitted, proceeds, rulebook, refs, sha, answer)
                in enumerate(chunk)]
    return out


def keep_decisions(memo: CaseMemo, asked: list[tuple[RecordedDecision, Asked]]) -> None:
    """Keep the baseline's answers (written with the memo's other fresh entries, at its save):
    per chunk, the decisions with the events their scenarios cite, and apart the scenarios'
    sentences."""
    rows, facts = [], []
    for d, a in asked:
        refs, sentences = _kept_facts(d.facts)
        rows.append([d.src, d.seq, d.t, d.vehicle, d.goal, d.action, d.permitted, d.proceeds, d.rulebook, refs,
                     a.rulebook.sha256 if a.rulebook is not None else None, a.permitted])
        facts.append(plain_text(sentences))
    chunks = range(0, len(rows), KEPT_CHUNK)
    for n, i in enumerate(chunks):
        memo.put("decisions", key_of("decisions", n), rows[i:i + KEPT_CHUNK], plain=True)
        if None not in facts[i:i + KEPT_CHUNK]:     # else not kept: the chunk's decisions are asked afresh
            memo.put("decisions", key_of("decision facts", n), facts[i:i + KEPT_CHUNK], plain=True)
    memo.put("decisions", key_of("decisions"), len(chunks), plain=True)


class _Scenarios:
    """One kept chunk's scenario sentences, as sealed text: a JSON array of each decision's own
    JSON text, so that the one scenario a changed decision asks is parsed alone (parsing a
    chunk's 2,000 scenarios for it was half of asking it), when first read."""

    def __init__(self, run: str, text: str, count: int) -> None:
        self.run, self._text, self._count = run, text, count
        self._rows: list | None = None

    def row(self, i: int) -> list:
        if self._rows is None:
            rows = parse_json(self._text)
            if not isinstance(rows, list) or len(rows) != self._count or not all(isinstance(r, str) for r in rows):
                raise ValueError("kept scenarios do not match their decisions")   # sealed by this code: never
            self._rows = rows
        return parse_json(self._rows[i])


class KeptFacts(Sequence):
    """A kept decision's Vehicle Scenario, the (sentence, EventRef) pairs `recorded_decisions`
    gives, made when first read: equal to (and hashed as) the tuple of them."""

    __slots__ = ("_chunk", "_i", "_refs", "_pairs")

    def __init__(self, chunk: _Scenarios, i: int, refs: list) -> None:
        self._chunk, self._i, self._refs = chunk, i, refs
        self._pairs: tuple | None = None

    def _made(self) -> tuple[tuple[Any, EventRef], ...]:
        if self._pairs is None:
            self._pairs = _unkept_facts(self._chunk.run, self._refs, self._chunk.row(self._i))
        return self._pairs

    def __getitem__(self, index: Any) -> Any:
        return self._made()[index]

    def __len__(self) -> int:
        return len(self._made())

    def __iter__(self) -> Iterator:
        return iter(self._made())

    def __eq__(self, other: object) -> bool:
        return self._made() == (other._made() if isinstance(other, KeptFacts) else other)

    def __hash__(self) -> int:
        return hash(self._made())

    def __repr__(self) -> str:
        return repr(self._made())


def _kept_facts(facts: Sequence[tuple[Any, EventRef]]) -> tuple[list, list]:
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
