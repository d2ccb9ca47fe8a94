"""Incidents as a list to scan: one line each, and the full explanations on request.

`gaps incidents` prints one line per incident so that an investigator sees a whole run at a
glance and then asks `gaps explain` about the one that matters. Lines are drawn from the typed
`Incident` (reasoner.model), so a renamed field fails here rather than printing a blank.
"""
from __future__ import annotations

from collections import Counter
from typing import TYPE_CHECKING, Iterable, Iterator

from reasoner.model import OWN_RECORD, Finding, Incident, Margin, Penalty, found_in
from reasoner.when import format_time

if TYPE_CHECKING:
    from reasoner import Case


def incident_line(inc: Incident, number: int | None = None) -> str:
    """One incident in one line: number, time, id, vehicle, action, rule, verdict, penalty,
    who is liable, the margin where the incident has one, and its findings."""
    fields = [format_time(inc.t), inc.id, f"vehicle {inc.vehicle}", inc.action, inc.rule or "no rule",
              inc.verdict, _penalty(inc.penalty), f"liable: {inc.liable}"]
    if inc.margin is not None:
        fields.append(_margin(inc.margin))
    if (found := _found(inc)) is not None:
        fields.append(found)
    fields.append(_findings(inc.findings))
    line = "  ".join(fields)
    return f"{number:>3}  {line}" if number is not None else line


def explanations(case: Case, incidents: Iterable[tuple[int, Incident]]) -> Iterator[str]:
    """The full text explanation of each numbered incident under a heading; the case verifies
    each run's chain once for all its incidents."""
    from .text import explain_incident
    for n, inc in incidents:
        yield f"── incident {n}: {inc.run} {inc.id} ──\n" + explain_incident(case, inc) + "\n"


def _found(inc: Incident) -> str | None:
    """Where the act was found, where that is news: only in the vehicle's own record, or in
    several records of the one act (one incident, one penalty); nothing for one monitor's."""
    sources = inc.sources
    if sources and found_in(sources) == OWN_RECORD:
        return "found in the vehicle's own record only"
    if len(sources) > 1:
        return f"one act, {len(sources)} records ({', '.join(dict.fromkeys(s.src for s in sources))})"
    return None


def _penalty(p: Penalty | None) -> str:
    if p is None:
        return "no penalty"
    parts = [f"£{p.fine_gbp}" if p.fine_gbp is not None else None,
             f"{p.points} points" if p.points else None]
    return " + ".join(part for part in parts if part) or p.offence


SHORT = {   # a margin's quantity as a listing line says it, value and unit filled in
    "seconds after red the stop line was crossed": "crossed {} after red",
    "seconds into red-and-amber the stop line was crossed": "crossed {} into red-and-amber",
    "metres from the stop line when amber came": "{} from the line at amber",
    "seconds stationary at the Stop line": "stood {} at the Stop line",
    "slowest measured speed before the Stop line": "slowed to {} before the Stop line",
    "deceleration of the other road user": "made another brake at {}",
    "seconds stopped in the box junction": "stood {} in the box",
    "mph over the speed limit": "{} over the limit",
}


def _margin(m: Margin) -> str:
    amount = f"{m.bound + ' ' if m.bound else ''}{m.value:g} {m.unit}"
    text = SHORT[m.quantity].format(amount) if m.quantity in SHORT else f"{m.quantity} {amount}"
    if m.uncertainty is not None:
        text += f" (± {m.uncertainty:g} {m.unit})"
    return text + (" (uncertain)" if m.uncertain else "") + (" (within its uncertainty)" if m.unproven else "")


def _findings(findings: tuple[Finding, ...]) -> str:
    """Each kind once, in the order first found, with how many where more than one: a run with
    lost events has nine "missing evidence" findings, which a line cannot list one by one."""
    if not findings:
        return "no findings"
    counts = Counter(f.kind for f in findings)
    names = ", ".join(_kind(kind, n, [f for f in findings if f.kind == kind]) for kind, n in counts.items())
    return f"{len(findings)} finding{'s' if len(findings) != 1 else ''}: {names}"


def _kind(kind: str, n: int, found: list[Finding]) -> str:
    """One kind: its name, how many where more than one, and for missing events which ones, each
    source's missing seqs joined into ranges ("missing evidence ×9: vehicle/173 seq 12-20")."""
    text = kind if n == 1 else f"{kind} ×{n}"
    spans: dict[str, list[tuple[int, int]]] = {}
    for f in found:
        if f.src is not None and f.missing_seq is not None:
            spans.setdefault(f.src, []).append(f.missing_seq)
    if not spans:
        return text
    return text + ": " + "; ".join(f"{src} seq {', '.join(_ranges(seqs))}" for src, seqs in spans.items())


def _ranges(seqs: list[tuple[int, int]]) -> list[str]:
    """Spans of seqs with those that touch joined: (12, 14), (15, 20) -> 12-20."""
    joined: list[list[int]] = []
    for first, last in sorted(seqs):
        if joined and first <= joined[-1][1] + 1:
            joined[-1][1] = max(joined[-1][1], last)
        else:
            joined.append([first, last])
    return [f"{a}" if a == b else f"{a}-{b}" for a, b in joined]


def acts_summary(incidents: list[Incident], recorded_pvs: int | None = None) -> str:
    """Where a run's incidents came from, so that the counts a user meets agree: one incident per
    act (DESIGN "One act, one offence"), those the monitors saw (with the potential violations
    they recorded among them: two cameras on one passage are one incident), and those found only
    in the vehicles' own records. `recorded_pvs`: what the producer said it recorded (the
    simulation's summary), said beside it where it differs from what the incidents cite."""
    own = sum(1 for inc in incidents if found_in(inc.sources) == OWN_RECORD)
    cited = sum(1 for inc in incidents for src in inc.sources if src.how == "recorded")
    seen = len(incidents) - own
    text = f"one per act: {seen} the monitors saw, citing the {cited} potential violations they recorded"
    if recorded_pvs is not None and recorded_pvs != cited:
        text += f" (of {recorded_pvs} recorded in all)"
    return text + f"; {own} found only in the vehicles' own records"
