"""What every case of an investigation is judged with, beside the case: the court.

The pipeline (pipeline.py) asks the court for the store's engine, fact reader and the run's
lookups, and for the few things a speed-up may answer from what it kept instead of working them
out: the state at a time, a case's measurement (and its parts a summary reads), a stage's answer
to a question, the run's sources and when each became an entity, a source's lost events. This
court works every one of them out, every time: it is the plain judge. reasoner/speedups/
holds the court that answers them from the case memo (speedups/kept_court.py); both give the
same answers, which the tests compare to the byte.
"""
from __future__ import annotations

from typing import Any, Callable

from store import State, Store, entity_since, state_of

from .. import acts, history, stretches
from ..engine import Engine, Rulebook
from ..facts import FactReader
from ..findings import Gaps
from ..le.sentences import constant
from ..le.terms import Atom
from ..measurement import Measurement, measure
from ..history import Passage
from ..perception import witnessed_functors
from ..history import Scenario
from .case import Case, Weighing
from .weighing import weighing_of

_RENDERED_LIMIT = 200_000                         # facts a court remembers the rendering of


class Court:
    """The plain judge's court: everything worked out when asked (within one investigation, the
    run's map, its sources and a fact's rendering are read once: they are the run's, not a case's)."""

    def __init__(self, store: Store, engine: Engine, reader: FactReader, problems: dict[str, list[str]]) -> None:
        self.store, self.engine, self.reader, self.problems = store, engine, reader, problems
        self._contexts: dict[str, history.RunContext] = {}
        self._names: dict[str, dict[Any, list[str]]] = {}
        self._entity_since: dict[tuple[str, str], float] = {}
        self._firsts: dict[tuple[str, Any], float] = {}
        self._rendered: dict[tuple[str, Atom], str] = {}
        self._witnessed: dict[str, set[str]] = {}

    # -- what a speed-up may answer from what it kept -------------------------------------
    def state(self, run: str, t: int, vehicle: str, src: str) -> State:
        """The vehicle's record and what the monitor last observed of it at t."""
        return state_of(self.store, run, t, entities=[f"vehicle/{vehicle}"], observed=[(src, vehicle)])

    def measured(self, case: Case, mscen: Scenario, vscen: Scenario) -> Measurement:
        """What the vehicle's passage through the junction of the act shows at the act beside
        what the monitor stated (DESIGN "Reasoning": histories)."""
        stretch = stretches.stretch_at(self.store, case.run, case.vehicle, case.t, self.context(case.run).map) \
            if case.action == acts.SPEEDING else None
        return measure(self.passage(case), case.t, case.action, mscen.facts, mscen.sentences, vscen.facts, stretch)

    def derived(self, case: Case, mscen: Scenario, vscen: Scenario) -> tuple:
        """The measurement's derived facts (a summary reads no more of it)."""
        return self.measured(case, mscen, vscen).derived

    def act(self, case: Case, mscen: Scenario, vscen: Scenario) -> Any:
        """The act as the measurement delimits it."""
        return self.measured(case, mscen, vscen).act

    def overruled(self, case: Case, mscen: Scenario, vscen: Scenario) -> frozenset[str]:
        """The stated predictions the measurement overrules."""
        return self.measured(case, mscen, vscen).overruled

    def weighing(self, case: Case, mscen: Scenario, vscen: Scenario) -> Weighing:
        """What the measurement contradicts and leaves unproven, and the act's moment."""
        return weighing_of(self.measured(case, mscen, vscen), case.action)

    def ask(self, case: Case, kind: str, question: list, compute: Callable[[], Any]) -> Any:
        """A stage's answer to a question (its rulebook's sha256 and what it is asked on)."""
        return compute()

    def sources(self, run: str) -> list[str]:
        return self.store.sources(run)

    def since(self, run: str, src: str) -> int | None:
        """When the source became an entity of the run's state (None: never)."""
        return entity_since(self.store, run, src)

    def gaps(self, run: str) -> Gaps:
        """The run's sources' lost events (missing evidence)."""
        return Gaps(self.store, run)

    # -- the run's lookups ----------------------------------------------------------------
    def context(self, run: str) -> history.RunContext:
        """What every history of the run shares (its map, its signals), read once."""
        if run not in self._contexts:
            self._contexts[run] = history.run_context(self.store, run)
        return self._contexts[run]

    def passage(self, case: Case) -> Passage | None:
        return history.passage(self.store, case.run, case.vehicle, case.t, context=self.context(case.run))

    def render(self, rb: Rulebook, atom: Atom) -> str:
        """rb.render(atom), once per rulebook and atom: a regression's new side renders the
        validator facts of every case, and half of them some earlier case rendered already (a
        vehicle's type, its light). Only an atom of text and whole numbers is remembered: one
        equal to it renders alike (1.0 and True equal 1, and do not)."""
        if not all(type(arg) is str or type(arg) is int for arg in atom.args):
            return rb.render(atom)
        key = (rb.sha256, atom)
        found = self._rendered.get(key)
        if found is None:
            if len(self._rendered) >= _RENDERED_LIMIT:
                self._rendered.clear()
            found = self._rendered[key] = rb.render(atom)
        return found

    def witnessed_by(self, monitor_rb: Rulebook) -> set[str]:
        """The functors the monitor rulebook reads (what a monitor witnesses), once per rulebook."""
        if monitor_rb.sha256 not in self._witnessed:
            self._witnessed[monitor_rb.sha256] = witnessed_functors(monitor_rb)
        return self._witnessed[monitor_rb.sha256]

    def others(self, case: Case, pairs: list[tuple[Atom, Any]]) -> set:
        """The constants of these facts that name another road user on record by the act's time
        (a source with an entity event by then, named by the part of its src after the "/"):
        a fact about one of them is not the vehicle's own."""
        named = self.named(case.run)
        out = set()
        for atom, _ in pairs:
            for arg in atom.args:
                if isinstance(arg, (str, int)) and arg != case.me and arg in named and arg not in out \
                        and self.first_since(case.run, arg) <= case.t:
                    out.add(arg)
        return out

    def first_since(self, run: str, name: Any) -> float:
        """When the first of the sources a constant names became an entity of the run (inf:
        none did), once per run and constant: a case asks it of every constant of its facts."""
        key = (run, name)
        found = self._firsts.get(key)
        if found is None:
            found = self._firsts[key] = min(self.since_once(run, src) for src in self.named(run)[name])
        return found

    def named(self, run: str) -> dict[Any, list[str]]:
        """The run's sources by the constant their id reads as, read once per run (a long run's
        thousands of sources are an index probe each)."""
        if run not in self._names:
            names: dict[Any, list[str]] = {}
            for src in self.sources(run):
                if "/" in src:
                    names.setdefault(constant([src.split("/", 1)[1]]), []).append(src)
            self._names[run] = names
        return self._names[run]

    def since_once(self, run: str, src: str) -> float:
        """`since`, once per run and source (inf: never an entity)."""
        key = (run, src)
        if key not in self._entity_since:
            since = self.since(run, src)
            self._entity_since[key] = float("inf") if since is None else since
        return self._entity_since[key]
