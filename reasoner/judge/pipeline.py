"""Judging one case, start to end: history → facts → monitor stage → validator stage → verdict →
sanctions → findings and proofs, each step one function of what the steps before it found; the
frozen `Incident` (model.py) is built once at the end.

    incident = judge(court, case, gaps)

The court (court.py) answers what a step asks beyond the case; the plain court works everything
out, a sped-up one (reasoner/speedups/) reads what it kept: the pipeline is the same.
"""
from __future__ import annotations

from typing import Any

from store import EventRef

from ..history import control_at
from ..findings import Gaps, missing_evidence
from ..measurement import Measurement
from ..model import Control, DerivedFact, Finding, Incident, Proofs, RulebookChoice, Scenarios
from ..history import Scenario, entity, has_perception, vehicle_action, vehicle_scenario
from ..stages import RuleSet
from . import findings as F
from . import monitor_stage, sanctions, validator_stage
from ..verdicts import Verdict
from .case import NO_WEIGHING, Case, Judged, Validation, Weighing, incident_id
from .court import Court
from .status import at_act
from .weighing import proved, weighing_of


def judge(court: Court, case: Case, gaps: Gaps, proofs: bool = True) -> Incident | None:
    """The incident; None for a potential violation nobody recorded that the observations
    suggested but the whole record (the measurements at the act) does not show. `proofs`
    False: the stages' proofs left empty (the verdict's rule is then the monitor's; where
    the monitor's proof names none, the validator's proof is worked out for its rule)."""
    unknown: list[Finding] = []
    mscen = monitor_stage.scenario_of(case)
    sources = F.sources(case, mscen)         # before the measured facts join the scenario
    measured = court.measured(case, mscen, vehicle_scenario(case.state, case.vehicle))
    weighing = weighing_of(measured, case.action)
    case = at_act(court, case, weighing[2])
    vscen = vehicle_scenario(case.state, case.vehicle)
    judged = stages(court, case, mscen, vscen, measured.derived, unknown, proofs, overruled=measured.overruled,
                    weighing=weighing)
    if judged is None:
        return None
    validation, control, rule = judged.validation, judged.control, judged.rule
    action = vehicle_action(case.state, case.vehicle)
    found = findings(court, case, gaps, mscen, vscen, measured, judged, unknown, action)
    return Incident(
        id=incident_id(case), run=case.run, t=case.t, vehicle=case.vehicle,
        action=case.action, monitor=case.monitor, recorded=case.pv is not None, rederived=judged.rederived,
        rule=rule.label if rule else None, law=rule.law if rule else None,
        verdict=validation.verdict, why=validation.why, penalty=judged.penalty,
        liable=sanctions.liable(judged.liability), liability=judged.liability, control=control, findings=found,
        evidence=F.evidence(case, mscen, vscen, action, control, found, measured), judged_on=judged.judged_on,
        rulebook=validation.rulebook, rulebooks=choices(case.rs),
        scenarios=Scenarios(tuple(vscen.facts), tuple(mscen.facts), validation.scenario, action),
        proofs=Proofs(monitor_stage.proof(judged.pv_answer, case.rs["monitor"], mscen, proofs), validation.proof),
        margin=measured.margin(rule.label if rule else None) if measured.present else None,
        derived=measured.derived, moments=measured.moments,
        rulebook_problems=tuple(court.problems.get(case.run) or ()), act=measured.act, sources=sources,
        second_limb=measured.unforced)


def stages(court: Court, case: Case, mscen: Scenario, vscen: Scenario, derived: tuple[DerivedFact, ...],
           unknown: list[Finding], proofs: bool, summary: bool = False, sanctioned: bool = True,
           overruled: frozenset[str] = frozenset(), weighing: Weighing = NO_WEIGHING) -> Judged | None:
    """What the stages answer of the case, on its scenarios and what its passage shows
    beside them (added to the Monitor Scenario here): None where it is no incident.
    `sanctioned` False: the penalty and who is liable are not asked (None), for the proofs
    alone. `weighing`: the claims the measurements contradict and the margins that prove
    nothing (weighing.py): a verdict that turns on either is not proven."""
    for f in derived:
        mscen.add([f.sentence], f.evidence[0] if f.evidence else EventRef.of(case.anchor))
    if overruled:       # stated predictions the measurements contradict: findings, not the act (issue 35)
        mscen.facts[:] = mscen.without(overruled).facts
        vscen = vscen.without(overruled)
    pv_answer, rule = monitor_stage.rederived(court, case, mscen, unknown)
    rederived = pv_answer is not None and pv_answer.holds
    if not case.pv and not rederived:
        return None
    judged_on = "vehicle scenario" if has_perception(case.state, case.vehicle) else "monitor scenario"
    if case.pv and not rederived:
        validation = Validation(Verdict.DISMISSED, monitor_stage.unsupported(mscen, bool(derived)))
    else:
        validation = validator_stage.validate(court, case, judged_on, vscen, mscen, unknown,
                                              frozenset(f.sentence for f in derived), proofs or rule is None,
                                              summary, weighing[0])
        validation = validator_stage.raised_on(court, case, mscen, validation, weighing[0], summary)
        validation = proved(validation, rule or validation.rule, weighing[1], summary)
    control = Control.from_json(control_at(entity(case.state, case.vehicle),
                                           weighing[2] if weighing[2] is not None else case.t))
    penalty, liability = sanctions.sanctions(court, case, validation, control, vscen) if sanctioned else (None, None)
    return Judged(pv_answer, rederived, judged_on, validation, control, rule or validation.rule, penalty, liability)


def findings(court: Court, case: Case, gaps: Gaps, mscen: Scenario, vscen: Scenario, measured: Measurement,
             judged: Judged, unknown: list[Finding], action: Any) -> tuple[Finding, ...]:
    """Every finding of the judged case, in the order an explanation lists them."""
    validation, control = judged.validation, judged.control
    fault = F.decision_fault(court, case, action, vscen, unknown)
    vehicle = f"vehicle/{case.vehicle}"
    found = (monitor_stage.disagreement(case, mscen, judged.rederived, bool(measured.derived)),
             *F.present(validation.dispute), *F.present(fault),
             *(c.to_finding() for c in measured.contradictions),
             *(c.to_finding() for c in F.beliefs_contradicted(court, case, measured, validation, mscen)),
             F.driving_contradicted(case.vehicle, vscen, control),
             *F.dssad_contradicted(case, mscen, control),
             *(c.to_finding() for c in F.beliefs_overruled(measured)),
             *F.unmeasured_claims(measured, validation),
             *(Finding("map reading", text, (ref,)) for text, ref in measured.readings),
             *missing_evidence(gaps, [vehicle, case.monitor, *measured.signals],
                               measured.at if measured.at is not None else case.t,
                               {vehicle: F.last_seen(case.state, case.vehicle)}),
             *F.dedup_unknown(unknown, {f.sentence for f in measured.derived}))
    return tuple(f for f in found if f is not None)


def choices(rs: RuleSet) -> dict[str, RulebookChoice]:
    return {stage: RulebookChoice(**b) for stage, b in rs.describe().items()}
