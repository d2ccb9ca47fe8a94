"""The validator stage: the verdict on the Validator Scenario, with its proof.

The Validator Scenario is the vehicle's view corrected by what the monitor witnessed and what
the history measured (perception.py); the verdict is punishable (the action is not among the
lawful ones), mitigated (it is) or dismissed. A verdict that turns on a claim the measurements
contradict, or that rests on one at the monitor stage, is not proven (DESIGN "Weighing").
"""
from __future__ import annotations

from dataclasses import replace
from typing import Any

from store import EventRef

from ..engine import Answer, Rulebook, enrich
from ..le.terms import Atom
from ..model import Finding, RulebookChoice, StageProof
from ..perception import corrected, dispute_finding
from ..history import Scenario, entity, status_facts
from ..stages import Choice
from ..vocabulary import CAN, MITIGATELY_VIOLATES, POTENTIALLY_VIOLATES, PUNISHABLY_VIOLATES
from ..verdicts import ASKED, Verdict
from .case import Case, Contested, Validation
from .court import Court

Turn = tuple[str, str, str, list[Atom], list[tuple[Atom, EventRef]]]


def validate(court: Court, case: Case, judged_on: str, vscen: Scenario, mscen: Scenario,
             unknown: list[Finding], derived: frozenset[str] = frozenset(), proofs: bool = True,
             summary: bool = False, contested: Contested = ()) -> Validation:
    """The verdict on the Validator Scenario, with its proof (`proofs` False: asked plainly,
    the proof left empty and no rule found). `summary`: for an incident's summary alone, so
    neither why nor the perception fault finding (what the verdict would be on the vehicle's
    own perception) is worked out."""
    choice = case.rs["validator"]
    if choice is None:
        return Validation(Verdict.DISMISSED, "no rulebook defines punishable and mitigated violations")
    rb, me, act = choice.rulebook, case.me, case.act
    mine = court.reader.pairs(rb, vscen.facts, unknown)
    seen = court.reader.pairs(rb, mscen.facts, unknown)
    pv_atom = POTENTIALLY_VIOLATES.atom(me, act)
    facts, disputes = validator_facts(court, case, judged_on, rb, mine, seen, derived)
    found, answer = verdict(court, rb, me, act, [a for a, _ in facts] + [pv_atom], proofs=proofs)
    dispute = None
    if disputes and not summary:
        alt, _ = verdict(court, rb, me, act, [a for a, _ in mine] + [pv_atom], proofs=False)
        if alt != found:
            dispute = dispute_finding(disputes, rb, alt, found)
    why = "" if summary else why_of(found, rb, me, act)
    turns = turns_on(court, rb, me, act, facts, pv_atom, found, contested)
    set_aside: tuple[tuple[Any, EventRef], ...] = ()
    if turns is not None:
        sentence, words, alt, extra, kept = turns
        set_aside = tuple((court.render(rb, a), ev) for a, ev in facts if (a, ev) not in kept)
        facts = kept
        if alt == Verdict.DISMISSED:
            found, why = Verdict.DISMISSED, "" if summary else (
                f"not proven: the verdict is {found} only on “{sentence}”, which the measurements contradict "
                f"beyond their tolerance: {words}")
        else:
            found, answer = verdict(court, rb, me, act, [a for a, _ in facts] + extra + [pv_atom], proofs=proofs)
            why = "" if summary else (
                f"{why_of(found, rb, me, act)}, on what the measurements show: “{sentence}” was stated, "
                f"but the measurements contradict it beyond their tolerance ({words}), so it decides nothing")
    rendered = tuple((court.render(rb, a), ev) for a, ev in facts)
    evidence = dict(rendered)
    shown: list[Any] = [] if not answer else answer.proofs[:1] if answer.proofs else [answer.why_not]
    proof = StageProof(rb.sha256, tuple(enrich(tree, rb, evidence) for tree in shown))
    rule = rb.rule(answer.proofs[0]["rule"]) if answer and answer.holds else None
    return Validation(found, why, choice_of(choice), rendered, proof, rule, dispute, set_aside)


def raised_on(court: Court, case: Case, mscen: Scenario, validation: Validation, contested: Contested,
              summary: bool) -> Validation:
    """Not proven where the potential violation itself rests on a claim the measurements
    contradict: the monitor rules no longer find it without the claim (a camera's "28 has
    speed of 38" where the car's own record has 30.0 mph; DESIGN "Weighing")."""
    monitor = case.rs["monitor"]
    said = {text: words for text, words, _ in contested}
    held = [text for text in mscen.sentences if isinstance(text, str) and text in said]
    if validation.verdict == Verdict.DISMISSED or monitor is None or not held:
        return validation
    rb = monitor.rulebook
    measured: list[tuple[Any, EventRef | None]] = [(m, None) for text, _, shown in contested if text in held
                                                   for m in shown]
    rest: list[Any] = [(text, ref) for text, ref in mscen.facts if text not in said] + measured
    if court.engine.holds(rb, POTENTIALLY_VIOLATES.atom(case.me, case.act), court.reader.atoms(rb, rest)):
        return validation
    why = "" if summary else (f"not proven: the potential violation rests on “{held[0]}”, and the measurements "
                              f"contradict it beyond their tolerance: {said[held[0]]}")
    return replace(validation, verdict=Verdict.DISMISSED, why=why)


def turns_on(court: Court, rb: Rulebook, me: Any, act: Any, facts: list[tuple[Atom, EventRef]], pv_atom: Atom,
             found: str, contested: Contested) -> Turn | None:
    """Where the verdict turns on a claim the measurements contradict beyond tolerance: the
    claim, what the measurements show, the verdict on them (asked with what they derive in the
    claims' place), the atoms they derive and the facts without the claims; None where no
    contested claim is in the scenario or the verdict is the same without it (DESIGN
    "Weighing": the verdict rests on what is proved, whichever side a claim helps)."""
    if found == Verdict.DISMISSED or not contested:
        return None
    atoms = {a: text for text, _, _ in contested for a, _ in court.reader.pairs(rb, _unreferenced([text]), [])}
    held = [a for a, _ in facts if a in atoms]
    if not held:
        return None
    texts = {atoms[a] for a in held}
    kept = [(a, ev) for a, ev in facts if a not in atoms]
    have = {a for a, _ in kept}
    shown = [m for text, _, ms in contested if text in texts for m in ms]
    measured = [a for a in court.reader.atoms(rb, _unreferenced(shown)) if a not in have]
    alt, _ = verdict(court, rb, me, act, [a for a, _ in kept] + measured + [pv_atom], proofs=False)
    if alt == found:
        return None
    text = atoms[held[0]]
    return text, next(words for said, words, _ in contested if said == text), alt, measured, kept


def validator_facts(court: Court, case: Case, judged_on: str, rb: Rulebook, mine: list, seen: list,
                    derived: frozenset[str]) -> tuple[list[tuple[Atom, EventRef]], list[dict]]:
    """The Validator Scenario: the vehicle's view corrected by what the monitor witnessed and
    the history measured; or, for a vehicle that recorded no perception, its spawn and what
    the monitor saw and the history measured. What the history measured is no belief of the
    vehicle's: it is added whatever the monitor rules look at, and the vehicle's silence on
    it is no perception fault."""
    if judged_on == "vehicle scenario":
        monitor = case.rs["monitor"]
        monitor_rb = monitor.rulebook if monitor else rb
        out, disputes = corrected(mine, seen, court.witnessed_by(monitor_rb), case.me,
                                  court.others(case, [*mine, *seen]))
        measured = {a for a, _ in court.reader.pairs(rb, _unreferenced(derived), [])}
        have = {a for a, _ in out}
        out += [(a, ev) for a, ev in seen if a in measured and a not in have]
        return out, [d for d in disputes if d["vehicle"] or any(a not in measured for a, _ in d["monitor"])]
    record = entity(case.state, case.vehicle) or {}
    spawn = record.get("spawn")
    own = [(a, EventRef.of(spawn, case.state.run, "entity.spawn"))
           for a in court.reader.known(rb, status_facts(case.vehicle, record))] if spawn else []
    return own + seen, []


def verdict(court: Court, rb: Rulebook, me: Any, act: Any, atoms: list[Atom],
            proofs: bool) -> tuple[str, Answer | None]:
    """Punishable, else mitigated, else dismissed (with why it is not punishable); each asked
    plainly first: a proof, or why not, is searched for only where it is shown."""
    goals = (PUNISHABLY_VIOLATES.atom(me, act), MITIGATELY_VIOLATES.atom(me, act))
    if not proofs:
        first = court.engine.first_holding(rb, goals, atoms)
        return (ASKED[first] if first >= 0 else Verdict.DISMISSED), None
    first, answer = court.engine.ask_first(rb, goals, atoms)
    return (ASKED[first] if first >= 0 else Verdict.DISMISSED), answer


def action_text(rb: Rulebook, me: Any, act: Any) -> str:
    """"173 can enter the junction", in the rulebook's words where it has the template."""
    return rb.render(CAN.atom(me, act)) if CAN.functor in rb.document.templates else f"{me} can {act}"


def why_of(found: str, rb: Rulebook, me: Any, act: Any) -> str:
    return {
        Verdict.PUNISHABLE: f"\"{action_text(rb, me, act)}\" is not among the lawful actions of the Validator Scenario",
        Verdict.MITIGATED: f"\"{action_text(rb, me, act)}\" is among the lawful actions of the Validator Scenario",
        Verdict.DISMISSED: "the validator rules establish neither a punishable nor a mitigated violation",
    }[Verdict(found)]


def choice_of(choice: Choice) -> RulebookChoice:
    return RulebookChoice(**choice.describe())


def _unreferenced(sentences: Any) -> Any:
    """Sentences with no event behind them, as the fact reader takes them (what is measured)."""
    return [(s, None) for s in sentences]
