"""The one entry point for scripting an investigation: open a store, ask what happened.

    import reasoner
    with reasoner.open("gaps.db") as case:
        for inc in case.incidents("paper-junctions", verdict="punishable"):
            print(inc.vehicle, inc.rule, inc.penalty.fine_gbp, inc.liable)

A `Case` is what an investigator has on the desk: one store, opened read-only so that nothing a
script does can change the evidence, and one `Investigation` over it so that rulebooks, parsed
facts and chain checks are loaded once and shared by every question. Its answers are the typed
values of `reasoner.model` (Incident, Explanation, Scene); `explain` renders them. The command
line is a thin shell over the same calls.
"""
from __future__ import annotations

import os
from pathlib import Path
from typing import Callable, Iterable, Sequence

from store import GapsError, NoSuchRun, Store, VerifyReport

from .chain_status import ChainStatus
from .explanation import Explanation
from .history import RunContext
from .investigation import Investigation, Speedups
from .model import MONITORS, OWN_RECORD, Incident, found_in
from .regress import Cluster, Regression, regress, regress_store     # its caller, as cli/ is
from .scene import Scene, run_start, scene
from .verdicts import Verdict
from .when import parse_time

Progress = Callable[[int, int], None]
VERDICTS = tuple(v.value for v in Verdict)    # the words `verdict=` filters by
SOURCES = ("monitors", "own-record", "all")    # where an act was found (model.Source), as `source=` filters


class NoSuchIncident(GapsError, LookupError):
    """An incident id or number the run does not have; the message lists the ones it has."""

    def __init__(self, run: str, wanted: str, found: list[Incident]) -> None:
        ids = ", ".join(f"{n}={inc.id}" for n, inc in enumerate(found, 1)) or "none"
        super().__init__(f"no incident {wanted!r} in run {run!r}; incidents: {ids}")


class Case:
    """One store under investigation, read-only; use as a context manager or call `close()`."""

    def __init__(self, store: Store, rules: Iterable[str | os.PathLike] = ()) -> None:
        self.store = store
        self.investigation = Investigation(store, rules=[os.fspath(r) for r in rules],
                                           speedups=Speedups.INCIDENTS)
        self._incidents: dict[str, list[Incident]] = {}

    def __enter__(self) -> Case:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        self.store.close()

    # -- what the store holds ------------------------------------------------------------
    def runs(self) -> list[str]:
        """The run ids of the store, by name."""
        return [r.run for r in self.store.runs()]

    def require(self, run: str) -> None:
        """NoSuchRun ("no run 'x'; runs: a, b") unless the store holds `run`."""
        known = self.runs()
        if run not in known:
            raise NoSuchRun(run, known)

    def verify(self, run: str | None = None, progress: Progress | None = None) -> VerifyReport:
        """The hash chains (and checkpoints, signatures, rulebook addresses) recomputed."""
        if run is not None:
            self.require(run)
        return self.store.verify(run, progress)

    # -- what happened -------------------------------------------------------------------
    def incidents(self, run: str | None = None, *, verdict: str | None = None, vehicle: str | None = None,
                  rule: str | None = None, source: str | None = None,
                  progress: Progress | None = None) -> list[Incident]:
        """Every potential violation of `run` (default: of every run), judged, in time order;
        filtered by verdict, vehicle, rule (rules compare without case: "hc 176") and where the
        act was found (`source`: "monitors", found by a monitor; "own-record", found in the
        vehicle's own record only; "all")."""
        if verdict is not None and verdict not in VERDICTS:
            raise GapsError(f"unknown verdict {verdict!r}; verdicts: {', '.join(VERDICTS)}")
        if source is not None and source not in SOURCES:
            raise GapsError(f"unknown source {source!r}; sources: {', '.join(SOURCES)}")
        if run is not None:
            self.require(run)
        runs = [run] if run is not None else self.runs()
        found = [inc for r in runs for inc in self._judged(r, progress)]
        return [inc for inc in found if _matches(inc, verdict, vehicle, rule, source)]

    def numbered(self, run: str | None = None, *, verdict: str | None = None, vehicle: str | None = None,
                 rule: str | None = None, source: str | None = None,
                 progress: Progress | None = None) -> list[tuple[int, Incident]]:
        """`incidents(...)`, each with its number in its run (what `gaps incidents` lists and
        `gaps explain --run R N` takes): a filter leaves the numbers as they are."""
        found = self.incidents(run, verdict=verdict, vehicle=vehicle, rule=rule, source=source, progress=progress)
        numbers: dict[tuple[str, str], int] = {}
        for r in {inc.run for inc in found}:
            for n, inc in enumerate(self._judged(r, None), 1):
                numbers.setdefault((r, inc.id), n)       # the first of an id, as `number` finds it
        return [(numbers[inc.run, inc.id], inc) for inc in found]

    def incident(self, run: str, wanted: str | int) -> Incident:
        """One incident of the run by id ("monitor/m1:3"), the id of any record of its act (one
        act, one incident: reasoner/oneact.py), or 1-based number in time order. The one way
        an incident is found by what a user typed: `gaps explain`, `gaps report --incident` and
        a script all come here."""
        self.require(run)
        found = self._judged(run, None)
        text = str(wanted)
        for inc in found:
            if inc.id == text:
                return inc
        for inc in found:
            if any(s.id == text for s in inc.sources):
                return inc
        if text.isdigit() and 1 <= int(text) <= len(found):
            return found[int(text) - 1]
        raise NoSuchIncident(run, text, found)

    def number(self, incident: Incident) -> int:
        """The incident's 1-based number in its run's time order: what `gaps explain --run R N`
        and `case.incident(run, N)` take."""
        for n, inc in enumerate(self._judged(incident.run, None), 1):
            if inc.id == incident.id:
                return n
        raise NoSuchIncident(incident.run, incident.id, self._judged(incident.run, None))

    def explanation(self, incident: Incident, *, why_not: Iterable[str] = (),
                    counterfactuals: bool = True) -> Explanation:
        """What explaining the incident needs beyond its verdict: lawful actions, why-not answers
        on the Validator Scenario, counterfactuals and the chain's status."""
        return self.investigation.explanation(incident, why_not=why_not, counterfactuals=counterfactuals)

    def chain(self, run: str) -> ChainStatus:
        """The run's hash chain recomputed (once per run for this case), as every explanation
        of its incidents cites it."""
        self.require(run)
        return self.investigation.chain(run)

    def context(self, run: str) -> RunContext:
        """What the run's histories share (its map, its road users), read once for this case:
        a report rebuilds many acts of one run."""
        return self.investigation.context(run)

    def time(self, run: str, at: int | str) -> int:
        """`at` in nanoseconds: as it is, or read as seconds from the run start ("12.5s") or ISO
        8601 with a zone (reasoner/when.py; TimeError says what could not be read)."""
        self.require(run)
        return at if isinstance(at, int) else parse_time(at, run_start(self.store, run))

    def scene(self, run: str, at: int | str, vehicle: str | None = None, judge: bool | None = None) -> Scene:
        """The scene of the run at `at`: nanoseconds, seconds from the run start ("12.5s") or
        ISO 8601 with a zone. `vehicle` narrows it to one and asks whether its goal was lawful."""
        return scene(self.store, run, self.time(run, at), vehicle=vehicle, judge=judge,
                     investigation=self.investigation)

    def _judged(self, run: str, progress: Progress | None) -> list[Incident]:
        if run not in self._incidents:
            self._incidents[run] = self.investigation.incidents(run, progress)
        return self._incidents[run]


def open(path: str | os.PathLike, *, rules: Iterable[str | os.PathLike] = ()) -> Case:  # noqa: A001
    """Open the store at `path` read-only for investigation; `rules` are LE rulebooks judged
    with first (a stage they do not define keeps the run's own or the current rulebook)."""
    return Case(Store.open_read_only(path), rules)


def regression(db: str | Path, rules: Sequence[str], baseline: Sequence[str] | None = None,
               runs: Sequence[str] | None = None, *, cluster: Cluster = Cluster(),
               progress: Callable[[str, int, int], None] | None = None) -> Regression:
    """The runs (None: every run) of the store at `db` judged under `baseline` (None: each run's
    own rulebooks, else the project's) and under `rules`, and what changed (`gaps regress`,
    docs/regress.md): in this process on the store opened read-only, or on `cluster`'s workers,
    one task a run, each opening it by its path."""
    if cluster.in_process:
        with Store.open_read_only(db) as store:
            return regress(store, rules, baseline, runs, progress=progress)
    return regress_store(db, rules, baseline, runs, cluster=cluster, progress=progress)


def _matches(inc: Incident, verdict: str | None, vehicle: str | None, rule: str | None,
             source: str | None = None) -> bool:
    return ((verdict is None or inc.verdict == verdict)
            and (vehicle is None or inc.vehicle == vehicle)
            and (rule is None or str(inc.rule).casefold() == rule.casefold())
            and _found(inc, source))


def _found(inc: Incident, source: str | None) -> bool:
    if source in (None, "all"):
        return True
    where = found_in(inc.sources)
    return where == OWN_RECORD if source == OWN_RECORD else MONITORS in where
