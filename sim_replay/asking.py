"""The simulation's one way to the law: the bundled rulebooks, asked through the reasoner's engine.

The agents hold no copy of a rule: a vehicle asks highway_code.le "V can enter the junction" on
its perceived facts, a monitor asks monitors.le "V potentially violates A" on its observation.
Sentences are read with the rulebook's own templates into terms (reasoner.facts.FactReader) and
handed to the engine as data, never as Prolog text (DESIGN "Facts are data").

A monitor asks on every observation, and most observations differ from an earlier one only in
which road users they are about; `holds` therefore remembers answers by the facts' shape (the
road users renamed: reasoner.shapes), as reasoner.episodes does. A vehicle's question
comes with the proof its vehicle.trace carries; where the rulebook keeps road users' values
apart from everything else (`Shaper.keeps_proofs`), that proof too is worked out once per shape
and the vehicle's own names put back into it (`_renamed`): the engine's answer to the renamed
facts is its answer to the facts, renamed. Thousands of vehicles ask a few hundred shapes
("a car driving itself with a green light and nobody about").
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from reasoner.onboard import CURRENT_SET, Answer, FactReader, Rulebook, Shaper, bundled, constant, enrich, get_engine

__all__ = ["Asked", "Rulebooks", "design_tree"]

KEPT_ANSWERS = 20_000     # answers kept by shape (the oldest go first): a long run's shapes stay few


@dataclass(frozen=True)
class Asked:
    """A question's answer and the proof (or why-not tree) that carries it, as DESIGN's JSON."""

    question: str
    holds: bool
    proof: dict[str, Any] | None


def design_tree(node: dict[str, Any]) -> dict[str, Any]:
    """An enriched proof tree in DESIGN's event form ("Proof trees"): the sentence as English,
    `rule` the label it cites ("HC 176"), its source line, and the children."""
    out = {"sentence": node["text"], "status": node["status"], "rule": node.get("label"),
           "source": node.get("source"), "evidence": list(node.get("evidence", ())),
           "children": [design_tree(k) for k in node.get("children", ())]}
    if node.get("truncated"):
        out["truncated"] = True
    return out


class Rulebooks:
    """The bundled rulebooks (reasoner.bundled.CURRENT_SET), loaded once; counts every question."""

    def __init__(self, names: tuple[str, ...] = CURRENT_SET) -> None:
        self.engine = get_engine()
        self.texts = {name: bundled(name) for name in names}
        self.books: dict[str, Rulebook] = {name: self.engine.load(text, name) for name, text in self.texts.items()}
        self.reader = FactReader()
        self.queries = 0          # questions: every one asked with its proof, and each yes/no of a new shape
        self.engine_asks = 0      # questions with proofs the engine worked out (the rest: their shape's answer)
        self._cache: dict[tuple, bool] = {}
        self._answers: dict[tuple, Answer] = {}
        self._shapers = {name: Shaper(rb) for name, rb in self.books.items()}

    def records(self) -> list[dict[str, str]]:
        """run.start's `rulebooks`: name, sha256 and full text of each."""
        return [{"name": name, "sha256": self.books[name].sha256, "text": text} for name, text in self.texts.items()]

    def sha256(self, name: str) -> str:
        return self.books[name].sha256

    def _atoms(self, rb: Rulebook, question: str, facts: list[str]) -> tuple[Any, list]:
        goal = self.reader.atom(rb, question)
        if goal is None:
            raise ValueError(f"{rb.name} has no template for the question {question!r}")
        atoms = []
        for f in facts:
            atom = self.reader.atom(rb, f)
            if atom is None:
                raise ValueError(f"{rb.name} has no template for {f!r}: the simulation states only its sentences")
            atoms.append(atom)
        return goal, atoms

    def ask(self, name: str, question: str, facts: list[str]) -> Asked:
        """One question with its proof: the first proof where it holds, the why-not tree where not."""
        rb = self.books[name]
        goal, atoms = self._atoms(rb, question, facts)
        self.queries += 1
        answer, back = self._answer(name, rb, goal, atoms)
        tree = answer.proofs[0] if answer.proofs else answer.why_not
        return Asked(question, answer.holds, _design(tree, rb, back) if isinstance(tree, dict) else None)

    def _answer(self, name: str, rb: Rulebook, goal: Any, atoms: list) -> tuple[Answer, dict[str, Any]]:
        """The engine's answer with its trees as data, worked out once per shape of the question
        and facts where the rulebook keeps proofs under renaming (module docstring), with what
        puts these facts' own names back in place of the stand-ins (`_design` does, as it writes
        the tree; {}: the answer is the facts' own)."""
        shaper = self._shapers[name]
        shaped = shaper.shape([goal, *atoms]) if shaper.keeps_proofs else None
        if shaped is None:
            self.engine_asks += 1
            return self.engine.ask(rb, goal, atoms), {}
        (shaped_goal, *shaped_atoms), names = shaped
        key = (name, shaped_goal, *shaped_atoms)
        found = self._answers.get(key)
        if found is None:
            self.engine_asks += 1
            found = self.engine.ask(rb, shaped_goal, shaped_atoms)
            if len(self._answers) >= KEPT_ANSWERS:
                del self._answers[next(iter(self._answers))]
            self._answers[key] = found
        return found, {stand_in: value for value, stand_in in names.items()}

    def holds(self, name: str, question: str, facts: list[str], vehicle: str) -> bool:
        """Yes or no, remembered by the shape of the question and facts."""
        rb = self.books[name]
        goal, atoms = self._atoms(rb, question, facts)
        shaped = self._shapers[name].shape([goal, *atoms], constant(vehicle.split(" ")))
        if shaped is not None:
            goal, *atoms = shaped[0]
        key = (name, goal, *atoms) if shaped is not None else None
        found = self._cache.get(key) if key is not None else None
        if found is None:
            self.queries += 1
            found = self.engine.holds(rb, goal, atoms)
            if key is not None:
                self._cache[key] = found
        return found


def _design(node: dict[str, Any], rb: Rulebook, back: dict[str, Any]) -> dict[str, Any]:
    """design_tree(enrich(_renamed(node, back), rb)) in one walk: only what the event's tree keeps
    is renamed (each node's sentence, status, rule, evidence and truncated), not the whole of the
    engine's tree, whose copy was a fifth of the cost of a vehicle's question; the same tree."""
    rule_id = _renamed(node.get("rule"), back)
    rule = rb.rule(rule_id)
    out = {"sentence": rb.render(_renamed(node["sentence"], back)), "status": _renamed(node["status"], back),
           "rule": rule.label if rule else None, "source": rb.source(rule_id),
           "evidence": [_renamed(e, back) for e in node.get("evidence", [])],
           "children": [_design(k, rb, back) for k in node["children"]]}
    if _renamed(node.get("truncated"), back):
        out["truncated"] = True
    return out


def _renamed(data: Any, back: dict[str, Any]) -> Any:
    """Prolog's data (dicts, lists, atoms, numbers) with each stand-in replaced by its value: a
    copy, so that what is kept is never handed out."""
    kind = type(data)
    if kind is dict:
        return {key: _renamed(value, back) for key, value in data.items()}
    if kind is list:
        return [_renamed(value, back) for value in data]
    if kind is str:
        return back.get(data, data)
    return data
