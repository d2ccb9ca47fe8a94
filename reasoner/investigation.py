"""From a recorded run to validated verdicts (the paper's Figure 1), from the store alone.

    inv = Investigation(store)                 # or Investigation(store, rules=["my.le"])
    for incident in inv.incidents("demo-001"):
        print(incident.verdict, incident.rule, incident.liable)

An incident is a potential violation: recorded on line by a monitor, or re-derived off line from
the monitor's observations (episodes.py); both, normally. The investigation finds a run's cases
(judge/cases.py), judges each through the plain pipeline (judge/pipeline.py: monitor stage,
validator stage, sanctions, findings and proofs) and makes the cases of one act one incident
(oneact.py). The verdicts depend only on the events, never on the order or batches they arrived
in: the state is a fold in (t, seq, src) order and the episodes are read in that order too.

What makes it fast sits beside the pipeline (reasoner/speedups/): one `Speedups` member chooses
which speed-ups an investigation judges through, each naming its modules (MEASUREMENTS, the
default; NONE, the plain judge alone; INCIDENTS for `gaps incidents`; BASELINE and NEW_SIDE for
a regression's two sides, which also share what they read of a run: `shared`).
"""
from __future__ import annotations

import gc
from functools import partial
from typing import Any, Callable, Iterable

from store import Store

from . import oneact
from .case_memo import CaseMemo
from .chain_status import ChainStatus, chain_status
from .collector import JudgementCollector
from .engine import Engine, Rulebook, get_engine
from .explanation import Explanation, explain
from .facts import FactReader
from .findings import Gaps
from .history import RunContext
from .judge import Court, Todo, case_of, find, judge
from .model import Incident
from .speedups import Speedups, kept_cases, kept_verdicts, summaries
from .speedups.kept_court import KeptCourt
from .speedups.shared import SharedReading
from .speedups.summaries import IncidentSummary, Judgement, whole
from .stages import RuleSet, current_rulebooks, given_rulebooks, recorded_rulebooks

__all__ = ["Investigation", "IncidentSummary", "Judgement", "SharedReading", "Speedups", "whole"]

# The cases are found and judged with the cyclic collector paused (reasoner/collector.py): its
# full passes traverse every case read, every incident judged so far and every value decoded from
# the kept measurements, a third of a judgement from kept measurements, to find almost nothing.
# Every YOUNG_EVERY cases the young generations alone are collected, so any cycles judging makes
# never pile up: memory stays what it is with the collector on.
YOUNG_EVERY = 256


class Investigation:
    """Verdicts for the runs of one store: finds each run's cases and judges each, through the
    pipeline or its speed-ups. Rulebooks and parsed facts are loaded once and shared."""

    def __init__(self, store: Store, engine: Engine | None = None, rules: Iterable[str] | None = None, *,
                 speedups: Speedups = Speedups.MEASUREMENTS, reader: FactReader | None = None,
                 shared: SharedReading | None = None) -> None:
        """`speedups`: which speed-ups judge (reasoner/speedups/__init__.py names each member's
        modules). `reader`, `shared`: the fact reader and the runs' readings shared with other
        askers (a regression's two sides)."""
        self.store = store
        self.speedups = speedups
        self.shared = shared
        self.engine = engine or get_engine()
        self.reader = reader or FactReader()
        self.problems: dict[str, list[str]] = {}
        plain = Court(store, self.engine, self.reader, self.problems)
        self.court = KeptCourt(plain, self.memo, self.keeps_verdicts, unproved=speedups.summarises) \
            if speedups.keeps else plain
        self._given = given_rulebooks(self.engine, rules or [])
        self._current = current_rulebooks(self.engine)
        self._rulesets: dict[str, RuleSet] = {}
        self._chains: dict[str, ChainStatus] = {}
        self._memos: dict[str, CaseMemo] = {}
        self._judgements: dict[str, tuple[RuleSet, str]] = {}

    # -- public ---------------------------------------------------------------------------
    def incidents(self, run: str, progress: Callable[[int, int], None] | None = None) -> list[Incident]:
        """Every potential violation of the run, judged, whole; ordered by time (`judgements`)."""
        return [whole(found) for found in self.judgements(run, progress)]

    def judgements(self, run: str, progress: Callable[[int, int], None] | None = None) -> list[Judgement]:
        """Every potential violation of the run, judged; ordered by time: whole incidents, or (by
        `speedups`: BASELINE, NEW_SIDE) incident summaries. `progress(done, total)` is called as the cases are judged
        (after the pass over the observations): `done` of the `total` cases (recorded potential
        violations and acts the sweep found), which end as fewer incidents (one per act; a case
        the rules do not raise is none)."""
        memo = self._memos[run] = CaseMemo(self.store, run, enabled=self.speedups.keeps)  # the chain as it stands now
        with JudgementCollector():
            rs, todo = self._cases(run, memo)
            monitor = rs["monitor"].rulebook.sha256 if rs["monitor"] else None
            gaps = self.court.gaps(run)
            skip = self._read(run, ("unraised", monitor), lambda: kept_cases.names_of(
                memo.get("unraised", kept_cases.unraised_key(monitor), plain=True)))
            found, unraised = self._judge_all(run, rs, gaps, todo, skip or frozenset(), progress)
        if skip is None:
            memo.put("unraised", kept_cases.unraised_key(monitor), unraised, plain=True)
        memo.save()
        merged = [group[0] if len(group) == 1 else summaries.merged(group) for group in oneact.groups(found)]
        return sorted(merged, key=lambda inc: inc.t) if len(merged) < len(found) else merged

    def keeps_verdicts(self, run: str, rs: RuleSet) -> bool:
        """Whether this run's incidents are kept: judged by the rulebooks in force (the run's own,
        else the current ones), which is what `gaps incidents` shows; a judgement with a rulebook
        given for any stage is worked out each time (a regression's new rules are judged afresh)."""
        return self.speedups.keeps_incidents and kept_verdicts.in_force(rs)

    def memo(self, run: str) -> CaseMemo:
        """What earlier investigations of the run's chain measured, and what this one adds."""
        if run not in self._memos:
            self._memos[run] = CaseMemo(self.store, run, enabled=self.speedups.keeps)
        return self._memos[run]

    def context(self, run: str) -> RunContext:
        """What every history of the run shares (its map, its signals), read once."""
        return self.court.context(run)

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
        return explain(self, incident, list(why_not), counterfactuals)

    # -- the run's cases ------------------------------------------------------------------
    def _cases(self, run: str, memo: CaseMemo) -> tuple[RuleSet, list[Todo]]:
        """The run's rulesets and its cases, kept under the monitor rulebook (and shared)."""
        recorded = self._read(run, ("recorded",),
                              lambda: list(self.store.events(run, kinds=["monitor.potential_violation"])))
        rs = self.ruleset(run, recorded)
        monitor = rs["monitor"].rulebook.sha256 if rs["monitor"] else None
        todo = self._read(run, ("cases", monitor), lambda: kept_cases.cases(memo, monitor, recorded, lambda: find(
            self.store, self.engine, self.reader, self.court.context(run), run, rs, recorded)))
        return rs, todo

    def _judge_all(self, run: str, rs: RuleSet, gaps: Gaps, todo: list[Todo], skip: frozenset,
                   progress: Callable[[int, int], None] | None) -> tuple[list[Judgement], list[list]]:
        """Each case judged but those nobody recorded that the monitor rulebook was found not to
        raise (`skip`); and the names of the unraised ones, for the next investigation."""
        found: list[Judgement] = []
        unraised: list[list] = []
        for done, item in enumerate(todo, 1):
            name = kept_cases.name(item)
            incident = None if name is not None and name in skip else self._judged(run, rs, gaps, item)
            if incident is not None:
                found.append(incident)
            elif name is not None:
                unraised.append(list(name))
            if done % YOUNG_EVERY == 0:
                gc.collect(1)
            if progress is not None:
                progress(done, len(todo))
        return found, unraised

    def _read(self, run: str, what: tuple, read: Callable[[], Any]) -> Any:
        """What `read` gives, or what another investigation sharing `shared` read of the same
        chain of the run (speedups/shared.py). A None read is not shared."""
        if self.shared is None:
            return read()
        return self.shared.get((run, self.memo(run).chain, *what), read)

    # -- one case -------------------------------------------------------------------------
    def _judged(self, run: str, rs: RuleSet, gaps: Gaps, todo: Todo) -> Judgement | None:
        """The case's incident: kept under the rulebooks in force (`keeps_incidents`), else judged."""
        if not self.keeps_verdicts(run, rs):
            return self._afresh(run, rs, gaps, todo)
        # `_afresh` judges whole here: a Speedups member that keeps incidents never judges by summary
        return kept_verdicts.incident(self.memo(run), self._judged_by(run, rs), todo,
                                      partial(self._afresh, run, rs, gaps, todo),
                                      by_summary=self.speedups.reads_summaries)

    def _judged_by(self, run: str, rs: RuleSet) -> str:
        found = self._judgements.get(run)
        if found is None or found[0] is not rs:
            found = self._judgements[run] = (rs, kept_verdicts.judged_by(rs, self.problems.get(run)))
        return found[1]

    def _afresh(self, run: str, rs: RuleSet, gaps: Gaps, todo: Todo) -> Judgement | None:
        """The case judged now: by its summary alone (NEW_SIDE), else whole."""
        case = case_of(self.court, run, rs, todo)
        if self.speedups.summarises:
            return summaries.summarised(self.court, case, gaps)
        return judge(self.court, case, gaps)
