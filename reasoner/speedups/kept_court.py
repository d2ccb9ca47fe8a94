"""The court that reads what earlier investigations of a run's chain measured and answered.

Measuring a case (the vehicle's passage, what it shows at the act, the state at the act) reads
and reconstructs from the record and is most of judging; it depends on the events and the code,
never on a rulebook, so it is kept in the case memo (reasoner/case_memo.py) with the parts a
summary reads apart. A stage's answer is kept by the judgement in force only (what a new
rulebook answers is worked out each time); an investigation that leaves proofs out remembers
its own answers, so that working them out later asks nothing twice.
"""
from __future__ import annotations

from typing import Any, Callable

from store import State

from ..case_memo import CaseMemo, key_of
from ..findings import Gaps
from ..judge.case import Case, Weighing
from ..judge.court import Court
from ..judge.weighing import weighing_of
from ..measurement import Measurement
from ..history import Scenario
from ..stages import RuleSet


class KeptCourt(Court):
    """A court whose measurements, states, sources and (for the judgement in force) stage
    answers are read from the run's case memo where kept, and kept where worked out."""

    def __init__(self, plain: Court, memo: Callable[[str], CaseMemo], keeps: Callable[[str, RuleSet], bool],
                 unproved: bool) -> None:
        """`keeps(run, rs)`: whether stage answers under these rulebooks are kept. `unproved`:
        the investigation leaves proofs out (its answers are remembered for working them out)."""
        super().__init__(plain.store, plain.engine, plain.reader, plain.problems)
        self.memo, self.keeps, self.unproved = memo, keeps, unproved
        self._answered: dict[tuple[str, str], Any] = {}

    def state(self, run: str, t: int, vehicle: str, src: str) -> State:
        return State.from_json(self.memo(run).remember("state", key_of(t, vehicle, src),
                                                       lambda: super(KeptCourt, self).state(run, t, vehicle, src)
                                                       .to_json(), plain=True))

    def measured(self, case: Case, mscen: Scenario, vscen: Scenario) -> Measurement:
        """Kept for the next investigation of the same chain, with the parts a summary reads
        apart (each its own entry: reading and sealing the whole measurement for them cost a
        summary more than any other kept entry)."""
        memo, key = self.memo(case.run), measurement_key(case, mscen)
        kept = memo.get("measurement", key)
        if kept is not None:
            return kept
        found = super().measured(case, mscen, vscen)
        memo.put("derived", key, found.derived)
        memo.put("act", key, [found.act])
        memo.put("overruled", key, tuple(sorted(found.overruled)))
        memo.put("weighing", key, weighing_of(found, case.action))
        memo.put("measurement", key, found)
        return found

    def derived(self, case: Case, mscen: Scenario, vscen: Scenario) -> tuple:
        found = self._part(case, mscen, "derived")
        return super().derived(case, mscen, vscen) if found is None else found

    def act(self, case: Case, mscen: Scenario, vscen: Scenario) -> Any:
        found = self._part(case, mscen, "act")
        return super().act(case, mscen, vscen) if found is None else found[0]

    def overruled(self, case: Case, mscen: Scenario, vscen: Scenario) -> frozenset[str]:
        found = self._part(case, mscen, "overruled")
        return super().overruled(case, mscen, vscen) if found is None else frozenset(found)

    def weighing(self, case: Case, mscen: Scenario, vscen: Scenario) -> Weighing:
        found = self._part(case, mscen, "weighing")
        return super().weighing(case, mscen, vscen) if found is None else found

    def _part(self, case: Case, mscen: Scenario, kind: str) -> Any:
        return self.memo(case.run).get(kind, measurement_key(case, mscen))

    def ask(self, case: Case, kind: str, question: list, compute: Callable[[], Any]) -> Any:
        """Read where the judgement in force of the same chain kept it: a regression's new side
        asks the stages whose rulebook it shares with the baseline nothing again."""
        memo, key = self.memo(case.run), key_of(kind, question)
        found = memo.get(kind, key, counted=False)
        if found is None and self.unproved:
            found = self._answered.get((kind, key))     # asked by this investigation (before `proved`)
        if found is not None:
            return found
        found = compute()
        if self.keeps(case.run, case.rs):
            memo.put(kind, key, found)
        elif self.unproved:
            self._answered[(kind, key)] = found
        return found

    def sources(self, run: str) -> list[str]:
        return self.memo(run).remember("sources", key_of("sources"), lambda: super(KeptCourt, self).sources(run),
                                       plain=True)

    def since(self, run: str, src: str) -> int | None:
        return self.memo(run).remember("since", key_of("since", src),      # [None]: never an entity
                                       lambda: [super(KeptCourt, self).since(run, src)], plain=True)[0]

    def gaps(self, run: str) -> Gaps:
        return Gaps(self.store, run, self.memo(run))


def measurement_key(case: Case, mscen: Scenario) -> str:
    """What names a case's measurement: its act and the events its Monitor Scenario's facts
    came from (before what the measurement shows is added to it)."""
    stated = list(dict.fromkeys((ref.src, ref.seq) for _, ref in mscen.facts if ref is not None))
    return key_of(case.t, case.vehicle, case.monitor, case.action, stated)
