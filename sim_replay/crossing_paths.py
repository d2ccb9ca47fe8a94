"""Pedestrians in a vehicle's path over a crossing, placed by SUMO's own shapes and positions.

SUMO's junction model makes every crossing that a junction lane runs over a foe of that lane
(`lane.getInternalFoes`), wherever on it the pedestrian is. A pedestrian at the far kerb, 5 m to
the side of the vehicle, who reaches the vehicle's way 3.4 s after it has gone, is "on a foe
crossing" as much as one who steps in front of it. Endangering needs more than that: the
pedestrian must be in the vehicle's path, or entering it, within a stated window of the vehicle
being there (issue 35). So a vehicle's passage is watched as SUMO's junction model watches a
crossing for it (MSLink::getLeaderInfo, MSPModel_Interacting::blockedAtDist):

- its path is the shape of the junction lanes it drives by (SUMO's: its junction lane and the ones
  it goes on by), as wide as the vehicle plus SUMO's pedestrian safety gap (MSPModel::SAFETY_GAP,
  1 m), which is how far to the side SUMO's model counts a pedestrian as blocking it;
- the conflict area is where that path runs over a crossing (the crossing's shape, as wide as SUMO
  makes it);
- the vehicle is in the conflict area while its body overlaps it: its front at its position, its
  length back along its heading, its width (SUMO's figures). A pedestrian is in it while its place
  does: its position, with half its width about it;
- the post-encroachment time (PET: from one road user leaving the conflict area to the other
  reaching it, 0 when both were in it at once; Allen, Shin and Cooper 1978) is measured tick by
  tick from those occupancies. A pedestrian is in the vehicle's path when both were in the area at
  once, or when it entered the area WINDOW_S or less after the vehicle left it (the vehicle passed
  just in front of it). WINDOW_S is the window SUMO's SSM device uses for a conflict by PET (its
  default threshold, 2 s). A pedestrian that had left the area before the vehicle came is past its
  path, however soon after: SUMO's junction model no longer counts a pedestrian completely past the
  vehicle's crossing point as blocking it (MSPModel_Interacting::blockedAtDist).

The pedestrians on a crossing in the HISTORY_S before the act are kept, so that one who was in the
vehicle's path before the act is measured as having been there first. A watch stays open until the
vehicle has left its way and WINDOW_S more have passed, or until LONGEST_S after the act. A right
turner waiting in the junction may reach the far crossing long after the act.
"""
from __future__ import annotations

import bisect
import math
import re
from collections import deque
from collections.abc import Iterable

import libsumo
from shapely.geometry import LineString, Point
from shapely.geometry.base import BaseGeometry
from shapely.ops import unary_union

from sim_replay.world_state import PedestrianState, VehicleState

__all__ = ["HISTORY_S", "LONGEST_S", "SAFETY_GAP_M", "WINDOW_S", "Geometry", "PathWatch", "Recent", "pet"]

WINDOW_S = 2.0          # PET at or under this is a conflict (SUMO's SSM device: its default PET threshold)
SAFETY_GAP_M = 1.0      # SUMO's MSPModel::SAFETY_GAP: added to a vehicle's width where pedestrians block it
HISTORY_S = WINDOW_S + 0.5   # pedestrians on crossings remembered this long before an act
LONGEST_S = 60.0        # a watch closes this long after its act whatever the vehicle does
_FLAT = 2               # shapely's flat cap: a path or a crossing ends where its shape ends
_CROSSING = re.compile(r"^:.+_c\d+_0$")     # SUMO's crossing lanes: ":<junction>_c<n>_0"

Found = tuple[str, str, float | None, float]   # (pedestrian, crossing, nearest m from the vehicle on its way, PET s)


def pet(mine: Iterable[float], theirs: Iterable[float]) -> tuple[float, str | None] | None:
    """The post-encroachment time between two road users' occupancies of one area, each given as
    the ticks (seconds) it was in it, and who was in it first: (0, None) where they share a tick,
    else the time from the first one's last tick there to the other's first (to the tick), with
    "mine" or "theirs". None where either never was in it. (Each occupies the area once in the
    watched stretch; a second visit is measured from the nearest ticks.)"""
    a, b = sorted(set(mine)), sorted(set(theirs))
    if not a or not b:
        return None
    best, first = math.inf, None
    for t in a:                  # the ticks of the other either side of this one
        i = bisect.bisect_left(b, t)
        if i < len(b) and b[i] == t:
            return 0.0, None
        for k in (i - 1, i):
            if 0 <= k < len(b) and abs(b[k] - t) < best:
                best, first = abs(b[k] - t), "mine" if t < b[k] else "theirs"
    return round(best, 2), first


class Geometry:
    """SUMO's shapes of junction lanes and crossings, asked once each in a run (one per World:
    two maps name their lanes alike)."""

    def __init__(self) -> None:
        self._lines: dict[str, LineString] = {}
        self._crossings: dict[str, BaseGeometry] = {}

    def line(self, lane: str) -> LineString:
        if lane not in self._lines:
            self._lines[lane] = LineString(libsumo.lane.getShape(lane))
        return self._lines[lane]

    def crossing(self, lane: str) -> BaseGeometry:
        """A crossing's area: its shape, as wide as SUMO makes the crossing."""
        if lane not in self._crossings:
            self._crossings[lane] = self.line(lane).buffer(libsumo.lane.getWidth(lane) / 2.0, cap_style=_FLAT)
        return self._crossings[lane]

    @staticmethod
    def way(v: VehicleState) -> tuple[str, ...]:
        """The junction lanes the vehicle drives by through the junction it is in or coming to:
        its junction lane (SUMO's next link's, where its front is not in the junction yet) and
        each one SUMO's links lead on to, up to the road out."""
        lane = v.lane if v.lane.startswith(":") else \
            next((link[4] for link in libsumo.vehicle.getNextLinks(v.id)[:1] if link[4]), "")
        way: list[str] = []
        while lane.startswith(":") and lane not in way and not _CROSSING.match(lane):
            way.append(lane)
            links = libsumo.lane.getLinks(lane)
            lane = (links[0][4] or links[0][0]) if links else ""
        return tuple(way)


class Recent:
    """The pedestrians on a crossing in the last HISTORY_S, tick by tick."""

    def __init__(self) -> None:
        self.ticks: deque[tuple[float, tuple[PedestrianState, ...]]] = deque()

    def tick(self, t: float, pedestrians: tuple[PedestrianState, ...]) -> None:
        self.ticks.append((t, tuple(p for p in pedestrians if p.crossing)))
        while self.ticks and self.ticks[0][0] < t - HISTORY_S:
            self.ticks.popleft()


class PathWatch:
    """One vehicle's passage through a junction, and the pedestrians on the crossings of its way."""

    def __init__(self, geometry: Geometry, v: VehicleState, t: float, recent: Recent | None = None) -> None:
        self.vehicle, self.since_s = v.id, t
        self.way = geometry.way(v)
        self.width, self.length = libsumo.vehicle.getWidth(v.id), libsumo.vehicle.getLength(v.id)
        self.areas: dict[str, BaseGeometry] = {}
        if self.way:
            path = unary_union([geometry.line(lane) for lane in self.way]).buffer(
                (self.width + SAFETY_GAP_M) / 2.0, cap_style=_FLAT)
            for lane in self.way:
                for foe in libsumo.lane.getInternalFoes(lane):
                    if _CROSSING.match(foe) and foe[:-2] not in self.areas:
                        area = path.intersection(geometry.crossing(foe))
                        if not area.is_empty:
                            self.areas[foe[:-2]] = area
        self.mine: dict[str, list[float]] = {}                     # crossing -> ticks the vehicle was in its area
        self.theirs: dict[tuple[str, str], list[float]] = {}       # (pedestrian, crossing) -> ticks it was
        self.nearest: dict[str, float] = {}
        self.left_s: float | None = None if self.way else t        # when the vehicle's back left its way
        self._on = False                                           # its front has been on its way
        self._radius: dict[str, float] = {}
        for when, pedestrians in (recent.ticks if recent is not None else ()):
            self._pedestrians(when, pedestrians, None)

    def tick(self, t: float, v: VehicleState | None, pedestrians: tuple[PedestrianState, ...]) -> None:
        """One tick: where the vehicle (None: it has left the map) and the pedestrians are."""
        if v is None:
            self.left_s = t if self.left_s is None else self.left_s
        elif self.left_s is None or t <= self.left_s:     # until its back is off its way
            if v.lane in self.way:
                self._on = True
            elif self._on and self.left_s is None and not v.lane.startswith(":"):
                self.left_s = t + self.length / max(v.speed_mps, 1.0)
            heading = math.radians(v.heading_deg)
            body = LineString([(v.x - self.length * math.cos(heading), v.y - self.length * math.sin(heading)),
                               (v.x, v.y)]).buffer(self.width / 2.0, cap_style=_FLAT)
            for crossing, area in self.areas.items():
                if body.intersects(area):
                    self.mine.setdefault(crossing, []).append(t)
        self._pedestrians(t, pedestrians, v if v is not None and (self.left_s is None or t <= self.left_s) else None)

    def _pedestrians(self, t: float, pedestrians: tuple[PedestrianState, ...], v: VehicleState | None) -> None:
        for p in pedestrians:
            crossing = p.crossing
            area = self.areas.get(crossing) if crossing else None
            if crossing is None or area is None:
                continue
            if v is not None:
                away = round(math.hypot(p.x - v.x, p.y - v.y), 1)
                self.nearest[p.id] = min(away, self.nearest.get(p.id, away))
            if p.id not in self._radius:
                try:
                    self._radius[p.id] = libsumo.person.getWidth(p.id) / 2.0
                except libsumo.TraCIException:
                    self._radius[p.id] = 0.24
            if Point(p.x, p.y).distance(area) <= self._radius[p.id]:
                self.theirs.setdefault((p.id, crossing), []).append(t)

    def open(self, t: float) -> bool:
        """Whether the watch still measures: the vehicle is on its way, or left it less than
        WINDOW_S ago, and the act is less than LONGEST_S old."""
        if t - self.since_s >= LONGEST_S:
            return False
        return self.left_s is None or t <= self.left_s + WINDOW_S

    def found(self) -> list[Found]:
        """The pedestrians in the vehicle's path within WINDOW_S: (who, crossing, nearest m from
        the vehicle while it was on its way, PET s), by name. In its path: in the conflict area
        with the vehicle at once, or entering it within WINDOW_S after the vehicle left (it passed
        just in front of the pedestrian). One that had left the area before the vehicle came is
        past its path, as SUMO's junction model has it: a pedestrian completely past the vehicle's
        crossing point no longer blocks it (MSPModel_Interacting::blockedAtDist)."""
        out: dict[str, Found] = {}
        for (who, crossing), ticks in self.theirs.items():
            measured = pet(self.mine.get(crossing, ()), ticks)
            if measured is None or measured[1] == "theirs" or measured[0] > WINDOW_S:
                continue
            if who not in out or measured[0] < out[who][3]:
                out[who] = (who, crossing, self.nearest.get(who), measured[0])
        return sorted(out.values())
