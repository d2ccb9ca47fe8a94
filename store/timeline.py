"""State at a series of rising times, for a reader that visits many moments of one run in order.

`state_at` answers one moment from the nearest snapshot. A reader going through a run's
incidents in time order asks for many moments, often close together: from one to the next it
is cheaper to fold the few events in between than to load a snapshot again. A Timeline does
that, and falls back to `state_at` when the next moment is further than MAX_STEP events ahead
or earlier than the last one. Each answer equals `state_at(store, run, t)` (tests check it).

The state handed out is the Timeline's own and changes on the next call: a caller keeps what it
needs (the pieces of state are never changed in place, only replaced, so keeping those is safe).
"""
from __future__ import annotations

from typing import Any

from .db import Store
from .state import fold_rows, prune, state_at

MAX_STEP = 3_000    # events folded forward before a snapshot is the cheaper way (bench/incidents.py)
_CHUNK = 4096

_WHERE = "FROM events WHERE run = ? AND t <= ? AND (t, seq, src) > (?, ?, ?)"
_AFTER = f"SELECT src, seq, t, kind, event {_WHERE} ORDER BY t, seq, src"
# counted on the time index alone (it holds every column named), before any event is read
_HOW_FAR = f"SELECT count(*) FROM (SELECT 1 {_WHERE} LIMIT ?)"


class Timeline:
    """The states of one run at rising times."""

    def __init__(self, store: Store, run: str) -> None:
        self.store, self.run = store, run
        self._state: dict[str, Any] | None = None
        self.jumps = self.steps = 0

    def at(self, t: int) -> dict[str, Any]:
        state = self._state
        if state is None or t < state["t"] or state["last"] is None or not self._step(state, t):
            self.jumps += 1
            state = self._state = state_at(self.store, self.run, t)
        else:
            self.steps += 1
            prune(state, t)
        state["t"] = t
        return state

    def _step(self, state: dict[str, Any], t: int) -> bool:
        """Fold the events after the state's last one up to t; False if there are too many."""
        last = state["last"]
        conn = self.store.connection
        where = (self.run, t, last["t"], last["seq"], last["src"])
        (ahead,) = conn.execute(_HOW_FAR, (*where, MAX_STEP + 1)).fetchone()
        if ahead > MAX_STEP:
            return False
        cursor = conn.execute(_AFTER, where)
        for rows in iter(lambda: cursor.fetchmany(_CHUNK), []):
            fold_rows(state, rows)
        return True
