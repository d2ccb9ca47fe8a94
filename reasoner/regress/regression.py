"""Regression of a new rulebook over logged runs: which verdicts and decisions it changes, and why.

    with Store.open_read_only("gaps.db") as store:
        result = regress(store, rules=["new/validators.le"], runs=["demo-sumo"])
        for case, change in result.changes:
            print(case.id, change.kind, change.before, "->", change.after, change.reasons)

Each chosen run is judged twice by the investigation (investigation.py), once with the baseline
(the rulebooks in force: the run's own, else the project's current ones; or the OLD files given)
and once with the new rulebooks in front of it (a stage they define is answered by them, the
others as in the baseline). The incidents are matched (regress_match.py) and compared: a verdict
flipped, an incident new or gone, the rule it falls under, and, where the verdict stayed, the
penalty or who is liable. Every recorded vehicle.decision is asked again under both vehicle-stage
rulebooks (regress_decisions.py). Each change carries the changed rules its two proofs went
through (regress_reasons.py), from the rule-by-rule diff of the two rulebooks of each stage
(regress_diff.py), which is also the rule change report.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable, Sequence

from store import NoSuchRun, Store

from ..collector import JudgementCollector
from ..engine import Engine, Rulebook, get_engine
from ..facts import FactReader
from ..investigation import Investigation, Judgement, SharedReading, Speedups, whole
from ..le.sentences import constant
from ..le.terms import Cond, Var
from ..model import Incident
from .books import GivenBooks, RegressError, load_given
from .decisions import (Asked, KeptDecision, RecordedDecision, Shapes, ask, keep_decisions,
                                kept_decisions, recorded_decisions, vehicle_choice)
from .diff import RuleChange, RulebookDiff, diff_rulebooks
from .match import match
from .reasons import Trees, attribute, reasons, used_rules
from ..stages import Choice, RuleSet
from ..vocabulary import INCURS_FIXED_PENALTY, PUNISHABLY_VIOLATES, STAGES
from ..verdicts import Verdict

Progress = Callable[[str, int, int], None]          # (run, done, total runs)
IN_FORCE = "in-force"
# The stages whose rules can explain each kind of change (the others' rules are not in its proofs).
EXPLAINED_BY = {"new": ("monitor", "validator"), "gone": ("monitor", "validator"),
                "verdict": ("monitor", "validator"), "rule": ("monitor", "validator"),
                "penalty": ("penalties",), "liability": ("liability",), "decision": ("vehicle",)}
Diffs = dict[str, RulebookDiff]                      # stage -> the diff of its two rulebooks
Kept = tuple[str | None, bool | None]                # a decision's kept baseline: its rulebook's sha256, its answer
Row = tuple[RecordedDecision, Choice | None, Choice | None, Kept | None]   # a decision, each side's choice, its Kept
ANSWERS: dict[bool | None, str] = {True: "permitted", False: "forbidden"}  # a decision's answer (else "not answerable")


@dataclass(frozen=True)
class Change:
    """One thing that differs between the two judgements of a case, and why."""

    kind: str                            # new, gone, verdict, rule, penalty, liability, decision
    before: str | None
    after: str | None
    reasons: tuple[str, ...]
    rules: tuple[RuleChange, ...] = ()   # the changed rules it is attributed to

    def to_json(self) -> dict[str, Any]:
        return {"kind": self.kind, "before": self.before, "after": self.after, "reasons": list(self.reasons),
                "rules": [r.key for r in self.rules]}


@dataclass(frozen=True)
class CaseResult:
    """One incident or recorded decision, judged under both rulebooks."""

    run: str
    case: str                            # "incident" or "decision"
    id: str                              # the incident's id (the baseline's where both) or the decision's src:seq
    vehicle: str
    action: str
    t: int
    before: str | None                   # the judgement in a line; None: the incident is not there
    after: str | None
    changes: tuple[Change, ...] = ()

    @property
    def changed(self) -> bool:
        return bool(self.changes)

    def to_json(self) -> dict[str, Any]:
        return {"case": self.case, "id": self.id, "run": self.run, "vehicle": self.vehicle, "action": self.action,
                "t": self.t, "before": self.before, "after": self.after,
                "changes": [c.to_json() for c in self.changes]}


@dataclass(frozen=True)
class RunResult:
    """A run's incidents and decisions under both judgements, and the rulebooks each stage used."""

    run: str
    incidents: tuple[CaseResult, ...]
    decisions: tuple[CaseResult, ...]
    baseline: dict[str, dict]            # stage -> {name, sha256, source}
    new: dict[str, dict]
    problems: tuple[str, ...] = ()
    seconds: dict[str, float] = field(default_factory=dict, compare=False)
    """Wall time judging its incidents and its decisions ({"incidents": s, "decisions": s}), for
    JUnit's `time`; not a result, so no part of equality or of the JSON."""

    def changed(self) -> list[CaseResult]:
        return [c for c in (*self.incidents, *self.decisions) if c.changed]

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "rulebooks": {"baseline": self.baseline, "new": self.new},
                "incidents": [c.to_json() for c in self.incidents],
                "decisions": {"checked": len(self.decisions),
                              "changed": [c.to_json() for c in self.decisions if c.changed]},
                **({"problems": list(self.problems)} if self.problems else {})}


@dataclass(frozen=True)
class Regression:
    """Everything `gaps regress` reports."""

    rules: tuple[str, ...]
    baseline: tuple[str, ...] | str      # IN_FORCE, or the OLD files
    runs: tuple[RunResult, ...]
    diffs: tuple[RulebookDiff, ...]
    unused: tuple[str, ...] = ()

    @property
    def changes(self) -> list[tuple[CaseResult, Change]]:
        return [(case, change) for run in self.runs for case in run.changed() for change in case.changes]

    @property
    def changed(self) -> bool:
        return any(run.changed() for run in self.runs)

    def flipped_by(self, rule: RuleChange) -> list[tuple[CaseResult, Change]]:
        """The changes attributed to one changed rule (the rule change report's right column)."""
        return [(case, change) for case, change in self.changes if rule in change.rules]

    def counts(self) -> dict[str, int]:
        out: dict[str, int] = {"runs": len(self.runs), "incidents": sum(len(r.incidents) for r in self.runs),
                               "decisions": sum(len(r.decisions) for r in self.runs)}
        for _, change in self.changes:
            out[change.kind] = out.get(change.kind, 0) + 1
        return out

    def to_json(self) -> dict[str, Any]:
        return {"changed": self.changed, "rules": list(self.rules),
                "baseline": self.baseline if isinstance(self.baseline, str) else list(self.baseline),
                "unused": list(self.unused), "counts": self.counts(),
                "rule_changes": [{**d.to_json(), "changes": [
                    {**c.to_json(), "flipped": [f"{case.run} {case.id} {ch.kind}" for case, ch in self.flipped_by(c)]}
                    for c in d.changes]} for d in self.diffs],
                "runs": [r.to_json() for r in self.runs]}


@dataclass(frozen=True)
class RunPart:
    """One run's result and the rulebook diffs it went through (with the stages it used them
    for): plain data, what a cluster's worker sends back (regress_cluster.py)."""

    result: RunResult
    diffs: tuple[RulebookDiff, ...]


def regress(store: Store, rules: Sequence[str], baseline: Sequence[str] | None = None,
            runs: Sequence[str] | None = None, *, engine: Engine | None = None,
            progress: Progress | None = None) -> Regression:
    """Judge the runs (None: every run) under the baseline and under `rules`, and compare."""
    engine = engine or get_engine()
    new = load_given(engine, rules, "--rules")
    old = load_given(engine, baseline, "--baseline") if baseline else None
    chosen = chosen_runs(store, runs)
    regressor = Regressor(store, engine, new, old)
    parts = []
    for n, run in enumerate(chosen):
        parts.append(regressor.part(run))
        if progress is not None:
            progress(run, n + 1, len(chosen))
    return assemble(new, old, parts)


def assemble(new: GivenBooks, old: GivenBooks | None, parts: Iterable[RunPart]) -> Regression:
    """The regression of runs judged apart (in one process or on a cluster), in the order given:
    each diff listed where a run first went through it, with every stage any run used it for,
    as one Regressor judging them one after another lists them."""
    stages: dict[tuple[str, str], set[str]] = {}
    diffs: dict[tuple[str, str], RulebookDiff] = {}
    results = []
    for part in parts:
        results.append(part.result)
        for d in part.diffs:
            key = (d.old_sha256, d.new_sha256)
            diffs.setdefault(key, d)
            stages.setdefault(key, set()).update(d.stages)
    merged = tuple(_with_stages(d, stages[key]) for key, d in diffs.items())
    return Regression(new.paths, old.paths if old else IN_FORCE, tuple(results), merged, new.unused)


def _with_stages(d: RulebookDiff, stages: Iterable[str]) -> RulebookDiff:
    return RulebookDiff(tuple(sorted(stages)), d.old_name, d.old_sha256, d.new_name, d.new_sha256, d.changes)


def chosen_runs(store: Store, runs: Sequence[str] | None) -> list[str]:
    """The runs asked for (each must be in the store, NoSuchRun), else every run. By name alone:
    a run's summary counts its events (on the hour, a scan of 11 million index entries)."""
    known = store.run_names()
    if runs is None:
        if not known:
            raise RegressError("the store holds no run to regress")
        return known
    for run in runs:
        if run not in known:
            raise NoSuchRun(run, known)
    return list(dict.fromkeys(runs))


class Regressor:
    """Two investigations of one store, the baseline's and the new rulebooks', and the diffs of
    the rulebooks they used, computed once per pair."""

    def __init__(self, store: Store, engine: Engine, new: GivenBooks, old: GivenBooks | None, *,
                 kept: bool = True) -> None:
        """`kept` False: nothing read from or written to the cache (every case measured and
        judged with its proofs, every decision asked, none answered by its shape): the plain
        path the kept one must agree with."""
        self.engine = engine
        self.store = store
        self.reader = FactReader()
        self.shapes = Shapes() if kept else None
        base = list(old.texts) if old else []       # texts the engine has loaded, under their paths
        shared = SharedReading() if kept else None     # the runs' cases, read by both sides alike
        # the baseline reads its kept incidents by their summaries; the new side judges each case only as far
        # as its summary goes, its proofs worked out for the changed incidents only (reasoner/speedups/)
        self.before = Investigation(store, engine, rules=base, shared=shared,
                                    speedups=Speedups.BASELINE if kept else Speedups.NONE)
        self.after = Investigation(store, engine, rules=[*new.texts, *base], reader=self.reader, shared=shared,
                                   speedups=Speedups.NEW_SIDE if kept else Speedups.NONE)
        self._diffs: dict[tuple[str, str], RulebookDiff] = {}
        given = [(rb, path) for side in (new, old) if side for rb, path in zip(side.books, side.paths)
                 if path not in side.unused]
        self._names = {rb.sha256: path for rb, path in reversed(given)}     # the first path of each text
        self._touched: dict[tuple[str, str], set[str]] = {}   # the diffs the run being judged used

    def part(self, run: str) -> RunPart:
        """The run judged, with the diffs (and stages) it used."""
        self._touched = {}
        with JudgementCollector():      # one collection for both sides and the decisions, not one each
            result = self.run(run)
        return RunPart(result, tuple(_with_stages(self._diffs[k], stages) for k, stages in self._touched.items()))

    def run(self, run: str) -> RunResult:
        started = time.perf_counter()
        base, new = self.before.judgements(run), self.after.judgements(run)
        rs_b, rs_n = self.before.ruleset(run), self.after.ruleset(run)
        diffs = self._stage_diffs(rs_b, rs_n)
        incidents = tuple(self._incident(run, b, n, diffs) for b, n in match(base, new))
        judged = time.perf_counter()
        decisions = self._decisions(run, rs_b, rs_n)
        seconds = {"incidents": judged - started, "decisions": time.perf_counter() - judged}
        problems = tuple(dict.fromkeys([*self.before.problems.get(run, []), *self.after.problems.get(run, [])]))
        return RunResult(run, incidents, decisions, rs_b.describe(), rs_n.describe(), problems, seconds)

    # -- the rulebooks ---------------------------------------------------------------------
    def _diff(self, old: Rulebook, new: Rulebook, stage: str) -> RulebookDiff:
        key = (old.sha256, new.sha256)
        if key not in self._diffs:
            self._diffs[key] = diff_rulebooks(old, new, names=self._names)
        self._touched.setdefault(key, set()).add(stage)
        return self._diffs[key]

    def _stage_diffs(self, rs_b: RuleSet, rs_n: RuleSet) -> Diffs:
        out = {}
        for stage in STAGES:
            b, n = rs_b[stage], rs_n[stage]
            if b is not None and n is not None and b.rulebook.sha256 != n.rulebook.sha256:
                out[stage] = self._diff(b.rulebook, n.rulebook, stage)
        return out

    # -- incidents -------------------------------------------------------------------------
    def _incident(self, run: str, b: Judgement | None, n: Judgement | None, diffs: Diffs) -> CaseResult:
        one = b or n
        if one is None:
            raise ValueError(f"{run}: an incident on neither side")      # match pairs each with one at least
        case = CaseResult(run, "incident", one.id, one.vehicle, one.action, one.t, _summary(b), _summary(n))
        return _with(case, self._incident_changes(b, n, diffs))

    def _incident_changes(self, b: Judgement | None, n: Judgement | None, diffs: Diffs) -> list[Change]:
        if b is None or n is None:
            kind = "new" if b is None else "gone"
            return [self._because(kind, _summary(b), _summary(n), _verdict_trees(b, n), diffs)]
        if b.verdict != n.verdict:
            return [self._because("verdict", b.verdict, n.verdict, _verdict_trees(b, n), diffs)]
        out = []
        if b.rule != n.rule:
            out.append(self._because("rule", b.rule, n.rule, _verdict_trees(b, n), diffs))
        if _penalty(b) != _penalty(n):
            out.append(self._because("penalty", _penalty_text(b), _penalty_text(n),
                                     [*self._penalty_trees(whole(b), self.before), *self._penalty_trees(whole(n), self.after)],
                                     diffs))
        if _liability(b) != _liability(n):
            out.append(self._because("liability", _liability_text(b), _liability_text(n),
                                     [*_liability_trees(whole(b)), *_liability_trees(whole(n))], diffs))
        return out

    def _because(self, kind: str, before: str | None, after: str | None, trees: Iterable[Trees],
                 diffs: Diffs) -> Change:
        """The change, attributed to the changed rules of the stages that explain its kind."""
        relevant = [diffs[stage] for stage in EXPLAINED_BY[kind] if stage in diffs]
        rules = attribute(relevant, used_rules(trees))
        return Change(kind, before, after, reasons(rules, relevant), rules)

    def _penalty_trees(self, inc: Incident, inv: Investigation) -> list[Trees]:
        """The penalties stage's proof of the incident's penalty, asked again (the incident keeps
        the penalty, not its proof)."""
        choice = inc.rulebooks.get("penalties")
        rb = inv.rulebook(choice.sha256) if choice else None
        if rb is None or inc.verdict != Verdict.PUNISHABLE:
            return []
        me = constant([inc.vehicle])
        facts = self.reader.known(rb, [s for s, _ in inc.scenarios.validator if isinstance(s, str)])
        facts.append(PUNISHABLY_VIOLATES.atom(me, constant(inc.action.split())))
        asked = self.engine.answers(rb, [Cond(atom=INCURS_FIXED_PENALTY.atom(me, Var("amount"), Var("points"),
                                                                             Var("offence")))], facts, explain=True)
        trees = [t for proof in asked.proofs for t in proof] or list(asked.why_not or [])
        return [Trees(rb.sha256, tuple(trees))]

    # -- decisions -------------------------------------------------------------------------
    def _decisions(self, run: str, rs_b: RuleSet, rs_n: RuleSet) -> tuple[CaseResult, ...]:
        """Every recorded decision under both sides: from the baseline's kept answers where no
        decision's vehicle-stage rulebook differs between the sides, else each asked again, on
        its kept Vehicle Scenario where the baseline kept it (and the baseline's answers kept,
        when it is the judgement in force)."""
        keeps, memo = self.before.keeps_verdicts(run, rs_b), self.before.memo(run)
        kept = kept_decisions(memo) if keeps else None
        cb, cn = _chooser(rs_b), _chooser(rs_n)
        if kept is not None and all(_unchanged(k, cb(k.decision), cn(k.decision)) for k in kept):
            return tuple(_kept_case(k) for k in kept)
        if self.shapes is not None:
            self.shapes.attach(memo)        # each decision's shape kept for the next regression
        rows: list[Row]
        if kept is None:
            rows = [(d, cb(d), cn(d), None) for d in recorded_decisions(self.store, run)]
        else:
            rows = [(k.decision, cb(k.decision), cn(k.decision), (k.rulebook, k.permitted)) for k in kept]
        if self.shapes is not None:     # the kept shapes the decisions ask, all at once: a call a rulebook
            self.shapes.ask_kept(self.engine, _asked_plainly(rows))
        judged = [self._decision(*row) for row in rows]
        if keeps and kept is None:
            keep_decisions(memo, [(d, before) for d, _, before in judged])
        shaped = self.shapes.keep() if self.shapes is not None else False
        if (keeps and kept is None) or shaped:
            memo.save()
        return tuple(case for _, case, _ in judged)

    def _decision(self, d: RecordedDecision, cb: Choice | None, cn: Choice | None,
                  kept: Kept | None = None) -> tuple[RecordedDecision, CaseResult, Asked]:
        """The decision's case, asked of the two sides' vehicle-stage choices, and the baseline's
        answer (`kept`: the rulebook and answer kept for it, taken where the baseline asks that
        very rulebook)."""
        if cb is not None and kept is not None and _takes_kept(cb, kept):
            before = Asked(cb.rulebook, kept[1])
        else:
            before = ask(self.engine, self.reader, cb, d, shapes=self.shapes)
        after = before if _same(cb, cn) else ask(self.engine, self.reader, cn, d, shapes=self.shapes)
        if before.permitted == after.permitted:
            return d, _unchanged_case(d, _answer(before.permitted)), before
        case = CaseResult(d.run, "decision", d.id, d.vehicle, str(d.goal), d.t, _answer(before.permitted),
                          _answer(after.permitted))
        proofs = [ask(self.engine, self.reader, c, d, proofs=True).proof for c in (cb, cn)]
        diffs = {"vehicle": self._diff(cb.rulebook, cn.rulebook, "vehicle")} if cb and cn else {}
        change = self._because("decision", case.before, case.after, [p for p in proofs if p is not None], diffs)
        return d, _with(case, [change]), before


def _takes_kept(cb: Choice | None, kept: Kept | None) -> bool:
    """Whether the baseline's answer is the one kept (it asks the very rulebook that gave it)."""
    return kept is not None and cb is not None and kept[0] == cb.rulebook.sha256


def _same(cb: Choice | None, cn: Choice | None) -> bool:
    """Whether the new side asks the baseline's vehicle-stage rulebook (and answers as it)."""
    return cb is not None and cn is not None and cb.rulebook.sha256 == cn.rulebook.sha256


def _asked_plainly(rows: list[Row]) -> list[tuple[Rulebook, RecordedDecision]]:
    """The rulebooks `Regressor._decision` asks each decision of without proofs (`ask` asks a goal
    that is a text)."""
    out = []
    for d, cb, cn, kept in rows:
        if isinstance(d.goal, str):
            if cb is not None and not _takes_kept(cb, kept):
                out.append((cb.rulebook, d))
            if cn is not None and not _same(cb, cn):
                out.append((cn.rulebook, d))
    return out


def _chooser(rs: RuleSet) -> Callable[[RecordedDecision], Choice | None]:
    """vehicle_choice of one side, worked out once per rulebook the decisions name (it depends on
    nothing else of a decision; a run's tens of thousands of decisions name a few)."""
    found: dict[str | None, Choice | None] = {}

    def choose(d: RecordedDecision) -> Choice | None:
        named = d.rulebook if isinstance(d.rulebook, str) else None
        try:
            return found[named]
        except KeyError:
            choice = found[named] = vehicle_choice(rs, d)
            return choice
    return choose


def _unchanged(k: KeptDecision, cb: Choice | None, cn: Choice | None) -> bool:
    """Whether both sides ask the kept decision of the very rulebook its kept answer came from."""
    return cb is not None and cn is not None and cb.rulebook.sha256 == cn.rulebook.sha256 == k.rulebook


def _kept_case(k: KeptDecision) -> CaseResult:
    """The decision's case from its kept answer (the same on both sides: no change)."""
    return _unchanged_case(k.decision, _answer(k.permitted))


def _unchanged_case(d: RecordedDecision, answer: str) -> CaseResult:
    """The case of a decision answered alike on both sides: CaseResult(d.run, "decision", d.id,
    d.vehicle, str(d.goal), d.t, answer, answer), made as its frozen dataclass's __init__ makes
    it, but with its fields set at once rather than by a setattr call each (a run's tens of
    thousands of decisions each make one, its fields written out: tests/reasoner/test_unchanged_case.py
    checks they are all CaseResult has)."""
    case = _new(CaseResult)
    _set(case, "__dict__", {"run": d.run, "case": "decision", "id": d.id, "vehicle": d.vehicle, "action": str(d.goal),
                            "t": d.t, "before": answer, "after": answer, "changes": ()})
    return case


_new, _set = object.__new__, object.__setattr__             # looked up once, not per decision


def _with(case: CaseResult, changes: list[Change]) -> CaseResult:
    """The case with its changes, but only those a reader can see: one whose before and after read
    alike (a self-driving entity's "no fixed penalty" under a raised fine) is not a change."""
    seen = tuple(c for c in changes if c.before != c.after)
    return CaseResult(case.run, case.case, case.id, case.vehicle, case.action, case.t, case.before, case.after, seen)


def _answer(permitted: bool | None) -> str:
    return ANSWERS.get(permitted, "not answerable")


def _verdict_trees(*incs: Judgement | None) -> list[Trees]:
    """The monitor stage's and the validator's proofs of the incidents."""
    out = []
    for inc in incs:
        if inc is None:
            continue
        out.append(Trees(inc.proofs.potential_violation.rulebook, tuple(inc.proofs.potential_violation.trees)))
        if inc.proofs.verdict is not None:
            out.append(Trees(inc.proofs.verdict.rulebook, tuple(inc.proofs.verdict.trees)))
    return out


def _liability_trees(inc: Incident) -> list[Trees]:
    return [Trees(inc.liability.rulebook, tuple(inc.liability.trees))] if inc.liability else []


def _penalty(inc: Judgement) -> tuple | None:
    p = inc.penalty
    return None if p is None else (p.offence, p.fine_gbp, p.points, p.fine_gbp_by_law, p.points_by_law,
                                   p.regulatory_sanctions)


def _penalty_text(inc: Judgement | None) -> str:
    p = inc.penalty if inc else None
    if p is None:
        return "no penalty"
    fine = "no fixed penalty" if p.fine_gbp is None else f"£{p.fine_gbp}"
    return f"{fine} + {p.points} points ({p.offence})"


def _liability(inc: Judgement) -> tuple:
    return inc.liable, inc.parties


def _liability_text(inc: Judgement) -> str:
    parties = ", ".join(inc.parties)
    return f"liable: {inc.liable}" + (f" (parties: {parties})" if parties and parties != inc.liable else "")


def _summary(inc: Judgement | None) -> str | None:
    """An incident's judgement in a line: verdict, rule, penalty, who is liable."""
    if inc is None:
        return None
    return f"{inc.verdict} {inc.rule or '(no rule)'}, {_penalty_text(inc)}, liable: {inc.liable}"
