"""What the SUMO world says about one tick: the values that cross from the world to the agents.

Everything here is a measurement of the physics (where a road user is, how fast, what the light
facing an approach shows), never a judgement: whether a vehicle may enter a junction is the
rulebook's, asked by the agents. Positions are metres in the network's coordinates; headings are the
map's convention (degrees counter-clockwise from east, reasoner.junctions), not SUMO's compass angle;
a vehicle's position is its front bumper, so "past the stop line" means its front is.

A road user's state is a NamedTuple rather than a frozen dataclass: as immutable and as typed, and
built in a quarter of the time (a frozen dataclass sets each of its twenty-one fields through
object.__setattr__), which matters when a tick builds a thousand of them ten times a second.
"""
from __future__ import annotations

import math
from collections.abc import Iterator
from dataclasses import asdict, dataclass, field
from typing import Any, NamedTuple

__all__ = ["COLOURS", "Collision", "PedestrianState", "SignalState", "Snapshot", "VehicleState"]

CELL_M = 25.0  # the side of Snapshot.near's squares

# SUMO's signal characters as DESIGN's signal.state colours ('u' is SUMO's red-yellow: red and amber)
COLOURS = {"r": "red", "u": "red_amber", "y": "amber", "Y": "amber", "G": "green", "g": "green",
           "s": "red", "o": "off", "O": "off"}


class VehicleState(NamedTuple):
    """A vehicle (a bicycle too) at the end of a tick."""

    id: str
    type: str                    # sim_replay.road_users: car, ambulance, ..., cyclist
    x: float
    y: float
    heading_deg: float
    speed_mps: float
    accel_mps2: float
    road: str | None             # None inside a junction
    edge: str
    lane: str
    lane_pos_m: float            # front bumper, metres from the lane's start
    signals: int                 # SUMO's signal bits (indicators, brake lights, blue light ...)
    junction: str | None         # the junction it is in (past its stop line), else None
    next_junction: str | None    # the junction its lane leads to, None on a road out of the map
    approach: str | None         # its approach at next_junction
    to_junction_m: float | None  # metres from its front to the end of its lane (where the junction starts)
    to_line_m: float | None      # the same, where its approach has a stop line (None: no line, or none ahead)
    line_kind: str | None        # signal, stop, give_way: the line ahead
    light: str | None            # the colour facing its approach (signal junctions)
    controlled: bool             # its law-deciding is ours (SUMO's right of way and red lights are off)
    held: bool                   # held at its line by the world (World.hold)

    def to_json(self) -> dict[str, Any]:
        return self._asdict()


class PedestrianState(NamedTuple):
    """A person walking, at the end of a tick."""

    id: str
    x: float
    y: float
    heading_deg: float
    speed_mps: float
    edge: str                    # a pavement's edge, a walking area or a crossing (":j1_c3")
    junction: str | None         # the junction whose crossing or corner it is on
    crossing: str | None         # the crossing it is on, if any

    def to_json(self) -> dict[str, Any]:
        return self._asdict()


@dataclass(frozen=True, slots=True)
class SignalState:
    """The colour one approach (or one crossing) of a signal junction shows."""

    junction: str
    approach: str                # vehicle approach (compass), or the crossing's arm
    colour: str                  # red, red_amber, green, amber, off
    since_s: float               # simulation time it began showing this colour
    crossing: str | None = None  # set for a pedestrian crossing's signal

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True, slots=True)
class Collision:
    """Two road users in one place, as SUMO detected it (it keeps both: no teleporting)."""

    collider: str
    victim: str
    kind: str                    # SUMO's: collision, frontal, junction, sharedLane, ...
    lane: str
    pos_m: float

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


@dataclass(frozen=True, slots=True)
class Snapshot:
    """One tick of the world: every road user and signal, and what began or ended in it."""

    step: int
    t_s: float                             # simulation seconds since the start
    vehicles: tuple[VehicleState, ...]     # in SUMO's order (by id)
    pedestrians: tuple[PedestrianState, ...]
    signals: tuple[SignalState, ...]       # every approach and crossing of every signal junction
    changed: tuple[SignalState, ...]       # those whose colour changed in this tick (all, on the first)
    departed: tuple[str, ...]              # road users that entered the network in this tick
    arrived: tuple[str, ...]               # road users that left it
    collisions: tuple[Collision, ...]
    by_id: dict[str, VehicleState] = field(default_factory=dict, compare=False, repr=False)
    pedestrians_by_id: dict[str, PedestrianState] = field(default_factory=dict, compare=False, repr=False)
    _cells: dict[tuple[int, int], list[VehicleState]] = field(default_factory=dict, compare=False, repr=False)

    def near(self, x: float, y: float, within_m: float) -> Iterator[VehicleState]:
        """The vehicles in the squares of CELL_M about (x, y) that reach within_m of it (a superset of
        those within it): a question about one road user's neighbours then costs its neighbourhood,
        not the whole network, which at a thousand vehicles is the difference that matters. In no
        particular order."""
        cells = self._cells
        if not cells and self.vehicles:
            for v in self.vehicles:
                cells.setdefault((int(v.x // CELL_M), int(v.y // CELL_M)), []).append(v)
        reach = math.ceil(within_m / CELL_M)
        cx, cy = int(x // CELL_M), int(y // CELL_M)
        if (2 * reach + 1) ** 2 > len(cells):     # a wide reach (a camera's range): the occupied squares are fewer
            for (i, j), there in cells.items():
                if abs(i - cx) <= reach and abs(j - cy) <= reach:
                    yield from there
            return
        for i in range(cx - reach, cx + reach + 1):
            for j in range(cy - reach, cy + reach + 1):
                yield from cells.get((i, j), ())

    def vehicle(self, ident: str) -> VehicleState | None:
        """A vehicle by id (None where it is not on the network), without a search."""
        return self.by_id.get(ident) if self.by_id or not self.vehicles else \
            next((v for v in self.vehicles if v.id == ident), None)

    def pedestrian(self, ident: str) -> PedestrianState | None:
        return self.pedestrians_by_id.get(ident) if self.pedestrians_by_id or not self.pedestrians else \
            next((p for p in self.pedestrians if p.id == ident), None)

    def signal(self, junction: str, approach: str) -> SignalState | None:
        return next((s for s in self.signals if s.junction == junction and s.approach == approach
                     and s.crossing is None), None)

    def to_json(self) -> dict[str, Any]:
        return {"step": self.step, "t_s": self.t_s, "vehicles": [v.to_json() for v in self.vehicles],
                "pedestrians": [p.to_json() for p in self.pedestrians],
                "signals": [s.to_json() for s in self.signals], "changed": [s.to_json() for s in self.changed],
                "departed": list(self.departed), "arrived": list(self.arrived),
                "collisions": [c.to_json() for c in self.collisions]}
