"""A run's cases kept, and the cases its monitor rulebook does not raise.

Finding the cases re-derives potential violations from every observation (a question to the
monitor rulebook) and sweeps the measurements: the list is kept under the monitor rulebook (and
the chain and the code, reasoner/case_memo.py). So are the cases nobody recorded that it does
not raise: no incident, whatever the other stages' rulebooks say, and not judged again (two
thirds of the hour's cases, a sixth of a judgement from kept measurements).
"""
from __future__ import annotations

from typing import Callable

from ..case_memo import CaseMemo, key_of
from ..episodes import Episode
from ..judge.case import anchor_key
from ..judge.cases import Todo


def cases(memo: CaseMemo, monitor: str | None, recorded: list[dict], find: Callable[[], list[Todo]]) -> list[Todo]:
    """The cases kept under the monitor rulebook `monitor` (its sha256), else `find()` and kept."""
    key = key_of("cases", monitor)
    kept = memo.get("cases", key, plain=True)
    if kept is not None:
        by_ref = {(pv["src"], pv["seq"]): pv for pv in recorded}
        todo = [unkept(item, by_ref) for item in kept]
        if all(item is not None for item in todo):
            return [item for item in todo if item is not None]
    found = find()
    memo.put("cases", key, [kept_form(item) for item in found], plain=True)
    return found


def kept_form(item: Todo) -> list:
    """A case to judge as plain data: the recorded potential violation by its (src, seq), the
    episode by the two observations a judgement reads of it (its first, and the one at t)."""
    t, src, pv, ep = item
    ref = [pv["src"], pv["seq"]] if pv else None
    if ep is None:
        return [t, src, ref, None]
    first, at = ep.first, ep.observation_at(t)
    return [t, src, ref, [ep.monitor, ep.vehicle, ep.action, [first] if at is first else [first, at]]]


def unkept(item: list, recorded: dict[tuple[str, int], dict]) -> Todo | None:
    """The case `kept_form` gave (None: its potential violation is not among those read)."""
    t, src, ref, ep = item
    pv = recorded.get((ref[0], ref[1])) if ref else None
    if ref and pv is None:
        return None
    return (t, src, pv, Episode(ep[0], ep[1], ep[2], ep[3]) if ep else None)


def unraised_key(monitor: str | None) -> str:
    return key_of("unraised", monitor)


def names_of(unraised: list | None) -> frozenset | None:
    """The kept unraised cases' names as `name` makes them (None: not kept)."""
    return None if unraised is None else frozenset(tuple(name) for name in unraised)


def name(todo: Todo) -> tuple | None:
    """What names a case nobody recorded (None: a recorded one, never skipped)."""
    t, _, pv, ep = todo
    if pv is not None or ep is None:
        return None
    return (t, anchor_key(pv, ep), ep.action)
