"""What an explanation asks the rules beyond the incident: lawful actions, why-not, counterfactuals.

An incident carries its verdict's proofs; a reader of it also asks which actions were lawful there
(the paper's Lawful Actions), why a sentence did or did not hold, and what would have changed the
verdict. These are questions to the same rulebooks, so the investigation that judged the incident
answers them with its own engine and the facts it already read (Investigation.explanation);
explain/ only renders the answers.

    inv = Investigation(store)
    incident = inv.incidents("demo-001")[0]
    why = inv.explanation(incident, why_not=["173 can enter the junction"])
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping, Protocol

from .chain_status import ChainStatus
from .counterfactuals import Counterfactual as Found
from .counterfactuals import QuestionUnreadable, search, why_not
from .engine import Engine, Rulebook
from .facts import FactReader
from .le.render import sentence_text
from .le.sentences import constant
from .le.terms import Atom
from .model import Incident, Tree
from .verdicts import Verdict
from .vocabulary import CAN, MUST_NOT, POTENTIALLY_VIOLATES


class Asked(Protocol):
    """What answers an explanation's questions: the engine and fact reader that judged the
    incident, its rulebooks by sha256 and its run's chain (an Investigation is one)."""

    engine: Engine
    reader: FactReader

    def rulebook(self, sha256: str) -> Rulebook | None: ...

    def chain(self, run: str) -> ChainStatus: ...

# DESIGN's core vocabulary: the colours a signal shows (a counterfactual may swap one for another)
COLOURS = ["red", "amber", "green"]
# a vehicle is never imagined a pedestrian
NOT_SWAPPED_IN = {"type": {"pedestrian"}}


@dataclass(frozen=True)
class Change:
    """One edit of the recorded facts, in the rulebook's words: add `fact`, remove it, or put
    `new` in its place; `data`/`new_data` are the sentences as [functor, *args] for phrasing."""

    kind: str
    fact: str
    new: str | None
    controlled: bool                   # within the vehicle's own control
    data: tuple[Any, ...]
    new_data: tuple[Any, ...] | None

    def to_json(self) -> dict[str, Any]:
        return {"kind": self.kind, "fact": self.fact, "new": self.new, "controlled": self.controlled}


@dataclass(frozen=True)
class Counterfactual:
    """A minimal set of changes after which the question's answer flips; kind: controlled,
    circumstance or mixed."""

    kind: str
    changes: tuple[Change, ...]

    def to_json(self) -> dict[str, Any]:
        return {"kind": self.kind, "changes": [c.to_json() for c in self.changes]}


@dataclass(frozen=True)
class WhyNot:
    """One why-not question and its answer: whether it holds, and the proof or the failed
    conditions. `on` is the scenario asked ("validator scenario", "monitor scenario"); `error`
    says why a question could not be read (then nothing else is set)."""

    question: str
    holds: bool | None = None
    trees: tuple[Tree, ...] = ()
    rulebook: str | None = None        # its name
    on: str | None = None
    answers: Any = None                # the bindings of a question with variables
    error: str | None = None

    def to_json(self) -> dict[str, Any]:
        if self.error is not None:
            return {"question": self.question, "error": self.error}
        out: dict[str, Any] = {"question": self.question, "holds": self.holds}
        if self.answers is not None:
            out["answers"] = self.answers
        out.update({"trees": list(self.trees), "rulebook": self.rulebook, "on": self.on})
        return out


@dataclass(frozen=True)
class Explanation:
    """What the rules answer about an incident beyond its verdict (see the module's docstring).

    lawful / not_lawful: the actions the validator rulebook names, split by whether "V can A"
    holds on the Validator Scenario (empty without a validator). counterfactuals: by question
    ("lawful", "no_potential_violation" for a punishable verdict, "punishable" for a mitigated
    one); None for a dismissal, without a validator, or when not asked for."""

    incident: str                                   # the incident's id
    monitor_rulebook: str | None                    # names of the rulebooks that judged it
    validator_rulebook: str | None
    potential_violation: str                        # "173 potentially violates enter the junction"
    lawful: tuple[str, ...]
    not_lawful: tuple[str, ...]
    why_not: tuple[WhyNot, ...]
    counterfactuals: Mapping[str, tuple[Counterfactual, ...]] | None
    chain: ChainStatus

    def to_json(self) -> dict[str, Any]:
        return {"incident": self.incident, "monitor_rulebook": self.monitor_rulebook,
                "validator_rulebook": self.validator_rulebook, "potential_violation": self.potential_violation,
                "lawful": list(self.lawful), "not_lawful": list(self.not_lawful),
                "why_not": [w.to_json() for w in self.why_not],
                "counterfactuals": None if self.counterfactuals is None else
                {q: [cf.to_json() for cf in found] for q, found in self.counterfactuals.items()},
                "chain": self.chain.to_json()}


def explain(inv: Asked, incident: Incident, questions: list[str], counterfactuals: bool) -> Explanation:
    """Investigation.explanation's work (see there)."""
    return _Asker(inv, incident).explanation(questions, counterfactuals)


class _Asker:
    """The questions about one incident, on the facts of its scenarios, with the investigation's
    engine and fact reader."""

    def __init__(self, inv: Asked, incident: Incident) -> None:
        self.inv, self.inc = inv, incident
        self.me = constant([incident.vehicle])
        self.act = constant(str(incident.action).split())
        self.pv = POTENTIALLY_VIOLATES.atom(self.me, self.act)
        proofs = incident.proofs
        self.monitor = self._book(proofs.potential_violation.rulebook)
        self.validator = self._book(proofs.verdict.rulebook if proofs.verdict else None)

    def explanation(self, questions: list[str], counterfactuals: bool) -> Explanation:
        lawful, unlawful = self._lawful_actions() if self.inc.proofs.verdict is not None else ((), ())
        rb = self.validator or self.monitor
        return Explanation(
            incident=self.inc.id, monitor_rulebook=self.monitor.name if self.monitor else None,
            validator_rulebook=self.validator.name if self.validator else None,
            potential_violation=rb.render(self.pv) if rb else sentence_text(self.pv),
            lawful=lawful, not_lawful=unlawful, why_not=self._why_not(questions),
            counterfactuals=self._counterfactuals() if counterfactuals else None,
            chain=self.inv.chain(self.inc.run))

    # -- why not ----------------------------------------------------------------------------------
    def _why_not(self, questions: list[str]) -> tuple[WhyNot, ...]:
        """The questions asked; without any, the one a reader of the verdict asks: for a mitigated
        violation why the prohibition did not apply, for a dismissal why the monitor rules did not
        derive it (the potential violation's own tree)."""
        out = []
        verdict = self.inc.verdict
        if not questions and verdict == Verdict.MITIGATED and self.validator is not None \
                and MUST_NOT.functor in self.validator.document.templates:
            questions = [self.validator.render(MUST_NOT.atom(self.me, self.act))]
        pv_trees = self.inc.proofs.potential_violation.trees
        if not questions and verdict == Verdict.DISMISSED and pv_trees:
            tree = pv_trees[0]
            out.append(WhyNot(tree["text"], tree["status"] != "failed", (tree,),
                              self.monitor.name if self.monitor else None, "monitor scenario"))
        return tuple(out) + tuple(self._ask(q) for q in questions)

    def _ask(self, question: str) -> WhyNot:
        """One why-not question on the Validator Scenario (an unreadable one says so)."""
        if self.validator is None:
            return WhyNot(question, error="no validator rulebook judged this incident")
        evidence = dict(self.inc.scenarios.validator)
        try:
            found = why_not(self.inv.engine, self.validator, question, self._validator_atoms(), evidence)
        except QuestionUnreadable as exc:
            return WhyNot(question, error=str(exc))
        return WhyNot(found["question"], found["holds"], tuple(found["trees"]), self.validator.name,
                      "validator scenario", answers=found.get("answers"))

    # -- lawful actions and counterfactuals ------------------------------------------------------------
    def _lawful_actions(self) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """The actions the validator rulebook speaks of, split by whether `V can A` holds on the
        Validator Scenario: the paper's Lawful Actions (of those the rules name)."""
        if self.validator is None:
            return (), ()
        named = (CAN.functor, MUST_NOT.functor, POTENTIALLY_VIOLATES.functor)
        actions = [self.act]
        for rule in self.validator.document.rules:
            h = rule.head
            if h.functor in named and len(h.args) == 2 and isinstance(h.args[1], str) and h.args[1] not in actions:
                actions.append(h.args[1])
        facts = self._validator_atoms()
        lawful: list[str] = []
        unlawful: list[str] = []
        for act in actions:
            (lawful if self.inv.engine.holds(self.validator, CAN.atom(self.me, act), facts)
             else unlawful).append(str(act))
        return tuple(lawful), tuple(unlawful)

    def _counterfactuals(self) -> dict[str, tuple[Counterfactual, ...]] | None:
        if self.validator is None or self.inc.verdict == Verdict.DISMISSED:
            return None
        engine, facts, can = self.inv.engine, self._validator_atoms(), CAN.atom(self.me, self.act)
        opts: dict[str, Any] = {"values": {"colour": COLOURS}, "exclude": NOT_SWAPPED_IN}
        out: dict[str, tuple[Counterfactual, ...]] = {}
        if self.inc.verdict == Verdict.PUNISHABLE:
            out["lawful"] = _worded(search(engine, self.validator, facts, can, True, self.me, fixed=[self.pv],
                                           **opts), self.validator)
            if self.monitor is not None:
                mfacts = self._atoms(self.monitor, self.inc.scenarios.monitor)
                found = search(engine, self.monitor, mfacts, self.pv, False, self.me, **opts)
                out["no_potential_violation"] = _worded(found, self.monitor)
        else:       # mitigated: only the cheap question, one change
            out[Verdict.PUNISHABLE.value] = _worded(search(engine, self.validator, facts, can, False, self.me, fixed=[self.pv],
                                               max_size=1, **opts), self.validator)
        return out

    # -- helpers ---------------------------------------------------------------------------------------
    def _book(self, sha: str | None) -> Rulebook | None:
        return self.inv.rulebook(sha) if sha else None

    def _atoms(self, rb: Rulebook, facts) -> list[Atom]:
        """The scenario's sentences the rulebook reads, as the investigation read them (a
        sentence no template fits is already an unknown-fact finding)."""
        return [a for a in (self.inv.reader.atom(rb, s) for s, _ in facts) if a is not None]

    def _validator_atoms(self) -> list[Atom]:
        if self.validator is None:          # no verdict's rulebook: an empty Validator Scenario
            return [self.pv]
        return self._atoms(self.validator, self.inc.scenarios.validator) + [self.pv]


def _worded(found: list[Found], rb: Rulebook) -> tuple[Counterfactual, ...]:
    return tuple(Counterfactual(cf.kind, tuple(
        Change(c.kind, rb.render(c.fact), rb.render(c.new) if c.new else None, c.controlled,
               (c.fact.functor, *c.fact.args), (c.new.functor, *c.new.args) if c.new else None)
        for c in cf.changes)) for cf in found)
