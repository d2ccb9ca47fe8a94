"""Findings about the record itself: decision faults and missing evidence.

(Perception faults are in perception.py, monitor disagreements come from matching episodes,
unknown facts from facts.py.) Each is a model.Finding.
"""
from __future__ import annotations

from typing import Any

from store import EventRef, Store

from .engine import Engine
from .facts import FactReader
from .le.sentences import constant
from .model import Decision, Finding
from .stages import Choice
from .when import format_time

SECOND = 1_000_000_000
WINDOW_S = 10    # a sequence gap this close to an incident is missing evidence about it
SILENT_S = 5     # a source that reported before the incident and not for this long went silent


def decision_fault(engine: Engine, reader: FactReader, choice: Choice | None, vehicle: str,
                   action: Decision | None, perceived: list[tuple[Any, EventRef]],
                   unknown: list[Finding]) -> Finding | None:
    """Whether the vehicle's recorded decision contradicts its own rulebook on its own perception.

    Two ways: the `permitted` it recorded is not what the rulebook answers (a wrong answer, or a
    tampered one), or it proceeded though the rulebook did not permit the action."""
    if action is None or choice is None or not isinstance(action.goal, str):
        return None
    rb = choice.rulebook
    goal = reader.atom(rb, action.goal)
    if goal is None:
        unknown.append(Finding("unknown fact", f"the decision's goal is not a sentence of {rb.name}; its decision "
                                               "could not be checked", (action.evidence,), fact=action.goal[:200]))
        return None
    if constant([vehicle]) not in goal.args:
        return None
    permitted = engine.holds(rb, goal, reader.atoms(rb, perceived))
    recorded, proceeds = action.permitted, action.proceeds
    said = f'its own rulebook ({rb.name}) on its own perception answers "{action.goal}": {_yes(permitted)}'
    if isinstance(recorded, bool) and recorded != permitted:
        detail = f"the vehicle recorded permitted={_yes(recorded)} but {said}"
    elif proceeds is True and not permitted:
        detail = f"the vehicle proceeded although {said}"
    else:
        return None
    return Finding("decision fault", detail, (action.evidence,), recomputed_permitted=permitted,
                   recorded_permitted=recorded, proceeds=proceeds)


def _yes(value: Any) -> str:
    return {True: "yes", False: "no"}.get(value, str(value))


class Gaps:
    """Sequence gaps of a run's sources, looked up per source as incidents need them.

    A run without gaps costs one probe per source (Store.has_sequence_gaps); only a source with
    gaps is read in full to list them."""

    def __init__(self, store: Store, run: str) -> None:
        self.store, self.run = store, run
        self._found: dict[str, list[tuple[int, int]]] = {}
        self._any: bool | None = None

    def of(self, src: str) -> list[tuple[int, int]]:
        if self._any is None:
            self._any = self.store.has_sequence_gaps(self.run)
        if not self._any:
            return []
        if src not in self._found:
            self._found[src] = self.store.sequence_gaps(self.run, src)
        return self._found[src]


def missing_evidence(gaps: Gaps, srcs: list[str], t: int, last_seen: dict[str, int | None]) -> list[Finding]:
    """Sequence gaps of the sources an incident rests on, near it; and sources gone silent.

    A gap is near when the events on either side of it bracket a moment within WINDOW_S of t.
    A source is silent if it had reported before t but not within SILENT_S before t, and
    reports nothing again within SILENT_S after it."""
    store, run = gaps.store, gaps.run
    out = []
    lo, hi = t - WINDOW_S * SECOND, t + WINDOW_S * SECOND
    for src in srcs:
        for first, last in gaps.of(src):
            before = store.t_of(run, src, first - 1)
            after = store.t_of(run, src, last + 1)
            if (before is None or before <= hi) and (after is None or after >= lo):
                out.append(Finding("missing evidence", f"{src} events {first} to {last} are missing "
                                   f"from the record, between {_when(before, 'its first event')} and "
                                   f"{_when(after, 'its last event')}, within {WINDOW_S} s of the incident",
                                   src=src, missing_seq=(first, last)))
    for src, seen in last_seen.items():
        if seen is None or t - seen <= SILENT_S * SECOND:
            continue
        next_t = store.next_t(run, src, t, t + SILENT_S * SECOND)
        if next_t is None or next_t - t > SILENT_S * SECOND:
            out.append(Finding("missing evidence", f"{src} went silent: its last report before the incident was "
                                                   f"{(t - seen) / SECOND:.1f} s earlier, and it reported nothing "
                                                   f"in the {SILENT_S} s after it", src=src))
    return out


def _when(t: int | None, otherwise: str) -> str:
    return otherwise if t is None else format_time(t)

