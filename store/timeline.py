"""State at a series of rising times, for a reader that visits many moments of one run in order.

`state_at` answers one moment from the nearest snapshot. A reader going through a run's
incidents in time order asks for many moments, often close together: from one to the next it
is cheaper to fold the few events in between than to load a snapshot again. A Timeline does
that, and falls back to `state_at` when the next moment is further than MAX_STEP events ahead
or earlier than the last one. Each answer equals `state_at(store, run, t)` (tests check it).

The Timeline folds on in its own dict; an answer is a State over that dict, and before folding
on from a dict it has handed out, the Timeline copies the dict's containers (entities, signals,
monitors, collisions, each entity record and monitor), so that every State handed out stays as
it was. The pieces themselves are shared: the fold never changes a piece in place, it only
replaces it.
"""
from __future__ import annotations

from typing import Any

from .db import Store
from .sqlite_errors import translate_methods
from .state import CollectorPaused, fold_at, fold_rows, prune
from .state_value import State

MAX_STEP = 3_000    # events folded forward before a snapshot is the cheaper way (bench/incidents.py)
_CHUNK = 4096

_WHERE = "FROM events WHERE run = ? AND t <= ? AND (t, seq, src) > (?, ?, ?)"
_AFTER = f"SELECT src, seq, t, kind, event {_WHERE} ORDER BY t, seq, src"
# counted on the time index alone (it holds every column named), before any event is read
_HOW_FAR = f"SELECT count(*) FROM (SELECT 1 {_WHERE} LIMIT ?)"


@translate_methods     # it reads the store itself: its callers meet the store's errors, never sqlite3's
class Timeline:
    """The states of one run at rising times."""

    def __init__(self, store: Store, run: str) -> None:
        self.store, self.run = store, run
        self._state: dict[str, Any] | None = None
        self._lent = False          # a State handed out shares the containers of self._state
        self._t = 0
        self.jumps = self.steps = 0

    def at(self, t: int) -> State:
        state = self._state
        if state is None or t < self._t or state["last"] is None or not self._near(state, t):
            self.jumps += 1
            with CollectorPaused():
                state = self._state = fold_at(self.store, self.run, t)
        else:
            self.steps += 1
            if self._lent:
                state = self._state = _detached(state)
            self._step(state, t)
            prune(state, t)
        self._t, self._lent = t, True
        return State.of(self.run, t, state)

    def _near(self, state: dict[str, Any], t: int) -> bool:
        """Whether at most MAX_STEP events lie between the state's last one and t."""
        (ahead,) = self.store.connection.execute(_HOW_FAR, (*self._where(state, t), MAX_STEP + 1)).fetchone()
        return ahead <= MAX_STEP

    def _step(self, state: dict[str, Any], t: int) -> None:
        """Fold the events after the state's last one up to t."""
        cursor = self.store.connection.execute(_AFTER, self._where(state, t))
        for rows in iter(lambda: cursor.fetchmany(_CHUNK), []):
            fold_rows(state, rows)

    def _where(self, state: dict[str, Any], t: int) -> tuple:
        last = state["last"]
        return (self.run, t, last["t"], last["seq"], last["src"])


def _detached(state: dict[str, Any]) -> dict[str, Any]:
    """A copy of the fold's dict that the fold can change without changing a State handed out
    before: every container the fold changes in place is copied (records and monitors are
    changed in place; pieces, signal approaches and ADS statuses are only ever replaced).
    Copied only when the Timeline folds on after handing a State out: most moments of a long
    run are reached by a jump to a snapshot, whose dict is new anyway."""
    monitors = {src: {part: dict(held) for part, held in monitor.items()}
                for src, monitor in state["monitors"].items()}
    return {**state,
            "entities": {src: dict(record) for src, record in state["entities"].items()},
            "signals": {junction: dict(approaches) for junction, approaches in state["signals"].items()},
            "monitors": monitors,
            "collisions": dict(state["collisions"])}
