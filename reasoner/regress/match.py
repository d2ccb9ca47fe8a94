"""Which incident of one judgement is which of the other.

An incident's id is the monitor event it is anchored on ("monitor/m1:12": the recorded potential
violation, or the first observation it was re-derived from), so the same act judged under two
rulebooks keeps its id, and ids are matched first. A changed monitor rulebook can re-derive an act
from another observation of the same episode, or a swept one from another event: those are the
same act when the vehicle and the action are the same and the times are at most MATCH_WINDOW_S
apart (the nearest pairs first, each incident used once). 5 s is shorter than any vehicle takes to
come back to a stop line, and longer than a monitor's episode of one crossing.
"""
from __future__ import annotations

from typing import Protocol, Sequence, TypeVar

MATCH_WINDOW_S = 5.0
SECOND = 1_000_000_000


class Named(Protocol):
    """What matching reads of an incident (a whole one or its summary)."""

    @property
    def id(self) -> str: ...
    @property
    def t(self) -> int: ...
    @property
    def vehicle(self) -> str: ...
    @property
    def action(self) -> str: ...


Incident = TypeVar("Incident", bound=Named)


def match(before: Sequence[Incident], after: Sequence[Incident]
          ) -> list[tuple[Incident | None, Incident | None]]:
    """Pairs (before, after), None on the side that lacks the incident; in time order."""
    by_id = {inc.id: inc for inc in after}
    pairs: list[tuple[Incident | None, Incident | None]] = []
    left: list[Incident] = []
    taken: set[int] = set()
    for inc in before:
        other = by_id.get(inc.id)
        if other is not None and id(other) not in taken:
            taken.add(id(other))
            pairs.append((inc, other))
        else:
            left.append(inc)
    right = [inc for inc in after if id(inc) not in taken]
    near = _nearest(left, right)
    paired_left = {id(a) for a, _ in near}
    paired_right = {id(b) for _, b in near}
    pairs += near
    pairs += [(inc, None) for inc in left if id(inc) not in paired_left]
    pairs += [(None, inc) for inc in right if id(inc) not in paired_right]
    pairs.sort(key=lambda p: (_either(p).t, _either(p).id))
    return pairs


def _either(pair: tuple[Incident | None, Incident | None]) -> Incident:
    """The incident of a pair (before, else after: a pair has one at least)."""
    found = pair[0] if pair[0] is not None else pair[1]
    assert found is not None, "a pair has an incident on one side at least"
    return found


def _nearest(left: list[Incident], right: list[Incident]) -> list[tuple[Incident, Incident]]:
    """The same vehicle and action within the window, closest in time first."""
    window = int(MATCH_WINDOW_S * SECOND)
    scored = sorted((abs(a.t - b.t), i, j) for i, a in enumerate(left) for j, b in enumerate(right)
                    if a.vehicle == b.vehicle and a.action == b.action and abs(a.t - b.t) <= window)
    used_left, used_right, out = set(), set(), []
    for _, i, j in scored:
        if i not in used_left and j not in used_right:
            used_left.add(i)
            used_right.add(j)
            out.append((left[i], right[j]))
    return out
