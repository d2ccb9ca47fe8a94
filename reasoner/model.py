"""What the reasoner hands to the other rooms: an incident and its parts, as typed, frozen values.

An incident used to be a dict built up in place, read elsewhere by string with `.get` defaults that
hid typos; these types say what each part holds, and `to_json()` writes exactly the JSON that
`gaps incidents --json` has always printed (tests/reasoner/test_incidents_golden.py), so scripts
reading it see no change but the `margin` key.

Proof trees stay JSON (DESIGN "Proof trees": sentence, status, rule, source, evidence, children):
they are data for renderers, already in their published shape.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping

from store import EventRef
from .unforced import Unforced

# What other rooms take from here (tests/architecture/test_walls.py): the incident and the parts of it
# explain names (explain/listing.py, explanation_doc.py, scene_text.py, featured.py, act_data.py, the
# report's rulebooks); the reasoner's own modules use the rest
# (Cited: the control status's events, which explain/scene_text.py cites)
__all__ = ["FASTEST_MEASURED", "OWN_RECORD", "Cited", "Control", "Decision", "Finding", "Incident", "Margin", "Penalty",
           "RulebookChoice", "found_in"]

Tree = Mapping[str, Any]          # a proof tree as DESIGN's JSON
Fact = tuple[Any, EventRef]       # a recorded sentence (a str, unless a producer wrote nonsense) and its event


def _refs(refs: Iterable[EventRef]) -> list[dict[str, Any]]:
    return [r.to_json() for r in refs]


def _facts(facts: Iterable[Fact]) -> list[list[Any]]:
    return [[sentence, ref.to_json()] for sentence, ref in facts]


@dataclass(frozen=True)
class RulebookChoice:
    """The rulebook a stage was judged with, and why that one: given with --rules, recorded by
    the run, or the project's current one."""

    name: str
    sha256: str
    source: str

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "sha256": self.sha256, "source": self.source}


@dataclass(frozen=True)
class Finding:
    """Something the record itself shows is wrong or missing, with the events it rests on.

    kind: perception fault, decision fault, monitor disagreement, missing evidence, unknown fact,
    contradiction, unmeasured claim (a stated prediction the verdict rests on, with nothing of the
    road user it names measured).
    The fields after `evidence` belong to one kind each (None where they do not apply)."""

    kind: str
    detail: str
    evidence: tuple[EventRef, ...] = ()
    fact: str | None = None                              # unknown fact: the sentence, cut to 200 characters;
                                                         # contradiction: the stated sentence
    src: str | None = None                               # missing evidence: the source
    missing_seq: tuple[int, int] | None = None           # missing evidence: first and last missing seq
    vehicle_said: tuple[str, ...] = ()                   # perception fault
    monitor_observed: tuple[str, ...] = ()               # perception fault
    recomputed_permitted: bool | None = None             # decision fault: the rulebook's answer
    recorded_permitted: Any = None                       # decision fault: what the vehicle recorded
    proceeds: Any = None                                 # decision fault: whether it went on

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> Finding:
        """A finding read back from the JSON `to_json` writes."""
        seq = data.get("missing_seq")
        return cls(kind=data["kind"], detail=data["detail"],
                   evidence=tuple(EventRef.from_json(r) for r in data.get("evidence", [])),
                   fact=data.get("fact"), src=data.get("src"),
                   missing_seq=(seq[0], seq[1]) if seq else None,
                   vehicle_said=tuple(data.get("vehicle_said", ())),
                   monitor_observed=tuple(data.get("monitor_observed", ())),
                   recomputed_permitted=data.get("recomputed_permitted"),
                   recorded_permitted=data.get("recorded_permitted"), proceeds=data.get("proceeds"))

    def to_json(self) -> dict[str, Any]:
        evidence = _refs(self.evidence)
        if self.kind == "perception fault":
            return {"kind": self.kind, "vehicle_said": list(self.vehicle_said),
                    "monitor_observed": list(self.monitor_observed), "evidence": evidence, "detail": self.detail}
        if self.kind == "decision fault":
            return {"kind": self.kind, "detail": self.detail, "evidence": evidence,
                    "recomputed_permitted": self.recomputed_permitted,
                    "recorded_permitted": self.recorded_permitted, "proceeds": self.proceeds}
        if self.kind == "unknown fact":
            return {"kind": self.kind, "fact": self.fact, "evidence": evidence, "detail": self.detail}
        if self.kind == "missing evidence":
            seq = {"missing_seq": list(self.missing_seq)} if self.missing_seq is not None else {}
            return {"kind": self.kind, "src": self.src, **seq, "evidence": evidence, "detail": self.detail}
        if self.kind == "contradiction" and self.fact is not None:
            return {"kind": self.kind, "fact": self.fact, "detail": self.detail, "evidence": evidence}
        return {"kind": self.kind, "detail": self.detail, "evidence": evidence}


@dataclass(frozen=True)
class Penalty:
    """The fixed penalty a punishable violation carries (penalties stage). With a liability stage,
    `fine_gbp` is the fixed penalty offered to the liable party and `points` those endorsed on a
    licence, `fine_gbp_by_law` and `points_by_law` what the law sets for the offence: a
    self-driving entity is offered no fixed penalty (`fine_gbp` None) and holds no licence, and
    faces `regulatory_sanctions` instead."""

    offence: str
    law: str | None
    fine_gbp: Any                                   # as the rulebook states it: a number, normally
    points: Any
    offences: tuple[Penalty, ...] = ()              # every offence found, when there are several
    points_by_law: Any = None
    regulatory_sanctions: tuple[str, ...] | None = None     # None: no liability stage judged it
    fine_gbp_by_law: Any = None

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"offence": self.offence, "law": self.law, "fine_gbp": self.fine_gbp,
                               "points": self.points}
        if self.offences:
            out["offences"] = [p.to_json() for p in self.offences]
        if self.regulatory_sanctions is not None:
            out["fine_gbp_by_law"] = self.fine_gbp_by_law
            out["points_by_law"] = self.points_by_law
            out["regulatory_sanctions"] = list(self.regulatory_sanctions)
        return out


@dataclass(frozen=True)
class Liability:
    """Who answers for a punishable violation (liability stage), on which facts and proof.
    `fixed_penalty`: who is offered the fixed penalty; None when the rulebook does not say (a
    recorded rulebook older than that rule), and the penalty is then reported as the law sets it."""

    parties: tuple[str, ...]
    licence_points: tuple[str, ...]
    sanctions: tuple[str, ...]
    facts: tuple[str, ...]
    rulebook: str                                   # sha256
    evidence: Mapping[str, EventRef]                # liability fact -> the event that shows it
    trees: tuple[Tree, ...]
    fixed_penalty: tuple[str, ...] | None = None

    def to_json(self) -> dict[str, Any]:
        out = {"parties": list(self.parties), "licence_points": list(self.licence_points),
               "sanctions": list(self.sanctions), "facts": list(self.facts), "rulebook": self.rulebook,
               "evidence": {s: r.to_json() for s, r in self.evidence.items()}, "trees": list(self.trees)}
        if self.fixed_penalty is not None:
            out["fixed_penalty"] = list(self.fixed_penalty)
        return out


@dataclass(frozen=True)
class Cited:
    """An event as the store's fold cites it in a piece of state, {src, seq, t} (store/state.py's
    `_cite`: the state already says the run, and where the piece sits says the kind). The control
    status's events and the scene's last event are these; `to_json()` is the fold's own shape."""

    src: str
    seq: int
    t: int

    @classmethod
    def of(cls, piece: Mapping[str, Any] | None) -> Cited | None:
        """The citation of a piece of folded state (None for none)."""
        return None if piece is None else cls(piece["src"], piece["seq"], piece["t"])

    def ref(self, run: str | None, kind: str | None) -> EventRef:
        """The store.EventRef of the event cited, given the run and kind the piece left out."""
        return EventRef(run, self.src, self.seq, self.t, kind)

    def to_json(self) -> dict[str, Any]:
        return {"src": self.src, "seq": self.seq, "t": self.t}


@dataclass(frozen=True)
class AdsEvent(Cited):
    """The latest ads.event of a vehicle's control status (control.py): the fold's citation of it
    and the event it reported, as sent (UN R157 8.2.1's DSSAD event: "activated", ...)."""

    event: Any

    @classmethod
    def of(cls, cut: Mapping[str, Any] | None) -> AdsEvent | None:
        """From control.py's {src, seq, t, event} (None for none)."""
        return None if cut is None else cls(cut["src"], cut["seq"], cut["t"], cut["event"])

    def ref(self, run: str | None, kind: str | None = "ads.event") -> EventRef:
        """The store.EventRef of this ads.event in `run`."""
        return super().ref(run, kind)

    def to_json(self) -> dict[str, Any]:
        return {**super().to_json(), "event": self.event}


def _cited(piece: Cited | None) -> dict[str, Any] | None:
    return None if piece is None else piece.to_json()


@dataclass(frozen=True)
class Control:
    """Who was in control of the vehicle at the incident (control.py), with the folded ads.event
    status it was read from: each status event as the store's fold cites it (`Cited`)."""

    in_control: str                 # "driver", "self-driving feature" or "user-in-charge"
    automated: bool
    engaged: bool
    user_in_charge: bool
    no_user_in_charge: bool
    transition_demand: Cited | None
    transition_demand_expired: bool
    since: Cited | None
    minimal_risk_manoeuvre: Cited | None
    failure: Cited | None
    last_ads_event: AdsEvent | None

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> Control:
        """From control.control_at's answer (the scene shows it as it is)."""
        return cls(data["in_control"], data["automated"], data["engaged"], data["user_in_charge"],
                   data["no_user_in_charge"], Cited.of(data["transition_demand"]), data["transition_demand_expired"],
                   Cited.of(data["since"]), Cited.of(data["minimal_risk_manoeuvre"]), Cited.of(data["failure"]),
                   AdsEvent.of(data["last_ads_event"]))

    def to_json(self) -> dict[str, Any]:
        return {"in_control": self.in_control, "automated": self.automated, "engaged": self.engaged,
                "user_in_charge": self.user_in_charge, "no_user_in_charge": self.no_user_in_charge,
                "transition_demand": _cited(self.transition_demand),
                "transition_demand_expired": self.transition_demand_expired, "since": _cited(self.since),
                "minimal_risk_manoeuvre": _cited(self.minimal_risk_manoeuvre), "failure": _cited(self.failure),
                "last_ads_event": self.last_ads_event.to_json() if self.last_ads_event else None}


@dataclass(frozen=True)
class Act:
    """The act an incident is about, as the record delimits it (reasoner/oneact.py): a vehicle's
    passage through a junction (`kind` "junction passage", `where` the junction) or a continuous
    stretch over a road's speed limit ("speeding stretch", `where` the road). `start` and `end` are
    ns; `open_start`/`open_end`: the record read begins or ends inside the act (a bound, not the
    act's own edge). Incidents of one road user, one rule and one act are one incident."""

    kind: str
    where: str | None
    start: int
    end: int
    method: str = ""
    open_start: bool = False
    open_end: bool = False

    def overlaps(self, other: Act) -> bool:
        return (self.kind, self.where) == (other.kind, other.where) and self.start <= other.end \
            and other.start <= self.end

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"kind": self.kind, "where": self.where, "start": self.start, "end": self.end,
                               "method": self.method}
        if self.open_start or self.open_end:
            out["open"] = [side for side, yes in (("start", self.open_start), ("end", self.open_end)) if yes]
        return out


OWN_RECORD = "own-record"        # Source.found_in of the vehicle's own record (entity.state, ads.event)
MONITORS = "monitors"            # ... of a monitor (its potential violation, observations or measurements)


@dataclass(frozen=True)
class Source:
    """One record of an act: the event an incident was first raised from (`id`, "<src>:<seq>"),
    its kind, and how it was raised: "recorded" (a monitor.potential_violation), "re-derived" (the
    monitor rules on its observations), "measured" (a sweep of the measurements: reasoner/sweep.py)."""

    id: str
    src: str
    kind: str
    how: str

    @property
    def found_in(self) -> str:
        return OWN_RECORD if self.src.startswith(("vehicle/", "pedestrian/")) else MONITORS

    def to_json(self) -> dict[str, Any]:
        return {"id": self.id, "src": self.src, "kind": self.kind, "how": self.how, "found_in": self.found_in}


def found_in(sources: Iterable[Source]) -> str:
    """Where an act was found: "monitors", "own-record" (only in the vehicle's own record), or
    "monitors and own-record"."""
    places = {s.found_in for s in sources}
    if places == {OWN_RECORD}:
        return OWN_RECORD
    return MONITORS if places <= {MONITORS} else f"{MONITORS} and {OWN_RECORD}"


FASTEST_MEASURED = "fastest measured speed"     # a speeding margin's figure: the speed that decided


@dataclass(frozen=True)
class Margin:
    """How far from the line a verdict was (DESIGN "Margins"): e.g. 1.2 s after red, 8 mph over.
    reasoner/margins.py measures them from a history; `method` says how, `figures` gives the
    other measured values of the same moment (speed when amber came, the stopping distance),
    `uncertain` what the record leaves open, `uncertainty` how far the value may be from the
    truth (reasoner/tolerance.py), `bound` "at least" where the record gives only a bound, and
    `unproven` why the margin does not prove the act (a conviction needs the margin beyond its
    uncertainty). Those after `figures` are written only when present, so a margin without
    them reads as it always has."""

    quantity: str
    value: float
    unit: str
    evidence: tuple[EventRef, ...] = ()
    method: str = ""
    figures: tuple[tuple[str, float, str], ...] = ()     # (quantity, value, unit)
    uncertain: str | None = None
    uncertainty: float | None = None    # ± in `unit`: sampling interval, sensor tolerance, interpolation
    bound: str | None = None            # "at least": the record gives a bound only (red began before it)
    unproven: str | None = None         # why the margin does not prove the act: within its uncertainty

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"quantity": self.quantity, "value": self.value, "unit": self.unit,
                               "evidence": _refs(self.evidence)}
        if self.method:
            out["method"] = self.method
        if self.figures:
            out["figures"] = [{"quantity": q, "value": v, "unit": u} for q, v, u in self.figures]
        if self.uncertain:
            out["uncertain"] = self.uncertain
        if self.uncertainty is not None:
            out["uncertainty"] = self.uncertainty
        if self.bound:
            out["bound"] = self.bound
        if self.unproven:
            out["unproven"] = self.unproven
        return out


@dataclass(frozen=True)
class DerivedFact:
    """A sentence a vehicle's history shows (no full stop, as scenario facts are kept), how, and on
    what: reasoner/derived.py derives them, and an incident carries those it was judged with."""

    sentence: str
    method: str
    evidence: tuple[EventRef, ...]
    uncertain: str | None = None

    def to_json(self) -> dict[str, Any]:
        return {"sentence": self.sentence, "method": self.method, "uncertain": self.uncertain,
                "evidence": [r.to_json() for r in self.evidence]}


@dataclass(frozen=True)
class Decision:
    """The Vehicle Action: the vehicle's latest vehicle.decision at the incident."""

    goal: Any
    action: Any
    permitted: Any
    proceeds: Any
    rulebook: Any
    evidence: EventRef

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> Decision:
        return cls(data.get("goal"), data.get("action"), data.get("permitted"), data.get("proceeds"),
                   data.get("rulebook"), EventRef.from_json(data["evidence"]))

    def to_json(self) -> dict[str, Any]:
        return {"goal": self.goal, "action": self.action, "permitted": self.permitted, "proceeds": self.proceeds,
                "rulebook": self.rulebook, "evidence": self.evidence.to_json()}


@dataclass(frozen=True)
class Scenarios:
    """The paper's scenarios at the incident, each fact with the event that recorded it."""

    vehicle: tuple[Fact, ...]
    monitor: tuple[Fact, ...]
    validator: tuple[Fact, ...]
    action: Decision | None

    def to_json(self) -> dict[str, Any]:
        return {"vehicle": _facts(self.vehicle), "monitor": _facts(self.monitor),
                "validator": _facts(self.validator), "action": self.action.to_json() if self.action else None}


@dataclass(frozen=True)
class StageProof:
    """One stage's proof (or why-not) trees, with the sha256 of the rulebook that gave them."""

    rulebook: str | None
    trees: tuple[Tree, ...]

    def to_json(self) -> dict[str, Any]:
        return {"rulebook": self.rulebook, "trees": list(self.trees)}


@dataclass(frozen=True)
class Proofs:
    """The monitor stage's proof of the potential violation; the validator's of the verdict
    (None where no validator judged: a dismissal on the monitor's own observation)."""

    potential_violation: StageProof
    verdict: StageProof | None = None

    def to_json(self) -> dict[str, Any]:
        out = {"potential_violation": self.potential_violation.to_json()}
        if self.verdict is not None:
            out["verdict"] = self.verdict.to_json()
        return out


@dataclass(frozen=True)
class Incident:
    """A potential violation, judged (reasoner/investigation.py says how).

    id is "<src>:<seq>" of the recorded potential violation, or of the first observation an
    unrecorded one was re-derived from; t is in ns since the epoch; verdict is punishable,
    mitigated or dismissed; liable is the party named first (LIABLE_ORDER) or "none"."""

    id: str
    run: str
    t: int
    vehicle: str
    action: str
    monitor: str
    recorded: bool
    rederived: bool
    rule: str | None
    law: str | None
    verdict: str                                    # a Verdict's word (reasoner/verdicts.py): typed Verdict
                                                    # once the investigation passes one (issue 38)
    why: str | None
    penalty: Penalty | None
    liable: str
    liability: Liability | None
    control: Control
    findings: tuple[Finding, ...]
    evidence: tuple[EventRef, ...]
    judged_on: str                                  # "vehicle scenario" or "monitor scenario"
    rulebook: RulebookChoice | None                 # the validator's
    rulebooks: Mapping[str, RulebookChoice]         # stage -> rulebook
    scenarios: Scenarios
    proofs: Proofs
    margin: Margin | None = None
    rulebook_problems: tuple[str, ...] = field(default=())
    derived: tuple[DerivedFact, ...] = ()           # what the history added to the Monitor Scenario
    moments: tuple[tuple[str, int], ...] = ()       # the passage's moments: ("crossed the stop line", t), ...
    act: Act | None = None                          # the act, as the record delimits it (None: not delimited)
    sources: tuple[Source, ...] = ()                # every record of the act (reasoner/oneact.py), the first first
    second_limb: tuple[Unforced, ...] = ()          # road users the act neither forced nor endangered, with the
                                                    # figures and the reason (reasoner/second_limb.py)

    @property
    def found_in(self) -> str:
        """Where the act was found: "monitors", "own-record" or "monitors and own-record"."""
        return found_in(self.sources)

    @property
    def parties(self) -> tuple[str, ...]:
        """Every party liable (the liability stage's), none without a liability."""
        return self.liability.parties if self.liability else ()

    @property
    def anchor(self) -> EventRef | None:
        """The event the incident is named after (the recorded potential violation, or the first
        observation it was re-derived from), among its evidence."""
        src, _, seq = self.id.rpartition(":")
        return next((r for r in self.evidence if r.src == src and str(r.seq) == seq), None)

    def to_json(self) -> dict[str, Any]:
        out = {"id": self.id, "run": self.run, "t": self.t, "vehicle": self.vehicle, "action": self.action,
               "monitor": self.monitor, "recorded": self.recorded, "rederived": self.rederived,
               "rule": self.rule, "law": self.law, "verdict": self.verdict, "why": self.why,
               "penalty": self.penalty.to_json() if self.penalty else None, "liable": self.liable,
               "liability": self.liability.to_json() if self.liability else None,
               "margin": self.margin.to_json() if self.margin else None,
               "control": self.control.to_json(), "findings": [f.to_json() for f in self.findings],
               "evidence": _refs(self.evidence), "judged_on": self.judged_on,
               "rulebook": self.rulebook.to_json() if self.rulebook else None,
               "rulebooks": {stage: b.to_json() for stage, b in self.rulebooks.items()},
               "scenarios": self.scenarios.to_json(), "proofs": self.proofs.to_json(),
               "found_in": self.found_in, "sources": [s.to_json() for s in self.sources],
               "act": self.act.to_json() if self.act else None}
        if self.rulebook_problems:
            out["rulebook_problems"] = list(self.rulebook_problems)
        if self.derived:
            out["derived"] = [f.to_json() for f in self.derived]
        if self.moments:
            out["moments"] = [{"what": what, "t": t} for what, t in self.moments]
        if self.second_limb:
            out["second_limb"] = [u.to_json() for u in self.second_limb]
        return out

    def summary_json(self) -> dict[str, Any]:
        """What `gaps incidents --json` prints: all but the scenarios and the proofs."""
        return {k: v for k, v in self.to_json().items() if k not in ("proofs", "scenarios", "derived", "moments",
                                                                  "second_limb")}
