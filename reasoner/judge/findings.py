"""A judged case's findings (perception and decision faults, contradictions, monitor
disagreement, missing evidence, unknown facts), each with the events it rests on, and the
evidence and sources of the incident."""
from __future__ import annotations

from typing import Any, Iterable

from store import EventRef, State

from .. import acts, oneact
from ..derived import Contradiction, checked
from ..findings import decision_fault as fault_of
from ..measurement import Measurement
from ..model import Control, Decision, Finding, Source
from ..history import Scenario, entity
from ..vocabulary import IS_DRIVING_ITSELF
from .asking import as_asked, asked_noting
from .case import Case, Validation, incident_id
from .court import Court


def decision_fault(court: Court, case: Case, action: Decision | None, vscen: Scenario,
                   unknown: list[Finding]) -> Finding | None:
    """Whether the vehicle's own decision was lawful by its own (vehicle stage) rulebook."""
    choice = case.rs.vehicle_rulebook(action.rulebook if action else None)
    own = action if action and action.action == case.action else None
    if choice is None or own is None:
        return fault_of(court.engine, court.reader, choice, case.vehicle, own, vscen.facts, unknown)
    return asked_noting(court, case, "fault", [choice.rulebook.sha256, case.vehicle, own.to_json(),
                                               as_asked(vscen.facts)],
                        lambda mine: fault_of(court.engine, court.reader, choice, case.vehicle, own,
                                              vscen.facts, mine), unknown)


def beliefs_contradicted(court: Court, case: Case, measured: Measurement, validation: Validation,
                         mscen: Scenario) -> tuple[Contradiction, ...]:
    """What the vehicle itself stated (its perception) and the verdict was taken on, that its
    passage's measurements contradict: an automated car that judged itself "too close to the
    stop line to stop safely" 28 m out at 30 mph (rule 126: 23 m) went on at amber on a belief
    the record does not bear out. The Validator Scenario keeps it (DESIGN "Reasoning": a
    contradiction is a finding, not an override); this is the finding. A belief the monitor's
    witness replaced (a misread light) is not in that scenario and has its perception-fault
    finding already."""
    if not measured.present:
        return ()
    stated = {text for text, _ in mscen.facts}
    own = [(text, ref) for text, ref in validation.scenario + validation.set_aside
           if text not in stated and ref is not None and ref.kind == "vehicle.perception"]
    if not own:
        return ()
    found = measured.contradicted(own)
    if found is None:           # a belief the measurement did not cover: ask the passage itself
        passage = acts.of(court.passage(case), case.t)
        found = checked(passage, measured.at, own)[1] if passage is not None and measured.at is not None else ()
    return found


def driving_contradicted(vehicle: str, vscen: Scenario, control: Control) -> Finding | None:
    """A contradiction finding where the vehicle states it is driving itself while its ads.event
    record, as it stood at the act, has the feature not engaged (DESIGN "Weighing": status at the
    act is the latest record before it; who drove follows that record, control.py)."""
    said = IS_DRIVING_ITSELF.text(vehicle)
    ref = next((ref for text, ref in vscen.facts if text == said and ref is not None), None)
    last = control.last_ads_event
    if ref is None or control.engaged or not last:
        return None
    event = last.ref(ref.run)
    return Finding("contradiction", f"\"{said}\" was stated ({ref.src} #{ref.seq}), but its ads.event record has the "
                   f"feature not engaged at the act (last: {last.event}, {last.src} #{last.seq})",
                   (ref, event), fact=said)


def dssad_contradicted(case: Case, mscen: Scenario, control: Control) -> tuple[Finding, ...]:
    """Contradictions between the DSSAD record (ads.event, UN R157 8.2.1) as it stood at the act
    and the other records of who drove: a monitor stating "V is driving itself" while the feature
    was not engaged, and a spawn that says the vehicle has no automated driving system (a human
    driver, SAE level under 3) while its DSSAD has the feature engaged. Who drove follows the
    DSSAD (control.py); the other record is a finding, never silently overruled."""
    out = []
    said = IS_DRIVING_ITSELF.text(case.vehicle)
    last = control.last_ads_event
    ads_ref = last.ref(case.run) if last else None
    ref = next((ref for text, ref in mscen.facts if text == said and ref is not None
                and ref.kind == "monitor.observation"), None)
    if ref is not None and not control.engaged:
        where = (f"its ads.event record has the feature not engaged at the act (last: {last.event}, "
                 f"{last.src} #{last.seq})" if last else "its record has no ads.event: no feature was engaged")
        out.append(Finding("contradiction", f"\"{said}\" was stated by {ref.src} (#{ref.seq}), but {where}",
                           (ref,) + ((ads_ref,) if ads_ref else ()), fact=said))
    spawn = (entity(case.state, case.vehicle) or {}).get("spawn") or {}
    body = spawn.get("body") or {}
    level = body.get("automation_level")
    denies = body.get("driver") == "human" and (level is None or (type(level) is int and level < 3))
    if control.engaged and denies and ads_ref is not None and last and spawn.get("src"):
        spawned = EventRef(case.run, spawn["src"], spawn["seq"], spawn["t"], "entity.spawn")
        out.append(Finding("contradiction", f"its entity.spawn ({spawned.src} #{spawned.seq}) says a human drives it "
                           f"with no automated driving system (automation level {level if level is not None else 'not stated'}), "
                           f"but its ads.event record has the feature engaged at the act ({last.event}, "
                           f"{last.src} #{last.seq}): who drove is read from the DSSAD record",
                           (spawned, ads_ref), fact=said))
    return tuple(out)


def beliefs_overruled(measured: Measurement) -> tuple[Contradiction, ...]:
    """The vehicle's own predictions the measurements overruled (left out of the Validator
    Scenario, so `beliefs_contradicted` no longer sees them): each is a finding, once."""
    over = measured.overruled
    found = {(c.stated, c.stated_by.key): c for *_, cs in measured.beliefs for c in cs if c.stated in over}
    return tuple(found.values())


def unmeasured_claims(measured: Measurement, validation: Validation) -> tuple[Finding, ...]:
    """The stated predictions the verdict was taken on with nothing of the road user measured:
    the sentence stands alone, and the explanation says so."""
    used = {text for text, _ in validation.scenario}
    return tuple(Finding("unmeasured claim", f"\"{text}\" was stated ({ref.src} #{ref.seq}) and nothing of {user} "
                         "about the act is in the record: it stands on the statement alone", (ref,), fact=text)
                 for text, ref, user in measured.unmeasured if text in used)


def dedup_unknown(unknown: list[Finding], derived: set[str]) -> list[Finding]:
    """One finding per unknown sentence and event, however many stages tried to read it. A
    derived sentence a rulebook has no template for is offered, not recorded: no finding."""
    seen, out = set(), []
    for f in unknown:
        if f.fact in derived:
            continue
        key = (f.fact, tuple(e.key for e in f.evidence))
        if key not in seen:
            seen.add(key)
            out.append(f)
    return out


def present(finding: Finding | None) -> tuple[Finding, ...]:
    return (finding,) if finding is not None else ()


def last_seen(state: State, vehicle: str) -> int | None:
    """When the vehicle was last recorded (None: despawned, or never)."""
    record = entity(state, vehicle) or {}
    times = [record[k]["t"] for k in ("state", "perception", "decision") if record.get(k)]
    return max(times) if times and not record.get("despawned") else None


def evidence(case: Case, mscen: Scenario, vscen: Scenario, decision: Decision | None, control: Control,
             findings: Iterable[Finding], measured: Measurement) -> tuple[EventRef, ...]:
    """Every event the incident rests on, once each, the anchor first."""
    refs = [EventRef.of(case.anchor)] + [ev for _, ev in (*mscen.facts, *vscen.facts)]
    refs += [ev for f in measured.derived for ev in f.evidence]
    if decision:
        refs.append(decision.evidence)
    if control.last_ads_event:
        refs.append(control.last_ads_event.ref(case.run))
    for f in findings:
        refs += f.evidence
    return oneact.once(refs)


def sources(case: Case, mscen: Scenario) -> tuple[Source, ...]:
    """The records the case's act was raised from: its anchor (the recorded potential violation,
    the monitor's observation it was raised from, or the road user's own measurement the sweep
    named) and, where another source's statements are its Monitor Scenario (a camera's light
    beside the vehicle's own positions), that source too."""
    anchor = case.anchor
    kind = anchor.get("kind") or ("monitor.potential_violation" if case.pv else "monitor.observation")
    how = "recorded" if case.pv else ("observed" if kind == "monitor.observation" else "measured")
    out = [Source(incident_id(case), anchor["src"], kind, how)]
    for _, ref in mscen.facts:      # (the measured facts added to it cite entity.state, signals, the map)
        if ref is not None and ref.kind == "monitor.observation" and ref.src not in {s.src for s in out}:
            out.append(Source(f"{ref.src}:{ref.seq}", ref.src, ref.kind, "stated"))
    return tuple(out)
