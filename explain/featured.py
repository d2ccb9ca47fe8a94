"""The incidents a tour of a run shows first: one of each kind the demo is seeded for.

A simulated run holds dozens of incidents; a newcomer should first read the few that show what
the system is for, in the paper's order (section 7.2, then the two it exists for beside them).
Picking them is reading the verdicts already given, never judging again.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterable

from reasoner.model import Incident
from reasoner.verdicts import HC_171, HC_176, Verdict

ASDE = "authorised self-driving entity"


@dataclass(frozen=True)
class Feature:
    title: str
    wanted: Callable[[Incident], bool]


def stated(inc: Incident, sentence: str) -> bool:
    """Whether the Validator Scenario the verdict rests on states this sentence (or the Monitor
    Scenario, where the validator had none)."""
    facts = inc.scenarios.validator or inc.scenarios.monitor
    return any(text == sentence for text, _ in facts)


def _red_running_car(i: Incident) -> bool:
    return (i.rule == HC_176 and i.verdict == Verdict.PUNISHABLE and i.liable == "driver"
            and stated(i, f"{i.vehicle} is of type car") and not stated(i, f"{i.vehicle} is on an emergency call"))


FEATURES = (
    Feature(f"a car entering on red: {Verdict.PUNISHABLE}, the driver liable ({HC_176})", _red_running_car),
    Feature(f"an emergency vehicle on a call entering on red: {Verdict.MITIGATED} (TSRGD Sch 14 para 5(5))",
            lambda i: i.rule == HC_176 and i.verdict == Verdict.MITIGATED),
    Feature("an automated car whose camera misread the light: a perception fault, its ASDE liable",
            lambda i: i.liable == ASDE and any(f.kind == "perception fault" for f in i.findings)),
    Feature(f"a Stop line run: {Verdict.PUNISHABLE} ({HC_171})",
            lambda i: i.rule == HC_171 and i.verdict == Verdict.PUNISHABLE),
)


def featured(numbered: Iterable[tuple[int, Incident]]) -> list[tuple[Feature, tuple[int, Incident] | None]]:
    """Each feature with the first incident that shows it (None where the run has none)."""
    found = list(numbered)
    return [(f, next(((n, i) for n, i in found if f.wanted(i)), None)) for f in FEATURES]
