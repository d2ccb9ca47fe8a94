"""Findings about the record itself: decision faults and missing evidence.

(Perception faults are in perception.py, monitor disagreements come from matching episodes,
unknown facts from facts.py.) Each is a model.Finding.
"""
from __future__ import annotations

from typing import Any, Callable

from store import EventRef, Store
from store.wire import LivelinessChange

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

    def __init__(self, store: Store, run: str, kept: Any = None) -> None:
        """`kept`: a reasoner/case_memo.CaseMemo of the run, to keep each source's gaps in (a
        long run's thousands of sources each cost a walk over their seqs)."""
        self.store, self.run, self.kept = store, run, kept
        self._found: dict[str, list[tuple[int, int, int | None, int | None]]] = {}
        self._any: bool | None = None
        self._changes: dict[str, list[LivelinessChange]] | None = None

    def liveliness(self, src: str) -> list[LivelinessChange]:
        """The source's liveliness changes as the ingest recorded them (none for a store filled by
        import, or a producer without tokens); the run's are read once."""
        if self._changes is None:
            self._changes = {}
            for change in self.store.liveliness_changes(self.run):
                self._changes.setdefault(change.src, []).append(change)
        return self._changes.get(src, [])

    def of(self, src: str) -> list[tuple[int, int]]:
        return [(first, last) for first, last, _, _ in self.spans(src)]

    def spans(self, src: str) -> list[tuple[int, int, int | None, int | None]]:
        """The source's gaps, each (first missing seq, last missing seq, t of the event before,
        t of the event after)."""
        if self._any is None:
            self._any = self._remembered("any gaps", "", lambda: self.store.has_sequence_gaps(self.run))
        if not self._any:
            return []
        if src not in self._found:
            self._found[src] = [tuple(span) for span in self._remembered("gaps", src, lambda: self._read(src))]
        return self._found[src]

    def _remembered(self, kind: str, key: str, compute: Callable[[], Any]) -> Any:
        return self.kept.remember(kind, key, compute, plain=True) if self.kept is not None else compute()

    def _read(self, src: str) -> list[list]:
        return [[first, last, self.store.t_of(self.run, src, first - 1), self.store.t_of(self.run, src, last + 1)]
                for first, last in self.store.sequence_gaps(self.run, src)]


def missing_evidence(gaps: Gaps, srcs: list[str], t: int, last_seen: dict[str, int | None]) -> list[Finding]:
    """Sequence gaps of the sources an incident rests on, near it; and sources gone silent.

    A gap is near when the events on either side of it bracket a moment within WINDOW_S of t.
    A source stopped publishing if the ingest recorded its liveliness token disappearing after its
    last event before t (store.LivelinessChange), however short ago. Otherwise it is silent if it
    had reported before t but not within SILENT_S before t, and reports nothing again within
    SILENT_S after it; with liveliness recorded for it, that it was still connected is said."""
    store, run = gaps.store, gaps.run
    out = []
    lo, hi = t - WINDOW_S * SECOND, t + WINDOW_S * SECOND
    for src in srcs:
        for first, last, before, after in gaps.spans(src):
            if (before is None or before <= hi) and (after is None or after >= lo):
                which = f"event {first} is" if first == last else f"events {first} to {last} are"
                out.append(Finding("missing evidence", f"{src} {which} missing "
                                   f"from the record, between {_when(before, 'its first event')} and "
                                   f"{_when(after, 'its last event')}, within {WINDOW_S} s of the incident",
                                   src=src, missing_seq=(first, last)))
    for src, seen in last_seen.items():
        if seen is None:
            continue
        stopped = _stopped(gaps, src, seen, t)
        if stopped is not None:
            out.append(stopped)
            continue
        if t - seen <= SILENT_S * SECOND:
            continue
        next_t = store.next_t(run, src, t, t + SILENT_S * SECOND)
        if next_t is None or next_t - t > SILENT_S * SECOND:
            held = " though it was connected: its liveliness token was held, so it published nothing rather " \
                   "than stopped" if gaps.liveliness(src) else ""
            out.append(Finding("missing evidence", f"{src} went silent{held}: its last report before the incident "
                                                   f"was {(t - seen) / SECOND:.1f} s earlier, and it reported nothing "
                                                   f"in the {SILENT_S} s after it", src=src))
    return out


def _stopped(gaps: Gaps, src: str, seen: int, t: int) -> Finding | None:
    """The source stopped publishing before the incident: its liveliness token disappeared after
    its last event before t (a process that died, a link that broke, a publisher closed), which is
    not the same as a source that was there and said nothing. A source whose last event is at the
    incident's moment reported it: a publisher closed after that (the demo's, when its scenario is
    over) takes nothing from the incident. The ingest's wall clock when it noticed stays out of
    the sentence: the run's clock is the source's world time, and two clocks in one sentence
    mislead (the change, with its wall-clock time, is in `gaps verify`'s wire records)."""
    for change in reversed(gaps.liveliness(src)):
        if change.alive or change.last_seq is None:
            continue
        last_t = gaps.store.t_of(gaps.run, src, change.last_seq)
        if last_t is not None and seen <= last_t < t:
            return Finding("missing evidence", f"{src} stopped publishing at {format_time(last_t)}, "
                                               f"{(t - last_t) / SECOND:.1f} s before the incident: its liveliness "
                                               f"token disappeared after its event {change.last_seq}, so nothing "
                                               "it would have reported since is on record", src=src)
    return None


def _when(t: int | None, otherwise: str) -> str:
    return otherwise if t is None else format_time(t)

