"""The sanctions of a punishable violation: its penalty (penalties stage) and who is liable
(liability stage, over the ads.event history: control.py). Each is asked of the court by its
question, named by the sentences it is asked on (a kept answer is found without parsing them)."""
from __future__ import annotations

from dataclasses import replace
from typing import Any

from store import EventRef

from ..history import ROLE, liability_facts, role
from ..engine import Rulebook, enrich
from ..le.render import arg_text
from ..le.terms import Atom, Cond, Var
from ..model import Control, Liability, Penalty
from ..history import Scenario
from ..stages import defines
from ..vocabulary import (FACES_REGULATORY_SANCTIONS, GETS_LICENCE_POINTS, INCURS_FIXED_PENALTY, IS_AN_OFFENCE_UNDER,
                          IS_LIABLE, IS_OFFERED_A_FIXED_PENALTY, PUNISHABLY_VIOLATES)
from .asking import as_asked
from ..verdicts import Verdict
from .case import Case, Validation
from .court import Court

LIABLE_ORDER = tuple(ROLE.values())   # who is named `liable` when several parties are


def sanctions(court: Court, case: Case, validation: Validation, control: Control,
              vscen: Scenario) -> tuple[Penalty | None, Liability | None]:
    """The penalty and the liability of a punishable verdict (None, None otherwise), the penalty
    as the liability stage offers it (a fixed penalty, licence points, regulatory sanctions)."""
    if validation.verdict != Verdict.PUNISHABLE:
        return None, None
    penalty = penalty_of(court, case, [s for s, _ in validation.scenario])
    liability = liability_of(court, case, control, vscen)
    if penalty is not None and liability is not None:
        offered = liability.fixed_penalty is None or bool(liability.fixed_penalty)
        penalty = replace(penalty, points_by_law=penalty.points, fine_gbp_by_law=penalty.fine_gbp,
                          fine_gbp=penalty.fine_gbp if offered else None,
                          points=penalty.points if liability.licence_points else 0,
                          regulatory_sanctions=liability.sanctions)
    return penalty, liability


def penalty_of(court: Court, case: Case, sentences: list) -> Penalty | None:
    """The penalties stage's answer on the Validator Scenario's sentences."""
    pen = case.rs["penalties"]
    if pen is None:
        return None
    punish = PUNISHABLY_VIOLATES.atom(case.me, case.act)
    rb = pen.rulebook
    return court.ask(case, "penalty", [rb.sha256, case.me, case.act, sentences],
                     lambda: [penalty(court, rb, case.me, court.reader.known(rb, sentences) + [punish])])[0]


def liability_of(court: Court, case: Case, control: Control, vscen: Scenario) -> Liability | None:
    """The liability stage's answer on who was in control at the act."""
    lia = case.rs["liability"]
    if lia is None:
        return None
    punish = PUNISHABLY_VIOLATES.atom(case.me, case.act)
    rb = lia.rulebook
    shown = [(s, control_ref(case.run, control, vscen, basis)) for s, basis in
             liability_facts(case.vehicle, control.to_json())]
    evidence = {s: r for s, r in shown if r}
    sentences = [s for s, _ in shown]
    return court.ask(case, "liability", [rb.sha256, case.me, case.act, sentences, as_asked(evidence.items())],
                     lambda: liability(court, rb, case.me, case.act,
                                       court.reader.known(rb, sentences) + [punish], evidence))


def penalty(court: Court, rb: Rulebook, me: Any, facts: list[Atom]) -> Penalty | None:
    """The highest fixed penalty the facts incur (all of them, where more than one offence does)."""
    question = [Cond(atom=INCURS_FIXED_PENALTY.atom(me, Var("amount"), Var("points"), Var("offence")))]
    found = []
    for binding in court.engine.answers(rb, question, facts, texts=False).bindings:
        _, _, amount, points, offence = binding[0]
        law = court.engine.answers(rb, [Cond(atom=IS_AN_OFFENCE_UNDER.atom(offence, Var("law")))], facts,
                                   texts=False)
        found.append(Penalty(arg_text(offence), arg_text(law.bindings[0][0][2]) if law.bindings else None,
                             amount, points))
    found = list(dict.fromkeys(found))     # one answer per proof: a fact stated twice proves it twice
    if not found:
        return None
    found.sort(key=lambda p: (-_num(p.fine_gbp), -_num(p.points), p.offence))
    return replace(found[0], offences=tuple(found)) if len(found) > 1 else found[0]


def liability(court: Court, rb: Rulebook, me: Any, act: Any, facts: list[Atom],
              evidence: dict[str, EventRef]) -> Liability:
    """Who is liable, who gets the licence points, who faces regulatory sanctions (and, where the
    rulebook says, who is offered a fixed penalty), with the proof of the first."""
    asked = [IS_LIABLE, GETS_LICENCE_POINTS, FACES_REGULATORY_SANCTIONS]
    if defines(rb, IS_OFFERED_A_FIXED_PENALTY.functor):
        asked.append(IS_OFFERED_A_FIXED_PENALTY)
    results = court.engine.answers_all(rb, [([Cond(atom=sentence.atom(Var("party"), act, me))], i == 0)
                                            for i, sentence in enumerate(asked)], facts)
    liable, points, regulatory, *offered = [tuple(role(arg_text(b[0][1])) for b in r.bindings) for r in results]
    return Liability(parties=liable, licence_points=points, sanctions=regulatory,
                     fixed_penalty=offered[0] if offered else None,
                     facts=tuple(rb.render(a) for a in facts), rulebook=rb.sha256,
                     evidence=evidence,
                     trees=tuple(enrich(tree, rb, evidence) for trees in results[0].proofs[:1] for tree in trees))


def liable(found: Liability | None) -> str:
    """The party named `liable`: the first of LIABLE_ORDER among the parties, or "none"."""
    if found is None:
        return "none"
    return next((r for r in LIABLE_ORDER if r in found.parties), found.parties[0] if found.parties else "none")


def control_ref(run: str, control: Control, vscen: Scenario, basis: str) -> EventRef | None:
    """The event behind a liability fact: the spawn, or an ads.event of the control status."""
    if basis == "spawn":
        return next((ev for _, ev in vscen.facts if ev.kind == "entity.spawn"), None)
    cited = control.since if basis == "since" else control.transition_demand
    return cited.ref(run, "ads.event") if cited else None


def _num(value: Any) -> float:
    return value if isinstance(value, (int, float)) else 0
