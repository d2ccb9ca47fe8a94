"""What a road user at a stop line can sense, measured from a tick of the world: no rule in it.

`Around` indexes one snapshot by junction, so that "who is approaching this junction" costs a
lookup, not a scan of every road user per vehicle. `Others.near(v)` is what a driver or a sensor
could notice about the road users at v's junction: their type, whether they are on the major road,
how soon they reach the junction. How that becomes sentences (and what a fault hides) is the
agents' (av.py, watchers.py); whether it matters is the rulebook's.
"""
from __future__ import annotations

from collections import defaultdict
from typing import NamedTuple

from sim_replay.sumo_net import Network
from sim_replay.world_state import Snapshot, VehicleState

__all__ = ["APPROACH_M", "Around", "Other", "STOPPED_MPS"]

APPROACH_M = 50.0        # a road user this close to a junction's entry, and moving towards it, is approaching
MOVING_MPS = 0.5
STOPPED_MPS = 0.1


class Other(NamedTuple):
    """A road user at or near a junction, as seen from one approaching it (a NamedTuple: a few
    hundred are made a tick, at a quarter of a frozen dataclass's cost)."""

    id: str
    type: str
    main_road: bool          # on an approach without a line where others have one (the major road)
    eta_s: float             # seconds until it reaches the junction at its speed (0: a pedestrian on a crossing)
    pedestrian: bool = False


class Around:
    """One snapshot's road users by the junction they approach or are in."""

    def __init__(self, snap: Snapshot, network: Network) -> None:
        self.snap = snap
        self._near: dict[str, list[Other]] = defaultdict(list)
        self._approach: dict[str, str | None] = {}
        for v in snap.vehicles:
            j = v.next_junction
            if (v.junction is not None or j is None or v.to_junction_m is None or v.to_junction_m > APPROACH_M
                    or v.speed_mps <= MOVING_MPS):
                continue          # inside a junction it is crossing, not approaching; far or still, not yet
            eta = v.to_junction_m / v.speed_mps
            junction = network.junctions.get(j)
            major = (junction is not None and junction.control in ("stop", "give_way")
                     and v.approach is not None and v.line_kind is None)
            self._near[j].append(Other(v.id, v.type, major, eta))
            self._approach[v.id] = v.approach
        for p in snap.pedestrians:
            if p.crossing is not None and p.junction is not None:     # on a crossing, not waiting at a corner
                self._near[p.junction].append(Other(p.id, "pedestrian", False, 0.0, True))

    def near(self, v: VehicleState) -> list[Other]:
        """The road users v could notice at the junction ahead (see `about`)."""
        return self.about(v.next_junction, v.id, v.approach) if v.next_junction is not None else []

    def about(self, junction: str | None, vid: str, approach: str | None) -> list[Other]:
        """The road users approaching a junction, as seen by vid on (or from) `approach`: not
        itself, not those behind it on its own approach (they follow it, they do not approach it).
        None (on no junction): nobody."""
        if junction is None:
            return []
        return [o for o in self._near.get(junction, ()) if o.id != vid
                and (o.pedestrian or self._approach.get(o.id) != approach)]
