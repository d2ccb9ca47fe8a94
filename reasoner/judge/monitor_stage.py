"""The monitor stage: the Monitor Scenario of a case and whether its rules re-derive the act.

A recorded potential violation the monitor's own observation does not support is dismissed;
one nobody recorded that the rules do not raise is no incident.
"""
from __future__ import annotations

from typing import Any

from store import EventRef

from ..engine import Answer, enrich
from ..model import Finding, StageProof
from ..history import Scenario, monitor_scenario
from ..stages import Choice, RuleSet
from ..vocabulary import POTENTIALLY_VIOLATES
from .asking import as_asked, asked_noting
from .case import SECOND, Case
from .court import Court

STATED_NEAR_S = 1.0                   # a monitor's statement this old at an act its measurements found is of it


def scenario_of(case: Case) -> Scenario:
    """The Monitor Scenario: the observation the case was raised from, else the monitor's last
    observation of the vehicle at t (else the facts its recorded potential violation states)."""
    if case.episode is not None:
        obs = case.episode.observation_at(case.t)
        if obs.get("kind") not in (None, "monitor.observation"):
            return stated_beside(case)
        scenario = Scenario()
        scenario.add(obs["body"].get("facts"), EventRef.of(obs))
        return scenario
    scenario = monitor_scenario(case.state, case.monitor, case.vehicle)
    if not scenario.facts and case.pv is not None and isinstance(case.pv["body"].get("facts"), list):
        scenario.add(case.pv["body"]["facts"], EventRef.of(case.pv))
    return scenario


def stated_beside(case: Case) -> Scenario:
    """The Monitor Scenario of an act found in a road user's own measurements (an entity.state
    the sweep named): what the junction's monitor stated of the vehicle at the act, where it
    observed it within STATED_NEAR_S before (a camera that states the light but not the
    crossing); else nothing stated, and the measurements alone show the act."""
    scenario = monitor_scenario(case.state, case.monitor, case.vehicle)
    if scenario.facts and not all(case.t - ref.t <= STATED_NEAR_S * SECOND for _, ref in scenario.facts):
        return Scenario()
    return scenario


def rederived(court: Court, case: Case, mscen: Scenario, unknown: list[Finding]) -> tuple[Answer | None, Any]:
    """The monitor rulebook's answer on the Monitor Scenario and the rule that holds (if any),
    asked of the court by its question."""
    monitor, why_not = case.rs["monitor"], case.pv is not None
    if monitor is None:
        return None, None

    def asked(mine: list[Finding]) -> list | None:
        answer, _ = rederive(court, case.rs, mscen, case.me, case.act, mine, why_not=why_not)
        return None if answer is None else [answer.proofs, answer.why_not]
    kept = asked_noting(court, case, "rederived", [monitor.rulebook.sha256, why_not, case.me, case.act,
                                                   as_asked(mscen.facts)], asked, unknown)
    if kept is None:
        return None, None
    answer = Answer(*kept)
    return answer, (monitor.rulebook.rule(answer.proofs[0]["rule"]) if answer.holds else None)


def rederive(court: Court, rs: RuleSet, mscen: Scenario, me: Any, act: Any, unknown: list[Finding],
             why_not: bool = True) -> tuple[Answer | None, Any]:
    """The monitor rulebook's answer with its proof; without `why_not`, None where it does not
    hold (a case nobody recorded that does not hold is no incident, and why it does not, the
    costliest question there is, is not asked)."""
    monitor = rs["monitor"]
    if monitor is None:
        return None, None
    rb = monitor.rulebook
    goal, atoms = POTENTIALLY_VIOLATES.atom(me, act), court.reader.atoms(rb, mscen.facts, unknown)
    if not why_not and not court.engine.holds(rb, goal, atoms):
        return None, None
    answer = court.engine.ask(rb, goal, atoms)
    rule = rb.rule(answer.proofs[0]["rule"]) if answer.holds else None
    return answer, rule


def unsupported(mscen: Scenario, measured: bool) -> str:
    """Why a recorded potential violation the monitor rules do not re-derive is dismissed."""
    if measured:
        return ("the monitor's own observation, with what the measurements show at the act (see the facts marked "
                "measured), does not show the potential violation it recorded")
    return ("the monitor's own observation does not show the potential violation it recorded" if mscen.facts
            else "no observation of the vehicle by the monitor supports the potential violation it recorded")


def disagreement(case: Case, mscen: Scenario, rederived: bool, measured: bool) -> Finding | None:
    """A monitor disagreement: it recorded what its rules do not derive, or derived what it did
    not record."""
    if case.pv and rederived:
        return None
    if not case.pv and not str(case.anchor.get("src", "")).startswith("monitor/"):
        return None             # an act found in a road user's own record: no monitor raised or missed it
    if case.pv:
        detail = ("the monitor recorded this potential violation, but the monitor rules do not derive it from "
                  "its own observation of the vehicle" + (" with what the measurements show at the act"
                                                          if measured else "") if mscen.facts else
                  "the monitor recorded this potential violation without any observation of the vehicle to "
                  "support it")
    else:
        detail = ("the monitor rules derive a potential violation from the monitor's observations" +
                  (" and what the measurements show at the act" if measured else "") +
                  ", but the monitor did not record one")
    return Finding("monitor disagreement", detail,
                   (EventRef.of(case.anchor), *(ev for _, ev in mscen.facts[:1])))


def proof(answer: Answer | None, choice: Choice | None, scenario: Scenario, trees: bool = True) -> StageProof:
    """The monitor stage's proof (`trees` False: its rulebook alone, the trees left out)."""
    if answer is None or choice is None:
        return StageProof(None, ())
    rb = choice.rulebook
    if not trees:
        return StageProof(rb.sha256, ())
    shown = answer.proofs[:1] or ([answer.why_not] if answer.why_not else [])
    return StageProof(rb.sha256, tuple(enrich(tree, rb, scenario.evidence) for tree in shown))
