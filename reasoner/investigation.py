"""From a recorded run to validated verdicts (the paper's Figure 1), from the store alone.

    inv = Investigation(store)                 # or Investigation(store, rules=["my.le"])
    for incident in inv.incidents("demo-001"):
        print(incident.verdict, incident.rule, incident.liable)

An incident is a potential violation: recorded on line by a monitor, or re-derived off line from
the monitor's observations (episodes.py); both, normally. For each, at its time t, from the
store's state at t of the vehicle and of the monitor's observation of it (store.state_of: the
parts of store.state_at an act needs, folded from their own sources' events):

1. the Monitor Scenario re-derives the potential violation (monitor stage); a recorded one that
   the monitor's own observation does not support is *dismissed*;
2. the Validator Scenario (the Vehicle Scenario with what the monitor witnessed, perception.py)
   decides *punishable* (the action is not among the lawful ones) or *mitigated* (it is);
3. a punishable one gets its penalty (penalties stage) and who is liable (liability stage, over
   the ads.event history: control.py);
4. findings (perception fault, decision fault, monitor disagreement, missing evidence, unknown
   fact), each with the events it rests on.

The verdicts depend only on the events, never on the order or batches they arrived in: the state
is a fold in (t, seq, src) order and the episodes are read in that order too.

Each part of an incident is computed by one function from what the parts before it found, and the
frozen `Incident` (model.py) is built once at the end.
"""
from __future__ import annotations

import gc
from dataclasses import dataclass, replace
from functools import cached_property
from typing import TYPE_CHECKING, Any, Callable, Iterable

from store import CollectorPaused, EventRef, State, Store, entity_since, state_of

from . import acts, history, oneact, stretches
from .chain_status import ChainStatus, chain_status
from .collector import JudgementCollector
from .history import ROLE, control_at, liability_facts, role
from .case_memo import CaseMemo, key_of
from .derived import Contradiction, checked
from .engine import Answer, Engine, Rulebook, enrich, get_engine
from .episodes import Episode, Rederiver, episodes, match
from .facts import FactReader
from .findings import Gaps, decision_fault, missing_evidence
from .le.render import arg_text
from .le.sentences import constant
from .le.terms import Atom, Cond, Var
from .model import (Control, Decision, DerivedFact, Finding, Incident, Liability, Penalty, Proofs, RulebookChoice,
                    Scenarios, Source, StageProof)
from .measurement import Measurement, measure, rule_key
from .history import Passage
from .perception import corrected, dispute_finding, witnessed_functors
from .sweep import Candidate, Sweep
from .stages import Choice, RuleSet, current_rulebooks, defines, given_rulebooks, recorded_rulebooks
from .history import (Scenario, entity, has_perception, monitor_scenario, status_facts, vehicle_action,
                        vehicle_scenario)
from .vocabulary import (CAN, FACES_REGULATORY_SANCTIONS, GETS_LICENCE_POINTS, INCURS_FIXED_PENALTY,
                         IS_AN_OFFENCE_UNDER, IS_DRIVING_ITSELF, IS_LIABLE, IS_OFFERED_A_FIXED_PENALTY,
                         MITIGATELY_VIOLATES, POTENTIALLY_VIOLATES, PUNISHABLY_VIOLATES)

if TYPE_CHECKING:
    from .explanation import Explanation

LIABLE_ORDER = tuple(ROLE.values())   # who is named `liable` when several parties are
SECOND = 1_000_000_000
SWEPT_NEAR_S = 15.0                   # a swept act this close to a judged one of the vehicle is that one
STATED_NEAR_S = 1.0                   # a monitor's statement this old at an act its measurements found is of it
# The cases are found and judged with the cyclic collector paused (reasoner/collector.py): its
# full passes traverse every case read, every incident judged so far and every value decoded from
# the kept measurements, a third of a judgement from kept measurements, to find almost nothing.
# Every YOUNG_EVERY cases the young generations alone are collected, so any cycles judging makes
# never pile up: memory stays what it is with the collector on.
YOUNG_EVERY = 256
_RENDERED_LIMIT = 200_000                         # facts an investigation remembers the rendering of
_VERDICTS = ("punishable", "mitigated")          # the questions of _verdict, in the order asked


@dataclass(frozen=True)
class _Case:
    """One potential violation to judge, and the state of the run at its time."""

    run: str
    rs: RuleSet
    state: State
    t: int
    monitor: str
    pv: dict | None               # the recorded monitor.potential_violation, if any
    episode: Episode | None       # the observations it was re-derived from, if any
    vehicle: str
    action: str

    @property
    def anchor(self) -> dict:
        return self.pv if self.pv else self.episode.first

    @cached_property
    def me(self) -> Any:
        """The vehicle as a constant; read once (a case's facts ask it of every argument)."""
        return constant([self.vehicle])

    @cached_property
    def act(self) -> Any:
        return constant(self.action.split())


@dataclass(frozen=True)
class _Validation:
    """What the validator stage found: the verdict, why, and what it rests on."""

    verdict: str
    why: str
    rulebook: RulebookChoice | None = None
    scenario: tuple[tuple[Any, EventRef], ...] = ()
    proof: StageProof | None = None
    rule: Any = None                          # the rule of the verdict's proof, where it holds
    dispute: Finding | None = None
    set_aside: tuple[tuple[Any, EventRef], ...] = ()   # contested claims the verdict was taken without


@dataclass(frozen=True)
class _Judged:
    """What the stages answered of a case: all a regression compares of it, before its findings."""

    pv_answer: Answer | None
    rederived: bool
    judged_on: str
    validation: _Validation
    control: Control
    rule: Any
    penalty: Penalty | None
    liability: Liability | None


_SUMMARY = ("id", "run", "t", "vehicle", "action", "verdict", "rule", "liable", "penalty", "parties", "act", "sources")


class KeptIncident:
    """An incident read by its summary (`_SUMMARY`: what tells it from the others and what a
    regression compares: its verdict, rule, penalty and who is liable): a kept incident of the
    judgement in force, or a regression's new side's judged as far as its summary goes; any
    other part is that of the whole incident, decoded from the cache (or judged again, if its
    entry no longer opens) or judged whole, when first asked for."""

    __slots__ = (*_SUMMARY, "proofs", "_load", "_whole", "_proved")

    def __init__(self, summary: list, load: Callable[[], Incident | None],
                 proved: Callable[[], Proofs | None] | None = None) -> None:
        """`proved`: the incident's proofs worked out alone (None: from the whole incident)."""
        for name, value in zip(_SUMMARY, summary, strict=True):
            setattr(self, name, value)
        self._load, self._whole, self._proved = load, None, proved

    def whole(self) -> Incident:
        if self._whole is None:
            self._whole = self._load()
        return self._whole

    def __getattr__(self, name: str) -> Any:       # only for what the summary does not hold
        if name.startswith("_"):
            raise AttributeError(name)
        if name == "proofs" and self._whole is None and self._proved is not None:
            found = self._proved()
            if found is not None:
                self.proofs = found
                return found
        return getattr(self.whole(), name)


def _summary_of(incident: Incident) -> list:
    return [getattr(incident, name) for name in _SUMMARY]


class SharedReading:
    """What investigations of one store read of a run alike, by what names it (the run, its chain,
    what it is): read and parsed once. Only the last run's is held."""

    def __init__(self) -> None:
        self._run: str | None = None
        self._read: dict[tuple, Any] = {}

    def get(self, key: tuple, read: Callable[[], Any]) -> Any:
        """The value read under `key` (its run first), else `read()` (kept unless None)."""
        if key[0] != self._run:
            self._run, self._read = key[0], {}
        found = self._read.get(key)
        if found is None:
            found = read()
            if found is not None:
                self._read[key] = found
        return found


class Investigation:
    """Verdicts for the runs of one store. Rulebooks and parsed facts are loaded once and shared."""

    def __init__(self, store: Store, engine: Engine | None = None, rules: Iterable[str] | None = None, *,
                 kept: bool = True, verdicts: bool = False, reader: FactReader | None = None,
                 proofs: bool = True, summaries: bool = False, shared: SharedReading | None = None) -> None:
        """`kept`: judge from what earlier investigations of the same chain measured, and keep what
        this one measures (reasoner/case_memo.py); False measures every case afresh and keeps nothing.
        `verdicts` (with `kept`): a run judged by the rulebooks in force (none given) keeps each
        incident, and the next such investigation of the same chain reads it instead of judging
        it (`gaps incidents`, a regression's baseline); off, every case is judged again (the
        benchmark of judging, tests of it). `reader`: a fact reader shared with other askers of
        the same rulebooks (a regression's decisions), so that a sentence is parsed once.
        `proofs` False: an incident's proofs of the potential violation and of the verdict are
        left empty (the verdict asked plainly), and `proved` works them out for an incident
        that shows them: a regression's new side shows the proofs of its changed incidents
        only (on the hour 214 of 1,760), and the proof search and its trees were most of
        judging the others. Such incidents are never kept (only the judgement in force is).
        `summaries` (with `verdicts`): a kept incident is handed back as a `KeptIncident`, read by
        its summary (kept beside it) and decoded whole only when a part outside the summary is
        asked for (a regression's baseline compares the summaries, and shows the proofs of the
        changed incidents only: on the hour 214 of 1,758, whose whole entries are 24 MB of JSON).
        `summaries` with `proofs` False (a regression's new side): each case is judged as far as
        its summary goes (`_summarised`: no finding, evidence or proof worked out) and handed
        back as a `KeptIncident`, judged whole, with its proofs, when a part outside the summary
        is asked for (`proved` hands it back as it is, its proofs worked out alone when asked
        for). `shared`: what investigations of the same runs read alike (a regression's two
        sides, both kept: the runs' recorded potential violations, their cases and those the
        monitor rulebook does not raise), read once."""
        self.store = store
        self.kept = kept
        self.verdicts = verdicts and kept
        self.summaries = summaries and (self.verdicts or not proofs)
        self.proofs = proofs or self.verdicts
        self._unproved: dict[tuple, tuple[_Case, Gaps]] = {}     # by _named(incident)
        self._answered: dict[tuple[str, str], Any] = {}     # stage answers of unkept cases (`proved` asks again)
        self.engine = engine or get_engine()
        self.reader = reader or FactReader()
        self._given = given_rulebooks(self.engine, rules or [])
        self._current = current_rulebooks(self.engine)
        self._rulesets: dict[str, RuleSet] = {}
        self._witnessed: dict[str, set[str]] = {}
        self._chains: dict[str, ChainStatus] = {}
        self._contexts: dict[str, history.RunContext] = {}
        self._names: dict[str, dict[Any, list[str]]] = {}
        self._entity_since: dict[tuple[str, str], float] = {}
        self._firsts: dict[tuple[str, Any], float] = {}
        self._rendered: dict[tuple[str, Atom], str] = {}
        self._memos: dict[str, CaseMemo] = {}
        self.problems: dict[str, list[str]] = {}
        self.shared = shared
        self._judgements: dict[str, tuple[RuleSet, str]] = {}

    # -- public ---------------------------------------------------------------------------
    def incidents(self, run: str, progress: Callable[[int, int], None] | None = None) -> list[Incident]:
        """Every potential violation of the run, judged; ordered by time. `progress(done, total)`
        is called as the cases are judged (after the pass over the observations): `done` of the
        `total` cases (recorded potential violations and acts the sweep found), which end as fewer
        incidents (one per act; a case the rules do not raise is none).

        A case nobody recorded that the monitor rulebook does not raise is no incident whatever
        the other rulebooks say; which ones those were is kept, like the cases, under the monitor
        rulebook (and the chain and the code), and the next investigation with that rulebook does
        not judge them again: two thirds of the hour's cases, a sixth of a judgement from kept
        measurements."""
        memo = self._memos[run] = CaseMemo(self.store, run, enabled=self.kept)      # the chain as it stands now
        with JudgementCollector():
            recorded = self._read(run, ("recorded",),
                                  lambda: list(self.store.events(run, kinds=["monitor.potential_violation"])))
            rs = self.ruleset(run, recorded)
            monitor = rs["monitor"].rulebook.sha256 if rs["monitor"] else None
            todo = self._read(run, ("cases", monitor), lambda: self._todo(run, rs, recorded))
            gaps = Gaps(self.store, run, memo)
            unraised_key = key_of("unraised", monitor)
            skip = self._read(run, ("unraised", monitor), lambda: _names_of(memo.get("unraised", unraised_key, plain=True)))
            kept_unraised = skip is not None
            skip = skip or frozenset()
            found: list[Incident] = []
            unraised: list[list] = []
            for done, (t, src, pv, ep) in enumerate(todo, 1):
                name = (t, _anchor_key(pv, ep), ep.action) if pv is None else None
                if name is not None and name in skip:
                    unraised.append(list(name))
                else:
                    incident = self._case_judged(run, rs, gaps, t, src, pv, ep)
                    if incident is not None:
                        found.append(incident)
                    elif name is not None:
                        unraised.append(list(name))
                if done % YOUNG_EVERY == 0:
                    gc.collect(1)
                if progress is not None:
                    progress(done, len(todo))
        if not kept_unraised:
            self.memo(run).put("unraised", unraised_key, unraised, plain=True)
        self.memo(run).save()
        merged = [group[0] if len(group) == 1 else _merged(group) for group in oneact.groups(found)]
        return sorted(merged, key=lambda inc: inc.t) if len(merged) < len(found) else merged

    def _read(self, run: str, what: tuple, read: Callable[[], Any]) -> Any:
        """What `read` gives, or what another investigation sharing `shared` read of the same
        chain of the run (the cases and the potential violations a regression's two sides read
        alike: read and parsed once). A None read is not shared."""
        if self.shared is None:
            return read()
        return self.shared.get((run, self.memo(run).chain, *what), read)

    def _case_judged(self, run: str, rs: RuleSet, gaps: Gaps, t: int, src: str, pv: dict | None,
                     ep: Episode | None) -> Incident | None:
        """The case's incident: kept under the rulebooks in force (`verdicts`), else judged."""
        if not self.keeps_verdicts(run, rs):
            return self._case_afresh(run, rs, gaps, t, src, pv, ep)
        key = key_of("incident", self._judged_by(run, rs), t, src, _anchor_key(pv, ep),
                     [pv["body"].get("vehicle"), pv["body"].get("action")] if pv else [ep.vehicle, ep.action])
        memo = self.memo(run)

        def whole() -> Incident | None:
            return memo.remember("incident", key, lambda: self._case_afresh(run, rs, gaps, t, src, pv, ep))
        if not self.summaries:
            return whole()
        summary = memo.get("incident summary", key)
        if summary is not None:
            return KeptIncident(summary, whole)
        incident = whole()
        if incident is not None:
            memo.put("incident summary", key, _summary_of(incident))
        return incident

    def _judged_by(self, run: str, rs: RuleSet) -> str:
        """What names the run's judgement in force in each of its incidents' keys: the rulebooks
        of its stages and the problems reading the run's own, digested once per run, not with
        every case (they were most of an incident's key)."""
        found = self._judgements.get(run)
        if found is None or found[0] is not rs:
            found = self._judgements[run] = (rs, key_of(rs.describe(), self.problems.get(run)))
        return found[1]

    def keeps_verdicts(self, run: str, rs: RuleSet) -> bool:
        """Whether this run's incidents are kept: judged by the rulebooks in force (the run's own,
        else the current ones), which is what `gaps incidents` shows; a judgement with a rulebook
        given for any stage is worked out each time (a regression's new rules are judged afresh)."""
        return self.verdicts and all(choice.source != "given" for choice in rs.stages.values())

    def _case_afresh(self, run: str, rs: RuleSet, gaps: Gaps, t: int, src: str, pv: dict | None,
                     ep: Episode | None) -> Incident | None:
        body = pv["body"] if pv else {}
        vehicle = str(body.get("vehicle")) if pv else ep.vehicle
        state = self._state(run, t, vehicle, src)
        case = _Case(run, rs, state, t, src, pv, ep, vehicle, str(body.get("action")) if pv else ep.action)
        if self.summaries and not self.proofs:
            return self._summarised(case, gaps)
        incident = self._judge(case, gaps, self.proofs)
        if incident is not None and not self.proofs:
            self._unproved[_named(incident)] = (case, gaps)
        return incident

    def proved(self, incident: Incident | None) -> Incident | None:
        """The incident with its proofs: judged again with them where this investigation left
        them out (`proofs` False); the same incident otherwise. An incident read by its summary
        (`summaries`) is handed back as it is: its proofs are worked out alone when asked for,
        any other part outside the summary by judging it whole."""
        if incident is None or self.proofs:
            return incident
        if isinstance(incident, KeptIncident):
            return incident         # its proofs, and any other part outside its summary, judged when asked for
        found = self._unproved.get(_named(incident))
        return incident if found is None else self._judge(*found, True)

    def _todo(self, run: str, rs: RuleSet, recorded: list[dict]) -> list[tuple]:
        """The cases to judge, in time order: the recorded potential violations, the episodes the
        monitor rulebook re-derives from the observations, the acts the sweep of the measurements
        finds. Kept under the monitor rulebook for the next investigation of the same chain."""
        monitor = rs["monitor"]
        memo, key = self.memo(run), key_of("cases", monitor.rulebook.sha256 if monitor else None)
        kept = memo.get("cases", key, plain=True)
        if kept is not None:
            by_ref = {(pv["src"], pv["seq"]): pv for pv in recorded}
            todo = [_case_unkept(item, by_ref) for item in kept]
            if all(item is not None for item in todo):
                return todo
        todo = self._find_todo(run, rs, recorded)
        memo.put("cases", key, [_case_kept(item) for item in todo], plain=True)
        return todo

    def _find_todo(self, run: str, rs: RuleSet, recorded: list[dict]) -> list[tuple]:
        monitor = rs["monitor"]
        eps: list[Episode] = []
        swept: list[Candidate] = []
        if monitor is not None:
            rederiver = Rederiver(self.engine, monitor.rulebook, self.reader)
            sweeper = Sweep(self.context(run).map)
            own = Sweep(self.context(run).map)     # the road users' own record, swept apart (its own time order)
            with CollectorPaused():    # hundreds of thousands of parsed observations, no cycles
                eps = list(episodes(_fed(self.store.events(run, kinds=["monitor.observation"]), sweeper), rederiver))
                for state in self.store.events(run, kinds=["entity.state"]):
                    if _well_formed(state):         # a damaged row's event is no measurement
                        own.add(state)
            swept = sorted(sweeper.candidates() + own.candidates(), key=lambda c: (c.t, c.event["src"], c.event["seq"]))
        todo = [(pv["t"], pv["src"], pv, episode) for pv, episode in match(eps, recorded)]
        todo += [(ep.first["t"], ep.monitor, None, ep) for ep in eps if not ep.recorded]
        todo += self._unrecorded(run, swept, todo)
        todo.sort(key=lambda item: (item[0], _anchor_key(item[2], item[3])))
        return todo

    def _state(self, run: str, t: int, vehicle: str, src: str) -> State:
        """The vehicle's record and what the monitor last observed of it at t (kept, like the
        measurements, for the next investigation of the same chain)."""
        return State.from_json(self.memo(run).remember("state", key_of(t, vehicle, src), lambda: state_of(
            self.store, run, t, entities=[f"vehicle/{vehicle}"], observed=[(src, vehicle)]).to_json(), plain=True))

    def memo(self, run: str) -> CaseMemo:
        """What earlier investigations of the run's chain measured, and what this one adds."""
        if run not in self._memos:
            self._memos[run] = CaseMemo(self.store, run, enabled=self.kept)
        return self._memos[run]

    def context(self, run: str) -> history.RunContext:
        """What every history of the run shares (its map, its signals), read once."""
        if run not in self._contexts:
            self._contexts[run] = history.run_context(self.store, run)
        return self._contexts[run]

    def _unrecorded(self, run: str, swept: list[Candidate], todo: list) -> list:
        """The swept candidates no recorded or re-derived potential violation of the same act
        already covers, as one-observation episodes. A speeding candidate is the start of a
        stretch over the limit, and is passed over only within the stretch's own gap tolerance
        of another: a second stretch soon after a first is another act (the cases of one act
        are one incident after judging, reasoner/oneact.py)."""
        near = int(SWEPT_NEAR_S * SECOND)
        near_speeding = int(stretches.STRETCH_GAP_S * SECOND)
        taken: dict[tuple[str, str], list[int]] = {}
        for t, _, pv, ep in todo:
            vehicle, action = (str(pv["body"].get("vehicle")), str(pv["body"].get("action"))) if pv else \
                (ep.vehicle, ep.action)
            taken.setdefault((vehicle, action), []).append(t)
        out = []
        for c in swept:
            times = taken.setdefault((c.user, c.action), [])
            if any(abs(c.t - t) <= (near_speeding if c.action == acts.SPEEDING else near) for t in times):
                continue
            times.append(c.t)
            junction = self.context(run).map.junction(c.junction)
            src = c.event["src"] if c.event.get("kind") == "monitor.observation" or not junction or not junction.monitors \
                else junction.monitors[0]
            out.append((c.t, src, None, Episode(src, c.user, c.action, [c.event])))
        return out

    def ruleset(self, run: str, recorded: list[dict] | None = None) -> RuleSet:
        """The rulebooks each stage of this run is judged with (given, recorded, current).
        `recorded`: the run's potential violations, if the caller has read them already."""
        if run not in self._rulesets:
            problems: list[str] = []
            if recorded is None:
                recorded = list(self.store.events(run, kinds=["monitor.potential_violation"]))
            shas = {e["body"].get("rulebook") for e in recorded if isinstance(e["body"].get("rulebook"), str)}
            books = recorded_rulebooks(self.engine, self.store, run, sorted(shas), problems)
            self._rulesets[run] = RuleSet(self.engine, self._given, books, self._current)
            self.problems[run] = problems
        return self._rulesets[run]

    def rulebook(self, sha256: str) -> Rulebook | None:
        """A rulebook any stage used, by its sha256 (for rendering proofs)."""
        for rs in self._rulesets.values():
            if sha256 in rs.by_sha:
                return rs.by_sha[sha256]
        return None

    def chain(self, run: str) -> ChainStatus:
        """The run's hash chain recomputed, once per run for this investigation: every incident's
        explanation cites it, and recomputing a long run takes seconds."""
        if run not in self._chains:
            self._chains[run] = chain_status(self.store, run)
        return self._chains[run]

    def explanation(self, incident: Incident, *, why_not: Iterable[str] = (),
                    counterfactuals: bool = True) -> Explanation:
        """What an explanation of the incident needs beyond the incident: the lawful actions, the
        answers to why-not questions (on the Validator Scenario), the counterfactuals and the
        chain's status, asked of this investigation's engine and rulebooks."""
        from .explanation import explain
        return explain(self, incident, list(why_not), counterfactuals)

    # -- one incident ---------------------------------------------------------------------
    def _judge(self, case: _Case, gaps: Gaps, proofs: bool = True) -> Incident | None:
        """The incident; None for a potential violation nobody recorded that the observations
        suggested but the whole record (the measurements at the act) does not show. `proofs`
        False: the stages' proofs left empty (the verdict's rule is then the monitor's; where
        the monitor's proof names none, the validator's proof is worked out for its rule)."""
        unknown: list[Finding] = []
        mscen = self._monitor_scenario(case)
        sources = _sources(case, mscen)         # before the measured facts join the scenario
        vscen = vehicle_scenario(case.state, case.vehicle)
        measured = self._measured(case, mscen, vscen)
        weighing = _weighing_of(measured, case.action)
        case = self._at_act(case, weighing[2])
        vscen = vehicle_scenario(case.state, case.vehicle)
        judged = self._stages(case, mscen, vscen, measured.derived, unknown, proofs, overruled=measured.overruled,
                              weighing=weighing)
        if judged is None:
            return None
        validation, control, rule = judged.validation, judged.control, judged.rule
        action = vehicle_action(case.state, case.vehicle)
        fault = self._decision_fault(case, action, vscen, unknown)
        findings = (_disagreement(case, mscen, judged.rederived, bool(measured.derived)), *_present(validation.dispute),
                    *_present(fault),
                    *(c.to_finding() for c in measured.contradictions),
                    *(c.to_finding() for c in self._beliefs_contradicted(case, measured, validation, mscen)),
                    _driving_contradicted(case.vehicle, vscen, control),
                    *_dssad_contradicted(case, mscen, control),
                    *(c.to_finding() for c in _beliefs_overruled(measured)),
                    *_unmeasured_claims(measured, validation),
                    *(Finding("map reading", text, (ref,)) for text, ref in measured.readings),
                    *missing_evidence(gaps, [f"vehicle/{case.vehicle}", case.monitor, *_signals(measured)],
                                      measured.at if measured.at is not None else case.t,
                                      {f"vehicle/{case.vehicle}": _last_seen(case.state, case.vehicle)}),
                    *_dedup_unknown(unknown, {f.sentence for f in measured.derived}))
        findings = tuple(f for f in findings if f is not None)
        return Incident(
            id=_incident_id(case), run=case.run, t=case.t, vehicle=case.vehicle,
            action=case.action, monitor=case.monitor, recorded=case.pv is not None, rederived=judged.rederived,
            rule=rule.label if rule else None, law=rule.law if rule else None,
            verdict=validation.verdict, why=validation.why, penalty=judged.penalty,
            liable=_liable(judged.liability), liability=judged.liability, control=control, findings=findings,
            evidence=_evidence(case, mscen, vscen, action, control, findings, measured), judged_on=judged.judged_on,
            rulebook=validation.rulebook, rulebooks=_choices(case.rs),
            scenarios=Scenarios(tuple(vscen.facts), tuple(mscen.facts), validation.scenario, action),
            proofs=Proofs(_proofs(judged.pv_answer, case.rs["monitor"], mscen, proofs), validation.proof),
            margin=measured.margin(rule.label if rule else None) if measured.present else None,
            derived=measured.derived, moments=measured.moments,
            rulebook_problems=tuple(self.problems.get(case.run) or ()), act=measured.act, sources=sources,
            second_limb=measured.unforced)

    def _summarised(self, case: _Case, gaps: Gaps) -> KeptIncident | None:
        """The case judged as far as its summary goes (`summaries` with `proofs` False: a
        regression's new side): the monitor stage, the verdict, its rule, the penalty and who is
        liable, every one asked as `_judge` asks it, and none of the findings, evidence or
        proofs; the whole incident, with its proofs, is judged when a part outside the summary
        is asked for (on the hour a regression shows 214 of 1,758 so)."""
        judged, _ = self._summary_stages(case, False)
        if judged is None:
            return None
        rule, liability = judged.rule, judged.liability
        mscen = self._monitor_scenario(case)
        sources = _sources(case, mscen)         # before the measured facts join the scenario
        act = self._act(case, mscen, vehicle_scenario(case.state, case.vehicle))
        summary = {"id": _incident_id(case), "run": case.run, "t": case.t, "vehicle": case.vehicle,
                   "action": case.action, "verdict": judged.validation.verdict, "rule": rule.label if rule else None,
                   "liable": _liable(liability), "penalty": judged.penalty,
                   "parties": liability.parties if liability else (), "act": act,
                   "sources": sources}
        return KeptIncident([summary[name] for name in _SUMMARY], lambda: self._judge(case, gaps, True),
                            lambda: self._proofs_alone(case))

    def _proofs_alone(self, case: _Case) -> Proofs | None:
        """The proofs of the monitor stage and of the verdict, as `_judge` with proofs finds them,
        without the rest of the incident (a regression shows a changed verdict's proofs alone)."""
        judged, mscen = self._summary_stages(case, True, sanctioned=False)
        if judged is None:
            return None
        return Proofs(_proofs(judged.pv_answer, case.rs["monitor"], mscen, True), judged.validation.proof)

    def _summary_stages(self, case: _Case, proofs: bool, sanctioned: bool = True) -> tuple[_Judged | None, Scenario]:
        """`_stages` for a summary (or its proofs alone) on the case's scenarios and its kept derived
        facts, with the Monitor Scenario they were added to."""
        mscen = self._monitor_scenario(case)
        vscen = vehicle_scenario(case.state, case.vehicle)
        overruled = self._overruled(case, mscen, vscen)
        derived, weighing = self._derived(case, mscen, vscen), self._weighing(case, mscen, vscen)
        case = self._at_act(case, weighing[2])
        vscen = vehicle_scenario(case.state, case.vehicle)
        judged = self._stages(case, mscen, vscen, derived, [], proofs, summary=True, sanctioned=sanctioned,
                              overruled=overruled, weighing=weighing)
        return judged, mscen

    def _stages(self, case: _Case, mscen: Scenario, vscen: Scenario, derived: tuple[DerivedFact, ...],
                unknown: list[Finding], proofs: bool, summary: bool = False, sanctioned: bool = True,
                overruled: frozenset[str] = frozenset(), weighing: Weighing = ((), (), None)) -> _Judged | None:
        """What the stages answer of the case, on its scenarios and what its passage shows
        beside them (added to the Monitor Scenario here): None where it is no incident.
        `sanctioned` False: the penalty and who is liable are not asked (None), for the proofs
        alone. `weighing`: the claims the measurements contradict and the margins that prove
        nothing (`_weighing`): a verdict that turns on either is not proven."""
        for f in derived:
            mscen.add([f.sentence], f.evidence[0] if f.evidence else EventRef.of(case.anchor))
        if overruled:       # stated predictions the measurements contradict: findings, not the act (issue 35)
            mscen.facts[:] = mscen.without(overruled).facts
            vscen = vscen.without(overruled)
        pv_answer, rule = self._rederived(case, mscen, unknown)
        rederived = pv_answer is not None and pv_answer.holds
        if not case.pv and not rederived:
            return None
        judged_on = "vehicle scenario" if has_perception(case.state, case.vehicle) else "monitor scenario"
        if case.pv and not rederived:
            validation = _Validation("dismissed", _unsupported(mscen, bool(derived)))
        else:
            validation = self._validate(case, judged_on, vscen, mscen, unknown, frozenset(f.sentence for f in derived),
                                        proofs or rule is None, summary, weighing[0])
            validation = self._raised_on(case, mscen, validation, weighing[0], summary)
            validation = _proved(validation, rule or validation.rule, weighing[1], summary)
        control = Control.from_json(control_at(entity(case.state, case.vehicle),
                                               weighing[2] if weighing[2] is not None else case.t))
        penalty, liability = self._sanctions(case, validation, control, vscen) if sanctioned else (None, None)
        return _Judged(pv_answer, rederived, judged_on, validation, control, rule or validation.rule, penalty, liability)

    def _derived(self, case: _Case, mscen: Scenario, vscen: Scenario) -> tuple[DerivedFact, ...]:
        """What the case's measurement shows beside what was stated (`_measured`'s `derived`),
        read from its own kept entry, kept beside the measurement: a third of it, and all a
        summary reads (reading and sealing the whole measurement for it cost a summary more
        than any other kept entry)."""
        found = self.memo(case.run).get("derived", _measurement_key(case, mscen))
        return self._measured(case, mscen, vscen).derived if found is None else found

    def _act(self, case: _Case, mscen: Scenario, vscen: Scenario) -> Any:
        """The case's act as its measurement delimits it (`_measured`'s `act`), read from its own
        kept entry beside the measurement, as `_derived` reads what a summary needs."""
        found = self.memo(case.run).get("act", _measurement_key(case, mscen))
        return self._measured(case, mscen, vscen).act if found is None else found[0]

    def _overruled(self, case: _Case, mscen: Scenario, vscen: Scenario) -> frozenset[str]:
        """The stated predictions the case's measurement overrules (Measurement.overruled), read
        from its own kept entry as `_derived` reads the derived facts."""
        found = self.memo(case.run).get("overruled", _measurement_key(case, mscen))
        return self._measured(case, mscen, vscen).overruled if found is None else frozenset(found)

    def _measured(self, case: _Case, mscen: Scenario, vscen: Scenario) -> Measurement:
        """What the vehicle's passage through the junction of the act shows at the act beside
        what the monitor stated (DESIGN "Reasoning": histories); kept for the next investigation
        of the same chain (reasoner/case_memo.py), since no rulebook changes it, with its
        `derived` apart (`_derived`)."""
        memo, key = self.memo(case.run), _measurement_key(case, mscen)

        def measured() -> Measurement:
            found = self._measure(case, mscen, vscen)
            memo.put("derived", key, found.derived)
            memo.put("act", key, [found.act])
            memo.put("overruled", key, tuple(sorted(found.overruled)))
            memo.put("weighing", key, _weighing_of(found, case.action))
            return found
        return memo.remember("measurement", key, measured)

    def _at_act(self, case: _Case, at: int | None) -> _Case:
        """The case with the vehicle's status as recorded at the act's moment (DESIGN "Weighing":
        the latest record before it; the spawn only a default): its spawn, latest entity.state and
        ADS status read at `at` where the record changed them between the act and the case's time
        (an ADS overridden, a call stood down, just after the act). Its perception and decision
        stay those at the case's time (DESIGN "Reasoning": the Vehicle Scenario at t)."""
        src = f"vehicle/{case.vehicle}"
        record = case.state.entities.get(src)
        if at is None or at == case.t or record is None:
            return case
        if at > case.t and not self._changed_before(case, record, at):
            return case
        if at < case.t and not _changed_after(record, at):
            return case
        then = self._state(case.run, at, case.vehicle, case.monitor).entities.get(src)
        if then is None:
            return case
        merged = {**record, **{kind: then.get(kind) for kind in ("spawn", "state", "ads", "despawned")}}
        return replace(case, state=replace(case.state, entities={**case.state.entities, src: merged}))

    def _changed_before(self, case: _Case, record: dict, at: int) -> bool:
        """Whether the vehicle's status may have changed between the case's time and its act, later
        (a camera that flagged the car on its way to the line): an ads.event or a spawn of it in
        between (its DSSAD record: a driver override just before it crossed), or, for a vehicle on
        or once on an emergency call, any state in between."""
        src = f"vehicle/{case.vehicle}"
        if self.store.source_events(case.run, src, kinds=["ads.event", "entity.spawn"], t_from=case.t + 1, t_to=at):
            return True
        spawn = ((record.get("spawn") or {}).get("body") or {}).get("emergency")
        state = (record.get("state") or {}).get("body") or {}
        return (spawn is True or state.get("emergency") is True) and bool(
            self.store.source_events(case.run, src, kinds=["entity.state"], t_from=case.t + 1, t_to=at))

    def _weighing(self, case: _Case, mscen: Scenario, vscen: Scenario) -> Weighing:
        """What the case's measurement contradicts and what its margins leave unproven
        (`_weighing_of`), read from its own kept entry beside the measurement, as `_derived`."""
        found = self.memo(case.run).get("weighing", _measurement_key(case, mscen))
        return _weighing_of(self._measured(case, mscen, vscen), case.action) if found is None else found

    def _measure(self, case: _Case, mscen: Scenario, vscen: Scenario) -> Measurement:
        stretch = stretches.stretch_at(self.store, case.run, case.vehicle, case.t, self.context(case.run).map) \
            if case.action == acts.SPEEDING else None
        return measure(self._passage(case), case.t, case.action, mscen.facts, mscen.sentences, vscen.facts, stretch)

    def _passage(self, case: _Case) -> Passage | None:
        return history.passage(self.store, case.run, case.vehicle, case.t, context=self.context(case.run))

    def _beliefs_contradicted(self, case: _Case, measured: Measurement, validation: _Validation,
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
            passage = acts.of(self._passage(case), case.t)
            found = checked(passage, measured.at, own)[1] if passage is not None and measured.at is not None else ()
        return found

    def _monitor_scenario(self, case: _Case) -> Scenario:
        if case.episode is not None:
            obs = case.episode.observation_at(case.t)
            if obs.get("kind") not in (None, "monitor.observation"):
                return self._stated_beside(case)
            scenario = Scenario()
            scenario.add(obs["body"].get("facts"), EventRef.of(obs))
            return scenario
        scenario = monitor_scenario(case.state, case.monitor, case.vehicle)
        if not scenario.facts and case.pv is not None and isinstance(case.pv["body"].get("facts"), list):
            scenario.add(case.pv["body"]["facts"], EventRef.of(case.pv))
        return scenario

    def _stated_beside(self, case: _Case) -> Scenario:
        """The Monitor Scenario of an act found in a road user's own measurements (an entity.state
        the sweep named): what the junction's monitor stated of the vehicle at the act, where it
        observed it within STATED_NEAR_S before (a camera that states the light but not the
        crossing); else nothing stated, and the measurements alone show the act."""
        scenario = monitor_scenario(case.state, case.monitor, case.vehicle)
        if scenario.facts and not all(case.t - ref.t <= STATED_NEAR_S * SECOND for _, ref in scenario.facts):
            return Scenario()
        return scenario

    def _rederived(self, case: _Case, mscen: Scenario, unknown: list[Finding]) -> tuple[Answer | None, Any]:
        """_rederive, as the judgement in force answered it where it asked the same monitor
        rulebook the same question on the same facts (a regression's new side, `_asked`)."""
        monitor, why_not = case.rs["monitor"], case.pv is not None
        if monitor is None:
            return None, None

        def asked(mine: list[Finding]) -> list | None:
            answer, _ = self._rederive(case.rs, mscen, case.me, case.act, mine, why_not=why_not)
            return None if answer is None else [answer.proofs, answer.why_not]
        kept = self._asked_noting(case, "rederived", [monitor.rulebook.sha256, why_not, case.me, case.act,
                                                      _as_asked(mscen.facts)], asked, unknown)
        if kept is None:
            return None, None
        answer = Answer(*kept)
        return answer, (monitor.rulebook.rule(answer.proofs[0]["rule"]) if answer.holds else None)

    def _asked(self, case: _Case, kind: str, question: list, compute: Callable[[], Any]) -> Any:
        """A stage's answer to a question (its rulebook's sha256 and everything it is asked on),
        computed, or read where the judgement in force of the same chain kept it: a regression's
        new side asks the stages whose rulebook it shares with the baseline nothing again. Only
        the judgement in force keeps them (what a new rulebook answers is worked out each time)."""
        memo, key = self.memo(case.run), key_of(kind, question)
        found = memo.get(kind, key, counted=False)
        if found is None and not self.proofs:
            found = self._answered.get((kind, key))     # asked by this investigation (before `proved`)
        if found is not None:
            return found
        found = compute()
        if self.keeps_verdicts(case.run, case.rs):
            memo.put(kind, key, found)
        elif not self.proofs:
            self._answered[(kind, key)] = found
        return found

    def _asked_noting(self, case: _Case, kind: str, question: list,
                      compute: Callable[[list[Finding]], Any], unknown: list[Finding]) -> Any:
        """`_asked` of a stage that notes findings as it answers: they are kept with the answer,
        and added to `unknown` whether the answer was computed or read."""
        def asked() -> list:
            mine: list[Finding] = []
            return [compute(mine), mine]
        answer, found = self._asked(case, kind, question, asked)
        unknown += found
        return answer

    def _rederive(self, rs: RuleSet, mscen: Scenario, me: Any, act: Any, unknown: list[Finding],
                  why_not: bool = True) -> tuple[Answer | None, Any]:
        """The monitor rulebook's answer with its proof; without `why_not`, None where it does not
        hold (a case nobody recorded that does not hold is no incident, and why it does not, the
        costliest question there is, is not asked)."""
        monitor = rs["monitor"]
        if monitor is None:
            return None, None
        rb = monitor.rulebook
        goal, atoms = POTENTIALLY_VIOLATES.atom(me, act), self.reader.atoms(rb, mscen.facts, unknown)
        if not why_not and not self.engine.holds(rb, goal, atoms):
            return None, None
        answer = self.engine.ask(rb, goal, atoms)
        rule = rb.rule(answer.proofs[0]["rule"]) if answer.holds else None
        return answer, rule

    def _validate(self, case: _Case, judged_on: str, vscen: Scenario, mscen: Scenario,
                  unknown: list[Finding], derived: frozenset[str] = frozenset(), proofs: bool = True,
                  summary: bool = False, contested: tuple[tuple[str, str, tuple[str, ...]], ...] = ()) -> _Validation:
        """The verdict on the Validator Scenario, with its proof (`proofs` False: asked plainly,
        the proof left empty and no rule found). `summary`: for an incident's summary alone, so
        neither why nor the perception fault finding (what the verdict would be on the vehicle's
        own perception) is worked out."""
        choice = case.rs["validator"]
        if choice is None:
            return _Validation("dismissed", "no rulebook defines punishable and mitigated violations")
        rb, me, act = choice.rulebook, case.me, case.act
        mine = self.reader.pairs(rb, vscen.facts, unknown)
        seen = self.reader.pairs(rb, mscen.facts, unknown)
        pv_atom = POTENTIALLY_VIOLATES.atom(me, act)
        facts, disputes = self._validator_facts(case, judged_on, rb, mine, seen, derived)
        verdict, answer = self._verdict(rb, me, act, [a for a, _ in facts] + [pv_atom], proofs=proofs)
        dispute = None
        if disputes and not summary:
            alt, _ = self._verdict(rb, me, act, [a for a, _ in mine] + [pv_atom], proofs=False)
            if alt != verdict:
                dispute = dispute_finding(disputes, rb, alt, verdict)
        why = "" if summary else _why(verdict, rb, me, act)
        turns = self._turns_on(rb, me, act, facts, pv_atom, verdict, contested)
        extra: list[Atom] = []
        set_aside: tuple[tuple[Any, EventRef], ...] = ()
        if turns is not None:
            sentence, words, alt, extra, kept = turns
            set_aside = tuple((self._render(rb, a), ev) for a, ev in facts if (a, ev) not in kept)
            facts = kept
            if alt == "dismissed":
                verdict, why = "dismissed", "" if summary else (
                    f"not proven: the verdict is {verdict} only on “{sentence}”, which the measurements contradict "
                    f"beyond their tolerance: {words}")
            else:
                verdict, answer = self._verdict(rb, me, act, [a for a, _ in facts] + extra + [pv_atom], proofs=proofs)
                why = "" if summary else (
                    f"{_why(verdict, rb, me, act)}, on what the measurements show: “{sentence}” was stated, "
                    f"but the measurements contradict it beyond their tolerance ({words}), so it decides nothing")
        rendered = tuple((self._render(rb, a), ev) for a, ev in facts)
        evidence = dict(rendered)
        proof = StageProof(rb.sha256, tuple(enrich(tree, rb, evidence) for tree in
                                            (answer.proofs[:1] or [answer.why_not] if answer else [])))
        rule = rb.rule(answer.proofs[0]["rule"]) if answer and answer.holds else None
        return _Validation(verdict, why, _choice(choice), rendered, proof, rule, dispute, set_aside)

    def _raised_on(self, case: _Case, mscen: Scenario, validation: _Validation,
                   contested: tuple[tuple[str, str, tuple[str, ...]], ...], summary: bool) -> _Validation:
        """Not proven where the potential violation itself rests on a claim the measurements
        contradict: the monitor rules no longer find it without the claim (a camera's "28 has
        speed of 38" where the car's own record has 30.0 mph; DESIGN "Weighing")."""
        monitor = case.rs["monitor"]
        said = {text: words for text, words, _ in contested}
        held = [text for text in mscen.sentences if isinstance(text, str) and text in said]
        if validation.verdict == "dismissed" or monitor is None or not held:
            return validation
        rb = monitor.rulebook
        measured = [(m, None) for text, _, shown in contested if text in held for m in shown]
        rest = [(text, ref) for text, ref in mscen.facts if text not in said] + measured
        if self.engine.holds(rb, POTENTIALLY_VIOLATES.atom(case.me, case.act), self.reader.atoms(rb, rest)):
            return validation
        why = "" if summary else (f"not proven: the potential violation rests on “{held[0]}”, and the measurements "
                                  f"contradict it beyond their tolerance: {said[held[0]]}")
        return replace(validation, verdict="dismissed", why=why)

    def _turns_on(self, rb: Rulebook, me: Any, act: Any, facts: list[tuple[Atom, EventRef]], pv_atom: Atom,
                  verdict: str, contested: tuple[tuple[str, str, tuple[str, ...]], ...]
                  ) -> tuple[str, str, str, list[Atom], list[tuple[Atom, EventRef]]] | None:
        """Where the verdict turns on a claim the measurements contradict beyond tolerance: the
        claim, what the measurements show, the verdict on them (asked with what they derive in the
        claims' place), the atoms they derive and the facts without the claims; None where no
        contested claim is in the scenario or the verdict is the same without it (DESIGN
        "Weighing": the verdict rests on what is proved, whichever side a claim helps)."""
        if verdict == "dismissed" or not contested:
            return None
        atoms = {a: text for text, _, _ in contested for a, _ in self.reader.pairs(rb, [(text, None)], [])}
        held = [a for a, _ in facts if a in atoms]
        if not held:
            return None
        texts = {atoms[a] for a in held}
        kept = [(a, ev) for a, ev in facts if a not in atoms]
        have = {a for a, _ in kept}
        measured = [a for a in self.reader.atoms(rb, [(m, None) for text, _, shown in contested if text in texts
                                                      for m in shown]) if a not in have]
        alt, _ = self._verdict(rb, me, act, [a for a, _ in kept] + measured + [pv_atom], proofs=False)
        if alt == verdict:
            return None
        text = atoms[held[0]]
        return text, next(words for said, words, _ in contested if said == text), alt, measured, kept

    def _render(self, rb: Rulebook, atom: Atom) -> str:
        """rb.render(atom), once per rulebook and atom in this investigation: a regression's
        new side renders the validator facts of every case, and half of them some earlier
        case rendered already (a vehicle's type, its light). Only an atom of text and whole
        numbers is remembered: one equal to it renders alike (1.0 and True equal 1, and do not)."""
        if not all(type(arg) is str or type(arg) is int for arg in atom.args):
            return rb.render(atom)
        key = (rb.sha256, atom)
        found = self._rendered.get(key)
        if found is None:
            if len(self._rendered) >= _RENDERED_LIMIT:
                self._rendered.clear()
            found = self._rendered[key] = rb.render(atom)
        return found

    def _validator_facts(self, case: _Case, judged_on: str, rb: Rulebook, mine: list, seen: list,
                         derived: frozenset[str]) -> tuple[list[tuple[Atom, EventRef]], list[dict]]:
        """The Validator Scenario: the vehicle's view corrected by what the monitor witnessed and
        the history measured; or, for a vehicle that recorded no perception, its spawn and what
        the monitor saw and the history measured. What the history measured is no belief of the
        vehicle's: it is added whatever the monitor rules look at, and the vehicle's silence on
        it is no perception fault."""
        if judged_on == "vehicle scenario":
            monitor_rb = case.rs["monitor"].rulebook if case.rs["monitor"] else rb
            out, disputes = corrected(mine, seen, self._witnessed_by(monitor_rb), case.me,
                                      self._others(case, [*mine, *seen]))
            measured = {a for a, _ in self.reader.pairs(rb, [(s, None) for s in derived], [])}
            have = {a for a, _ in out}
            out += [(a, ev) for a, ev in seen if a in measured and a not in have]
            return out, [d for d in disputes if d["vehicle"] or any(a not in measured for a, _ in d["monitor"])]
        record = entity(case.state, case.vehicle) or {}
        spawn = record.get("spawn")
        own = [(a, EventRef.of(spawn, case.state.run, "entity.spawn"))
               for a in self.reader.known(rb, status_facts(case.vehicle, record))] if spawn else []
        return own + seen, []

    def _decision_fault(self, case: _Case, action: Decision | None, vscen: Scenario,
                        unknown: list[Finding]) -> Finding | None:
        choice = case.rs.vehicle_rulebook(action.rulebook if action else None)
        own = action if action and action.action == case.action else None
        if choice is None or own is None:
            return decision_fault(self.engine, self.reader, choice, case.vehicle, own, vscen.facts, unknown)

        return self._asked_noting(case, "fault", [choice.rulebook.sha256, case.vehicle, own.to_json(),
                                                  _as_asked(vscen.facts)],
                                  lambda mine: decision_fault(self.engine, self.reader, choice, case.vehicle, own,
                                                              vscen.facts, mine), unknown)

    def _others(self, case: _Case, pairs: list[tuple[Atom, EventRef]]) -> set:
        """The constants of these facts that name another road user on record by the act's time
        (a source with an entity event by then, named by the part of its src after the "/"):
        a fact about one of them is not the vehicle's own."""
        named = self._named(case.run)
        out = set()
        for atom, _ in pairs:
            for arg in atom.args:
                if isinstance(arg, (str, int)) and arg != case.me and arg in named and arg not in out \
                        and self._first_since(case.run, arg) <= case.t:
                    out.add(arg)
        return out

    def _first_since(self, run: str, name: Any) -> float:
        """When the first of the sources a constant names became an entity of the run (inf:
        none did), once per run and constant: a case asks it of every constant of its facts."""
        key = (run, name)
        found = self._firsts.get(key)
        if found is None:
            found = self._firsts[key] = min(self._since(run, src) for src in self._named(run)[name])
        return found

    def _named(self, run: str) -> dict[Any, list[str]]:
        """The run's sources by the constant their id reads as, read once per run (and kept: a
        long run's thousands of sources are an index probe each)."""
        if run not in self._names:
            names: dict[Any, list[str]] = {}
            for src in self.memo(run).remember("sources", key_of("sources"), lambda: self.store.sources(run),
                                               plain=True):
                if "/" in src:
                    names.setdefault(constant([src.split("/", 1)[1]]), []).append(src)
            self._names[run] = names
        return self._names[run]

    def _since(self, run: str, src: str) -> float:
        """When the source became an entity of the run's state (inf: never)."""
        key = (run, src)
        if key not in self._entity_since:
            since = self.memo(run).remember("since", key_of("since", src),      # [None]: never an entity
                                            lambda: [entity_since(self.store, run, src)], plain=True)[0]
            self._entity_since[key] = float("inf") if since is None else since
        return self._entity_since[key]

    def _witnessed_by(self, monitor_rb: Rulebook) -> set[str]:
        if monitor_rb.sha256 not in self._witnessed:
            self._witnessed[monitor_rb.sha256] = witnessed_functors(monitor_rb)
        return self._witnessed[monitor_rb.sha256]

    def _verdict(self, rb: Rulebook, me: Any, act: Any, atoms: list[Atom], proofs: bool) -> tuple[str, Answer | None]:
        # punishable, else mitigated, else dismissed (with why it is not punishable); each asked
        # plainly first: a proof, or why not, is searched for only where it is shown
        goals = (PUNISHABLY_VIOLATES.atom(me, act), MITIGATELY_VIOLATES.atom(me, act))
        if not proofs:
            first = self.engine.first_holding(rb, goals, atoms)
            return (_VERDICTS[first] if first >= 0 else "dismissed"), None
        first, answer = self.engine.ask_first(rb, goals, atoms)
        return (_VERDICTS[first] if first >= 0 else "dismissed"), answer

    # -- penalty and liability, for a punishable violation ----------------------------------
    def _sanctions(self, case: _Case, validation: _Validation, control: Control,
                   vscen: Scenario) -> tuple[Penalty | None, Liability | None]:
        if validation.verdict != "punishable":
            return None, None
        punish = PUNISHABLY_VIOLATES.atom(case.me, case.act)
        penalty = None
        # Each asked on the sentences, named by them (the rulebook reads them alike every time):
        # a kept answer is found without parsing them or writing out the atoms.
        if (pen := case.rs["penalties"]) is not None:
            sentences = [s for s, _ in validation.scenario]
            penalty = self._asked(case, "penalty", [pen.rulebook.sha256, case.me, case.act, sentences],
                                  lambda: [self._penalty(pen.rulebook, case.me,
                                                         self.reader.known(pen.rulebook, sentences) + [punish])])[0]
        liability = None
        if (lia := case.rs["liability"]) is not None:
            shown = [(s, _control_ref(case.run, control, vscen, basis)) for s, basis in
                     liability_facts(case.vehicle, control.to_json())]
            evidence = {s: r for s, r in shown if r}
            liability = self._asked(case, "liability", [lia.rulebook.sha256, case.me, case.act,
                                                        [s for s, _ in shown], _as_asked(evidence.items())],
                                    lambda: self._liability(lia.rulebook, case.me, case.act,
                                                            self.reader.known(lia.rulebook, [s for s, _ in shown])
                                                            + [punish], evidence))
        if penalty is not None and liability is not None:
            offered = liability.fixed_penalty is None or bool(liability.fixed_penalty)
            penalty = replace(penalty, points_by_law=penalty.points, fine_gbp_by_law=penalty.fine_gbp,
                              fine_gbp=penalty.fine_gbp if offered else None,
                              points=penalty.points if liability.licence_points else 0,
                              regulatory_sanctions=liability.sanctions)
        return penalty, liability

    def _penalty(self, rb: Rulebook, me: Any, facts: list[Atom]) -> Penalty | None:
        question = [Cond(atom=INCURS_FIXED_PENALTY.atom(me, Var("amount"), Var("points"), Var("offence")))]
        found = []
        for binding in self.engine.answers(rb, question, facts, texts=False).bindings:
            _, _, amount, points, offence = binding[0]
            law = self.engine.answers(rb, [Cond(atom=IS_AN_OFFENCE_UNDER.atom(offence, Var("law")))], facts,
                                      texts=False)
            found.append(Penalty(arg_text(offence), arg_text(law.bindings[0][0][2]) if law.bindings else None,
                                 amount, points))
        found = list(dict.fromkeys(found))     # one answer per proof: a fact stated twice proves it twice
        if not found:
            return None
        found.sort(key=lambda p: (-_num(p.fine_gbp), -_num(p.points), p.offence))
        return replace(found[0], offences=tuple(found)) if len(found) > 1 else found[0]

    def _liability(self, rb: Rulebook, me: Any, act: Any, facts: list[Atom],
                   evidence: dict[str, EventRef]) -> Liability:
        asked = [IS_LIABLE, GETS_LICENCE_POINTS, FACES_REGULATORY_SANCTIONS]
        if defines(rb, IS_OFFERED_A_FIXED_PENALTY.functor):
            asked.append(IS_OFFERED_A_FIXED_PENALTY)
        results = self.engine.answers_all(rb, [([Cond(atom=sentence.atom(Var("party"), act, me))], i == 0)
                                               for i, sentence in enumerate(asked)], facts)
        liable, points, sanctions, *offered = [tuple(role(arg_text(b[0][1])) for b in r.bindings) for r in results]
        return Liability(parties=liable, licence_points=points, sanctions=sanctions,
                         fixed_penalty=offered[0] if offered else None,
                         facts=tuple(rb.render(a) for a in facts), rulebook=rb.sha256,
                         evidence=evidence,
                         trees=tuple(enrich(tree, rb, evidence) for trees in results[0].proofs[:1] for tree in trees))


def action_text(rb: Rulebook, me: Any, act: Any) -> str:
    """"173 can enter the junction", in the rulebook's words where it has the template."""
    return rb.render(CAN.atom(me, act)) if CAN.functor in rb.document.templates else f"{me} can {act}"


def _why(verdict: str, rb: Rulebook, me: Any, act: Any) -> str:
    return {
        "punishable": f"\"{action_text(rb, me, act)}\" is not among the lawful actions of the Validator Scenario",
        "mitigated": f"\"{action_text(rb, me, act)}\" is among the lawful actions of the Validator Scenario",
        "dismissed": "the validator rules establish neither a punishable nor a mitigated violation",
    }[verdict]


def _unsupported(mscen: Scenario, measured: bool) -> str:
    """Why a recorded potential violation the monitor rules do not re-derive is dismissed."""
    if measured:
        return ("the monitor's own observation, with what the measurements show at the act (see the facts marked "
                "measured), does not show the potential violation it recorded")
    return ("the monitor's own observation does not show the potential violation it recorded" if mscen.facts
            else "no observation of the vehicle by the monitor supports the potential violation it recorded")


def _driving_contradicted(vehicle: str, vscen: Scenario, control: Control) -> Finding | None:
    """A contradiction finding where the vehicle states it is driving itself while its ads.event
    record, as it stood at the act, has the feature not engaged (DESIGN "Weighing": status at the
    act is the latest record before it; who drove follows that record, control.py)."""
    said = IS_DRIVING_ITSELF.text(vehicle)
    ref = next((ref for text, ref in vscen.facts if text == said and ref is not None), None)
    last = control.last_ads_event
    if ref is None or control.engaged or not last:
        return None
    event = EventRef(ref.run, last["src"], last["seq"], last["t"], "ads.event")
    return Finding("contradiction", f"\"{said}\" was stated ({ref.src} #{ref.seq}), but its ads.event record has the "
                   f"feature not engaged at the act (last: {last.get('event')}, {last['src']} #{last['seq']})",
                   (ref, event), fact=said)


def _dssad_contradicted(case: _Case, mscen: Scenario, control: Control) -> tuple[Finding, ...]:
    """Contradictions between the DSSAD record (ads.event, UN R157 8.2.1) as it stood at the act
    and the other records of who drove: a monitor stating "V is driving itself" while the feature
    was not engaged, and a spawn that says the vehicle has no automated driving system (a human
    driver, SAE level under 3) while its DSSAD has the feature engaged. Who drove follows the
    DSSAD (control.py); the other record is a finding, never silently overruled."""
    out = []
    said = IS_DRIVING_ITSELF.text(case.vehicle)
    last = control.last_ads_event
    ads_ref = EventRef(case.run, last["src"], last["seq"], last["t"], "ads.event") if last else None
    ref = next((ref for text, ref in mscen.facts if text == said and ref is not None
                and ref.kind == "monitor.observation"), None)
    if ref is not None and not control.engaged:
        where = (f"its ads.event record has the feature not engaged at the act (last: {last.get('event')}, "
                 f"{last['src']} #{last['seq']})" if last else "its record has no ads.event: no feature was engaged")
        out.append(Finding("contradiction", f"\"{said}\" was stated by {ref.src} (#{ref.seq}), but {where}",
                           (ref,) + ((ads_ref,) if ads_ref else ()), fact=said))
    spawn = (entity(case.state, case.vehicle) or {}).get("spawn") or {}
    body = spawn.get("body") or {}
    level = body.get("automation_level")
    denies = body.get("driver") == "human" and (level is None or (type(level) is int and level < 3))
    if control.engaged and denies and ads_ref is not None and spawn.get("src"):
        spawned = EventRef(case.run, spawn["src"], spawn["seq"], spawn["t"], "entity.spawn")
        out.append(Finding("contradiction", f"its entity.spawn ({spawned.src} #{spawned.seq}) says a human drives it "
                           f"with no automated driving system (automation level {level if level is not None else 'not stated'}), "
                           f"but its ads.event record has the feature engaged at the act ({last.get('event')}, "
                           f"{last['src']} #{last['seq']}): who drove is read from the DSSAD record",
                           (spawned, ads_ref), fact=said))
    return tuple(out)


Weighing = tuple[tuple[tuple[str, str, tuple[str, ...]], ...], tuple[tuple[str | None, str], ...], int | None]


def _weighing_of(measured: Measurement, action: str) -> Weighing:
    """The claims the measurement contradicts (sentence, what it shows, what it derives), by rule
    why a margin proves nothing (reasoner/margins.py `unproven`), and the act's moment: for a
    junction act, when the vehicle crossed its line (else entered the junction) by the moment it
    was judged at, the act itself; a speeding or box act is judged when recorded."""
    if not measured.present:
        return (), (), None
    return measured.contested, measured.unproven(), _act_moment(measured, action)


def _act_moment(measured: Measurement, action: str) -> int | None:
    at = measured.at
    if at is None or action in (acts.SPEEDING, acts.BOX):
        return at
    for what in ("crossed the stop line", "entered the junction"):
        found = [t for said, t in measured.moments if said == what and t <= at]
        if found:
            return found[-1]
    return at


def _changed_after(record: dict, at: int) -> bool:
    """Whether the vehicle's status may have changed between the act and the record's time: an
    ads.event after it, or, for a vehicle that is or was on an emergency call, a state after it."""
    ads = (record.get("ads") or {}).get("last")
    if ads and ads.get("t", 0) > at:
        return True
    spawn = ((record.get("spawn") or {}).get("body") or {}).get("emergency")
    state = record.get("state") or {}
    return (spawn is True or (state.get("body") or {}).get("emergency") is True) and state.get("t", 0) > at


def _proved(validation: _Validation, rule: Any, unproven: tuple[tuple[str | None, str], ...],
            summary: bool) -> _Validation:
    """A conviction needs the act's margin beyond its uncertainty (DESIGN "Margins"): a
    punishable verdict whose rule's margin does not exceed it is not proven, and dismissed so."""
    if validation.verdict != "punishable" or not unproven:
        return validation
    key = rule_key(rule.label if rule is not None else None)
    why = next((w for r, w in unproven if r == key), None)
    if why is None:
        return validation
    return replace(validation, verdict="dismissed", why="" if summary else f"not proven: {why}")


def _liable(liability: Liability | None) -> str:
    if liability is None:
        return "none"
    return next((r for r in LIABLE_ORDER if r in liability.parties),
                liability.parties[0] if liability.parties else "none")


def _control_ref(run: str, control: Control, vscen: Scenario, basis: str) -> EventRef | None:
    """The event behind a liability fact: the spawn, or an ads.event of the control status."""
    if basis == "spawn":
        return next((ev for _, ev in vscen.facts if ev.kind == "entity.spawn"), None)
    piece = getattr(control, basis)
    return EventRef.of(piece, run, "ads.event") if piece else None


def _choice(choice: Choice) -> RulebookChoice:
    return RulebookChoice(**choice.describe())


def _choices(rs: RuleSet) -> dict[str, RulebookChoice]:
    return {stage: RulebookChoice(**b) for stage, b in rs.describe().items()}


def _present(finding: Finding | None) -> tuple[Finding, ...]:
    return (finding,) if finding is not None else ()


def _dedup_unknown(unknown: list[Finding], derived: set[str]) -> list[Finding]:
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


def _disagreement(case: _Case, mscen: Scenario, rederived: bool, measured: bool) -> Finding | None:
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
    event = case.pv if case.pv else case.episode.first
    return Finding("monitor disagreement", detail,
                   (EventRef.of(event), *(ev for _, ev in mscen.facts[:1])))


def _proofs(answer: Answer | None, choice: Choice | None, scenario: Scenario, trees: bool = True) -> StageProof:
    """The monitor stage's proof (`trees` False: its rulebook alone, the trees left out)."""
    if answer is None or choice is None:
        return StageProof(None, ())
    rb = choice.rulebook
    if not trees:
        return StageProof(rb.sha256, ())
    trees = answer.proofs[:1] or ([answer.why_not] if answer.why_not else [])
    return StageProof(rb.sha256, tuple(enrich(tree, rb, scenario.evidence) for tree in trees))


def _last_seen(state: State, vehicle: str) -> int | None:
    record = entity(state, vehicle) or {}
    times = [record[k]["t"] for k in ("state", "perception", "decision") if record.get(k)]
    return max(times) if times and not record.get("despawned") else None


def _well_formed(event: Any) -> bool:
    return type(event) is dict and type(event.get("body")) is dict and type(event.get("t")) is int \
        and type(event.get("src")) is str and type(event.get("seq")) is int


def _fed(events: Iterable[dict], sweeper: Sweep) -> Iterable[dict]:
    """The events, each shown to the sweeper on its way through."""
    for event in events:
        sweeper.add(event)
        yield event


def _stated_by(scenario: Scenario) -> list:
    """The events a scenario's facts came from: they and the case's time, vehicle and monitor
    (which give the state, hence the vehicle's own facts) name everything a measurement reads."""
    return list(dict.fromkeys((ref.src, ref.seq) for _, ref in scenario.facts if ref is not None))


def _case_kept(item: tuple) -> list:
    """A case to judge as plain data: the recorded potential violation by its (src, seq), the
    episode by the two observations a judgement reads of it (its first, and the one at t)."""
    t, src, pv, ep = item
    if ep is None:
        return [t, src, [pv["src"], pv["seq"]], None]
    first, at = ep.first, ep.observation_at(t)
    return [t, src, [pv["src"], pv["seq"]] if pv else None,
            [ep.monitor, ep.vehicle, ep.action, [first] if at is first else [first, at]]]


def _case_unkept(item: list, recorded: dict[tuple[str, int], dict]) -> tuple | None:
    """The case `_case_kept` gave (None: its potential violation is not among those read)."""
    t, src, ref, ep = item
    pv = recorded.get((ref[0], ref[1])) if ref else None
    if ref and pv is None:
        return None
    return (t, src, pv, Episode(ep[0], ep[1], ep[2], ep[3]) if ep else None)


def _as_asked(facts: Iterable[tuple[Any, EventRef | None]]) -> list[tuple]:
    """Facts as a stage question names them (case_memo.key_of): each with its event reference's
    fields, or None, in one tuple (a reference's own repr, a Python call each, was half of a
    question's key)."""
    return [(text, None) if ref is None else (text, ref.run, ref.src, ref.seq, ref.t, ref.kind) for text, ref in facts]


def _incident_id(case: _Case) -> str:
    return f"{case.anchor['src']}:{case.anchor['seq']}"


def _beliefs_overruled(measured: Measurement) -> tuple[Contradiction, ...]:
    """The vehicle's own predictions the measurements overruled (left out of the Validator
    Scenario, so `_beliefs_contradicted` no longer sees them): each is a finding, once."""
    over = measured.overruled
    found = {(c.stated, c.stated_by.key): c for *_, cs in measured.beliefs for c in cs if c.stated in over}
    return tuple(found.values())


def _unmeasured_claims(measured: Measurement, validation: _Validation) -> tuple[Finding, ...]:
    """The stated predictions the verdict was taken on with nothing of the road user measured:
    the sentence stands alone, and the explanation says so."""
    used = {text for text, _ in validation.scenario}
    return tuple(Finding("unmeasured claim", f"\"{text}\" was stated ({ref.src} #{ref.seq}) and nothing of {user} "
                         "about the act is in the record: it stands on the statement alone", (ref,), fact=text)
                 for text, ref, user in measured.unmeasured if text in used)


def _measurement_key(case: _Case, mscen: Scenario) -> str:
    """What names a case's measurement: its act and the events its Monitor Scenario's facts
    came from (before what the measurement shows is added to it)."""
    return key_of(case.t, case.vehicle, case.monitor, case.action, _stated_by(mscen))


def _names_of(unraised: list | None) -> frozenset | None:
    """The kept unraised cases' names as _todo's loop makes them (None: not kept)."""
    return None if unraised is None else frozenset(tuple(name) for name in unraised)


def _named(incident: Incident) -> tuple:
    """What tells an incident from the run's others (two acts of one observation share its id)."""
    return (incident.run, incident.id, incident.vehicle, incident.action, incident.t)


def _anchor_key(pv: dict | None, episode: Episode | None) -> str:
    anchor = pv if pv else episode.first
    return f"{anchor['src']}:{anchor['seq']:020d}"


def _num(value: Any) -> float:
    return value if isinstance(value, (int, float)) else 0


def _signals(measured: Measurement) -> list[str]:
    """The signals whose reports the passage read: their lost events are missing evidence too."""
    return list(measured.signals)


def _evidence(case: _Case, mscen: Scenario, vscen: Scenario, decision: Decision | None, control: Control,
              findings: Iterable[Finding], measured: Measurement) -> tuple[EventRef, ...]:
    """Every event the incident rests on, once each, the anchor first."""
    refs = [EventRef.of(case.anchor)] + [ev for _, ev in (*mscen.facts, *vscen.facts)]
    refs += [ev for f in measured.derived for ev in f.evidence]
    if decision:
        refs.append(decision.evidence)
    if control.last_ads_event:
        refs.append(EventRef.of(control.last_ads_event, case.run, "ads.event"))
    for f in findings:
        refs += f.evidence
    return oneact.once(refs)



def _sources(case: _Case, mscen: Scenario) -> tuple[Source, ...]:
    """The records the case's act was raised from: its anchor (the recorded potential violation,
    the monitor's observation it was raised from, or the road user's own measurement the sweep
    named) and, where another source's statements are its Monitor Scenario (a camera's light
    beside the vehicle's own positions), that source too."""
    anchor = case.anchor
    kind = anchor.get("kind") or ("monitor.potential_violation" if case.pv else "monitor.observation")
    how = "recorded" if case.pv else ("observed" if kind == "monitor.observation" else "measured")
    out = [Source(_incident_id(case), anchor["src"], kind, how)]
    for _, ref in mscen.facts:      # (the measured facts added to it cite entity.state, signals, the map)
        if ref is not None and ref.kind == "monitor.observation" and ref.src not in {s.src for s in out}:
            out.append(Source(f"{ref.src}:{ref.seq}", ref.src, ref.kind, "stated"))
    return tuple(out)


def _merged(group: list) -> Any:
    """One incident for the records of one act (reasoner/oneact.py): whole incidents merged now;
    incidents read by their summaries merged by their summaries, and whole when asked for."""
    if all(isinstance(i, Incident) for i in group):
        return oneact.merge(group)
    rep, first = oneact.representative(group), oneact.named(group)
    summary = {name: getattr(rep, name) for name in _SUMMARY}
    summary.update(id=first.id, t=first.t, sources=oneact.sources_of([first, *(i for i in group if i is not first)]))
    return KeptIncident([summary[name] for name in _SUMMARY],
                        lambda: oneact.merge([i.whole() if isinstance(i, KeptIncident) else i for i in group]),
                        lambda: rep.proofs)
