"""The state of a run at a time, as handed to the other rooms.

The fold (store/state.py) works on one plain dict, changed in place event after event and cached
as snapshots; what leaves the store is this frozen value, built once at the end of a read, so a
reader names the parts it uses (`state.entities`) and a typo fails at once instead of reading as
missing. The pieces inside stay the fold's JSON data: they are event data, each piece of state
{"src", "seq", "t", "body"} being the event it came from cut down to a citation and a body.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Mapping

Piece = dict[str, Any]
Ref = dict[str, Any]


@dataclass(frozen=True, slots=True)
class State:
    """What the record says the run was at time t: the fold of its events with t' <= t."""

    run: str
    """The run asked about."""
    t: int
    """The time asked about (ns since the epoch)."""
    events: int
    """How many of the run's events were folded (those with t' <= t), vehicle.trace included."""
    last: Ref | None
    """{src, seq, t} of the last event folded, in (t, seq, src) order; None before the first."""
    start: Piece | None
    """The run.start piece: map, seed, config and the rulebooks in force (name, version,
    sha256; their LE text is left out, it is in the cited event). None if not recorded yet."""
    end: Piece | None
    """The run.end piece, or None while the run goes on (or its end was not recorded)."""
    entities: dict[str, dict[str, Any]]
    """Per entity src: spawn, state, perception, decision (the latest piece of each kind), ads
    (the ADS status folded from the ads.event history, see state.ads_status) and despawned
    (the entity.despawn piece, None while present). A new entity.spawn starts a fresh record."""
    signals: dict[str, dict[str, dict[str, Any]]]
    """Per junction, per approach ("*" when the event names none): colour, since ({src, seq, t}
    of the report that first showed this colour) and last (the latest report's piece)."""
    monitors: dict[str, dict[str, dict[str, Piece]]]
    """Per monitor src: observations (per vehicle, the latest made within OBSERVATION_WINDOW_S
    before t) and potential_violations (per vehicle, the latest)."""
    collisions: dict[str, Piece]
    """Per entity id named in a collision: the latest collision piece naming it."""

    @classmethod
    def of(cls, run: str, t: int, folded: Mapping[str, Any]) -> State:
        """The state from the fold's dict (store.state.empty_state's keys)."""
        return cls(run, t, folded["events"], folded["last"], folded["start"], folded["end"],
                   folded["entities"], folded["signals"], folded["monitors"], folded["collisions"])

    @classmethod
    def from_json(cls, data: Mapping[str, Any]) -> State:
        """The state `to_json` gave."""
        return cls.of(data["run"], data["t"], data)

    def to_json(self) -> dict[str, Any]:
        """{"run", "t", then the fold's keys}: the state as plain JSON data."""
        return {"run": self.run, "t": self.t, "events": self.events, "last": self.last,
                "start": self.start, "end": self.end, "entities": self.entities,
                "signals": self.signals, "monitors": self.monitors, "collisions": self.collisions}
