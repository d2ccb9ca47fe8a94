"""One act, one offence: the incidents of one road user, one rule and one act made one.

Several records may raise the same act: two cameras on one junction, a camera's flag and its own
observations re-derived, a camera and the vehicle's own telemetry. A court convicts once for one
act (the shared notes: "a single passage through a junction or a single continuous stretch over a
limit is one offence, however many cameras recorded it"). So the investigation judges each record
as a case (investigation.py), and then the cases of one act become one incident here:

- one road user (`vehicle`) and one rule: the same `action` (enter the junction, enter the box
  junction, exceed the speed limit), the law's act, whichever rule of it judged each record;
- one act (model.Act): for a junction rule, the vehicle's passage through that junction
  (reasoner/rebuild.py: from its first sample near the junction to its last), two records being
  of one act when their passages overlap; for speeding, one continuous stretch over the road's
  limit (reasoner/stretches.py, with its stated gap tolerance), two records being of one act when
  their stretches overlap. A record whose act the measurements do not delimit (no passage, no
  speed measured) is an act of its own: nothing the record shows joins it to another.

The merged incident keeps every record: its `sources` (each with its id, source and how it was
raised, the one it is named by first), the evidence and findings of all of them; it is named (its
`id` and `t`) by the earliest record a monitor made, else by the earliest of the road user's own
record, so its id does not move when a rulebook changes a verdict, and an act a monitor recorded
keeps the id it had before its other records were found. Its verdict, rule, penalty,
liability, scenarios and margin are those of one record, the representative: a record that proves
the act (punishable or mitigated) before one that is dismissed, and among those, the verdict most
favourable to the road user (mitigated before punishable), since a defence one record shows is not
undone by another's silence. Records that disagree on the verdict are a finding ("sources
disagree"), naming each one's.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Any, Iterable

from store import EventRef

from .model import MONITORS, Act, Finding, Incident, Source
from .verdicts import Verdict

PREFERENCE = {Verdict.MITIGATED: 0, Verdict.PUNISHABLE: 1, Verdict.DISMISSED: 2}


def groups(incidents: Iterable[Any]) -> list[list[Any]]:
    """The incidents (time-ordered) in groups of one road user, one action and one act, each
    group time-ordered, the groups in the order of their first incident."""
    out: list[list[Any]] = []
    open_: dict[tuple[str, str], list[tuple[list[Act], list[Any]]]] = {}
    for inc in incidents:
        act = inc.act
        if act is None:
            out.append([inc])
            continue
        mine = open_.setdefault((inc.vehicle, inc.action), [])
        for acts, group in mine:
            if any(act.overlaps(other) for other in acts):
                acts.append(act)
                group.append(inc)
                break
        else:
            group = [inc]
            mine.append(([act], group))
            out.append(group)
    return out


def named(group: list[Any]) -> Any:
    """The record the merged incident is named by: the earliest a monitor made (recorded,
    re-derived or swept from its measurements), else the earliest of the road user's own record;
    so an act a monitor recorded keeps the id it has always had, whatever else recorded it."""
    return min(group, key=lambda inc: (not inc.sources or inc.sources[0].found_in != MONITORS, inc.t, inc.id))


def representative(group: list[Any]) -> Any:
    """The record whose judgement the merged incident takes (module docstring)."""
    return min(group, key=lambda inc: (PREFERENCE.get(inc.verdict, 3), inc.t, inc.id))


def sources_of(group: list[Any]) -> tuple[Source, ...]:
    """Every record of the group's act, once each, in the group's order."""
    seen: dict[str, Source] = {}
    for inc in group:
        for source in inc.sources:
            seen.setdefault(source.id, source)
    return tuple(seen.values())


def merge(group: list[Incident]) -> Incident:
    """The one incident of a group's act (module docstring)."""
    first, rep = named(group), representative(group)
    findings = list(rep.findings)
    have = {_key(f) for f in findings}
    for inc in group:
        for f in inc.findings:
            if _key(f) not in have:
                have.add(_key(f))
                findings.append(f)
    verdicts = {inc.verdict for inc in group}
    if len(verdicts) > 1:
        findings.append(_disagree(group, rep))
    evidence = once(ref for inc in [first, rep, *group] for ref in inc.evidence)
    sources = sources_of([first, *(inc for inc in group if inc is not first)])
    return replace(rep, id=first.id, t=first.t, monitor=first.monitor,
                   recorded=any(inc.recorded for inc in group), rederived=any(inc.rederived for inc in group),
                   findings=tuple(findings), evidence=evidence, act=_span(group), sources=sources)


def _disagree(group: list[Incident], rep: Incident) -> Finding:
    each = "; ".join(f"{inc.id} ({', '.join(s.src for s in inc.sources[:1])}): {inc.verdict}"
                     + (f" under {inc.rule}" if inc.rule else "") for inc in group)
    detail = (f"the records of this one act were judged differently: {each}. The incident takes "
              f"{rep.id}'s {rep.verdict} (a record that proves the act before one dismissed; mitigated before "
              "punishable, a defence one record shows not undone by another's silence)")
    anchors = tuple(ref for inc in group for ref in inc.evidence[:1])
    return Finding("sources disagree", detail, anchors)


def _span(group: list[Incident]) -> Act | None:
    """The act as all the group's records delimit it: from the earliest start to the latest end."""
    acts = [inc.act for inc in group if inc.act is not None]
    if not acts:
        return None
    lo = min(acts, key=lambda a: a.start)
    hi = max(acts, key=lambda a: a.end)
    return replace(acts[0], start=lo.start, end=hi.end, open_start=lo.open_start, open_end=hi.open_end)


def _key(f: Finding) -> tuple:
    return (f.kind, f.detail, f.fact, f.src)


def once(refs: Iterable[EventRef]) -> tuple[EventRef, ...]:
    """The refs in their order, each once (by its key)."""
    seen, out = set(), []
    for r in refs:
        if r.key not in seen:
            seen.add(r.key)
            out.append(r)
    return tuple(out)
