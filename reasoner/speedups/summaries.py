"""Incidents read by their summaries: what tells one from the others and what a regression
compares (its verdict, rule, penalty and who is liable), with the whole incident loaded only
when asked for.

A regression's baseline reads the kept summaries of the judgement in force, and its new side
judges each case only as far as its summary goes (`summarised`: no finding, evidence or proof
worked out); both then show the proofs of the changed incidents only (on the hour 214 of 1,758,
whose whole entries are 24 MB of JSON). `IncidentSummary` is its own type: a caller that needs
more than the summary asks for it, by `whole` (or `proofs`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Callable, Union

from .. import oneact
from ..findings import Gaps
from ..judge import monitor_stage, pipeline, sanctions
from ..judge import findings as F
from ..judge.case import Case, Judged, incident_id
from ..judge.court import Court
from ..judge.status import at_act
from ..model import Act, Incident, Penalty, Proofs, Source
from ..history import Scenario, vehicle_scenario

SUMMARY = ("id", "run", "t", "vehicle", "action", "verdict", "rule", "liable", "penalty", "parties", "act", "sources")


@dataclass(frozen=True, eq=False)
class IncidentSummary:
    """An incident by its summary (the fields of `SUMMARY`, as the whole incident has them); the
    whole incident is `whole()`, loaded (decoded from the cache, or judged) when first asked for,
    and its proofs `proofs`, worked out alone where that is cheaper."""

    id: str
    run: str
    t: int
    vehicle: str
    action: str
    verdict: str
    rule: str | None
    liable: str
    penalty: Penalty | None
    parties: tuple[str, ...]
    act: Act | None
    sources: tuple[Source, ...]
    load: Callable[[], Incident | None] = field(repr=False)
    prove: Callable[[], Proofs | None] | None = field(default=None, repr=False)
    _found: dict[str, Any] = field(default_factory=dict, repr=False)

    def whole(self) -> Incident:
        """The whole incident (loaded once)."""
        if "whole" not in self._found:
            self._found["whole"] = self.load()
        found = self._found["whole"]
        assert found is not None, f"incident {self.id} of {self.run} no longer judges as one"
        return found

    @property
    def proofs(self) -> Proofs:
        """The whole incident's proofs, worked out alone where `prove` can (once)."""
        if "whole" not in self._found and self.prove is not None:
            if "proofs" not in self._found:
                self._found["proofs"] = self.prove()
            if self._found["proofs"] is not None:
                return self._found["proofs"]
        return self.whole().proofs


Judgement = Union[Incident, IncidentSummary]


def whole(incident: Judgement) -> Incident:
    """The whole incident of an incident or of its summary."""
    return incident.whole() if isinstance(incident, IncidentSummary) else incident


def summary_of(incident: Judgement) -> list:
    """The summary's fields of an incident (whole, or its summary), as kept (in `SUMMARY`'s order)."""
    return [getattr(incident, name) for name in SUMMARY]


def kept(summary: list, load: Callable[[], Incident | None],
         prove: Callable[[], Proofs | None] | None = None) -> IncidentSummary:
    """The incident summary of kept fields (`summary_of`'s list)."""
    fields: dict[str, Any] = dict(zip(SUMMARY, summary, strict=True))
    return IncidentSummary(**fields, load=load, prove=prove)


def summarised(court: Court, case: Case, gaps: Gaps) -> IncidentSummary | None:
    """The case judged as far as its summary goes: the monitor stage, the verdict, its rule,
    the penalty and who is liable, every one asked as the pipeline asks it, and none of the
    findings, evidence or proofs; the whole incident, with its proofs, is judged when asked for."""
    judged, _ = _summary_stages(court, case, False)
    if judged is None:
        return None
    rule, liability = judged.rule, judged.liability
    mscen = monitor_stage.scenario_of(case)
    sources = F.sources(case, mscen)         # before the measured facts join the scenario
    act = court.act(case, mscen, vehicle_scenario(case.state, case.vehicle))
    return IncidentSummary(
        id=incident_id(case), run=case.run, t=case.t, vehicle=case.vehicle, action=case.action,
        verdict=judged.validation.verdict, rule=rule.label if rule else None, liable=sanctions.liable(liability),
        penalty=judged.penalty, parties=liability.parties if liability else (), act=act, sources=sources,
        load=lambda: pipeline.judge(court, case, gaps, True), prove=lambda: proofs_alone(court, case))


def proofs_alone(court: Court, case: Case) -> Proofs | None:
    """The proofs of the monitor stage and of the verdict, as the pipeline with proofs finds
    them, without the rest of the incident (a regression shows a changed verdict's proofs alone)."""
    judged, mscen = _summary_stages(court, case, True, sanctioned=False)
    if judged is None:
        return None
    return Proofs(monitor_stage.proof(judged.pv_answer, case.rs["monitor"], mscen, True), judged.validation.proof)


def _summary_stages(court: Court, case: Case, proofs: bool, sanctioned: bool = True) -> tuple[Judged | None, Scenario]:
    """The pipeline's stages for a summary (or its proofs alone) on the case's scenarios and the
    parts of its measurement a summary reads, with the Monitor Scenario they were added to."""
    mscen = monitor_stage.scenario_of(case)
    vscen = vehicle_scenario(case.state, case.vehicle)
    overruled = court.overruled(case, mscen, vscen)
    derived, weighing = court.derived(case, mscen, vscen), court.weighing(case, mscen, vscen)
    case = at_act(court, case, weighing[2])
    vscen = vehicle_scenario(case.state, case.vehicle)
    judged = pipeline.stages(court, case, mscen, vscen, derived, [], proofs, summary=True, sanctioned=sanctioned,
                             overruled=overruled, weighing=weighing)
    return judged, mscen


def merged(group: list[Judgement]) -> Judgement:
    """One incident for the records of one act (reasoner/oneact.py): whole incidents merged now;
    incidents read by their summaries merged by their summaries, and whole when asked for."""
    if all(isinstance(i, Incident) for i in group):
        return oneact.merge([whole(i) for i in group])
    rep, first = oneact.representative(group), oneact.named(group)
    summary = {name: getattr(rep, name) for name in SUMMARY}
    summary.update(id=first.id, t=first.t, sources=oneact.sources_of([first, *(i for i in group if i is not first)]))
    return kept([summary[name] for name in SUMMARY], lambda: oneact.merge([whole(i) for i in group]),
                lambda: rep.proofs)
