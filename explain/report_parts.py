"""A run's report as values: what explain/report.py builds once from the case (reasoner.Case) and
report_html.py and report_md.py render by attribute; `Report.to_json` is what `gaps report -o
r.json` prints (docs/report.md), key for key and in the same order.

An incident's explanation stays the explanation document of explanation_doc.py (the JSON `gaps
explain --json` prints, laid out by layout.py), carried as it is.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from reasoner import ChainStatus
from reasoner.model import RulebookChoice

from .picture_parts import Picture
from .provenance import Provenance
from .timeline_parts import ActTimeline


@dataclass(frozen=True)
class SummaryRow:
    """The summary table's row of an incident: what an insurer scans first."""

    id: str
    t: int
    time: str
    vehicle: str
    action: str
    rule: str | None
    verdict: str
    penalty: str | None
    liable: str
    findings: int

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "t": self.t, "time": self.time, "vehicle": self.vehicle, "action": self.action,
                "rule": self.rule, "verdict": self.verdict, "penalty": self.penalty, "liable": self.liable,
                "findings": self.findings}


@dataclass(frozen=True)
class StageRulebook:
    """The rulebook one stage of an incident's verdict was judged with."""

    stage: str
    book: RulebookChoice

    def to_json(self) -> dict[str, Any]:
        return {"stage": self.stage, **self.book.to_json()}


@dataclass(frozen=True)
class ReportEntry:
    """One incident of the report: its number in the run, its row, its explanation document, the
    picture of the scene at it and the timeline around it."""

    number: int
    row: SummaryRow
    explanation: dict[str, Any]
    scene: Picture
    timeline: ActTimeline
    rulebooks: tuple[StageRulebook, ...]

    def to_json(self) -> dict[str, Any]:
        return {"number": self.number, "row": self.row.to_json(), "explanation": self.explanation,
                "scene": self.scene.to_json(), "timeline": self.timeline.to_json(),
                "rulebooks": [b.to_json() for b in self.rulebooks]}


@dataclass(frozen=True)
class LastCheckpoint:
    """The run's latest checkpoint: how many events it covers, the chain head, the Merkle root."""

    events: Any
    head: Any
    merkle_root: Any

    def to_json(self) -> dict[str, Any]:
        return {"events": self.events, "head": self.head, "merkle_root": self.merkle_root}


@dataclass(frozen=True)
class ReportChain:
    """The run's chain as the reasoner recomputed it, its sentence (evidence.chain_text) and
    checkpoints (count, latest)."""

    status: ChainStatus
    text: str
    checkpoints: int
    last: LastCheckpoint | None

    def to_json(self) -> dict[str, Any]:
        return {**self.status.to_json(), "text": self.text,
                "checkpoints": {"count": self.checkpoints, "last": self.last.to_json() if self.last else None}}


@dataclass(frozen=True)
class UsedRulebook:
    """A rulebook of the report: where it came from (given, recorded, current), the stages it
    served (none: recorded by the run, not used) and its version."""

    name: Any
    sha256: str
    source: str
    stages: tuple[str, ...]
    version: str | None

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "sha256": self.sha256, "source": self.source, "stages": list(self.stages),
                "version": self.version}


@dataclass(frozen=True)
class Report:
    """The report of a run (or of one incident of it: `selected`, its id)."""

    run: str
    generated: str
    provenance: Provenance
    incidents_in_run: int
    selected: str | None
    chain: ReportChain
    rulebooks: tuple[UsedRulebook, ...]
    incidents: tuple[ReportEntry, ...]

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "generated": self.generated, "provenance": self.provenance.to_json(),
                "incidents_in_run": self.incidents_in_run, "selected": self.selected,
                "chain": self.chain.to_json(), "rulebooks": [b.to_json() for b in self.rulebooks],
                "incidents": [e.to_json() for e in self.incidents]}
