"""Acts nobody recorded: where the measurements suggest one, a moment for the history to judge.

A monitor's rules raise a potential violation from the sentences it states (episodes.py). Some
acts are in no sentence a camera writes: a car rolling over a Stop line (nobody wrote "has not
stopped"), a car pulling out of a Give Way junction so that a main-road car brakes, a car
standing in a yellow box, a car crossing on red seen by a camera that writes positions and speeds
but no light. This module reads the same measurements (x, y, speed_mps of each observation, in
the run's order) and names the moments worth a history: the reasoner rebuilds the passage there
and asks the monitor rules on what it shows (investigation.py); most candidates come to nothing.

Which measurements: the monitors' (monitor.observation), already read for the episodes, and the
road users' own entity.state, swept apart (each in its own time order): an act is found in every
source that records it, and one only the vehicle's own record shows says so (model.Source). Candidates, per road
user and junction entry (first position inside the junction's area after EPISODE_GAP_S outside):

    stop line      entries at a Stop junction without a measurement below STILL_MPS since
                   APPROACH_S before (a stop at the line shows as one)
    give way       entries at a Give Way junction, or one the map gives a major road, within
                   FORCE_WINDOW_S of braking at FORCE_DECEL_MPS2 or harder by a road user on an
                   arm the map makes the major road or in the junction's area (where the map
                   does not say, "on the main road" cannot be derived, and no candidate could
                   come to anything); within WALKER_WINDOW_S of a pedestrian's own position in
                   the junction's area (a Stop kept at the line may still endanger one stepping
                   into the vehicle's path: para 1's "endanger any person"); and every such
                   entry where an arm of the major road is in no monitor's view: the traffic
                   there, braking or approaching, is only in its own record, which the history
                   reads and a sweep of the cameras' measurements cannot
    lights         entries at a signal junction whose measurement states no light for the road user
                   (a camera that states lights raises these acts from its sentences; an
                   entity.state states none)
    box            the first measurement standing still inside a yellow box
    speed limit    the first measurement of each stretch over the speed limit of the road it is
                   on, anywhere on the map (reasoner/stretches.py delimits the stretch: a
                   measurement over the limit more than STRETCH_GAP_S after the last starts another)

Every candidate is found in one pass with a few comparisons an observation, so the sweep costs
little beside reading the observations, and the histories run only where a candidate is.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any, Iterable

from .derived import FORCE_DECEL_MPS2
from .history import Junction, Map, sector
from .history import MPH_PER_MPS, STOPPED_MPS
from .stretches import STRETCH_GAP_S

SECOND = 1_000_000_000
EPISODE_GAP_S = 5.0       # inside the junction again after this long outside: a new entry
APPROACH_S = 15.0         # the approach to a Stop line looked at for a standstill
STILL_MPS = 1.0           # a measurement this slow may be a stop a 2 Hz camera caught the end of
FORCE_WINDOW_S = 6.0      # another road user's braking this close to an entry is looked at
WALKER_WINDOW_S = 2.0     # a pedestrian in the junction's area this close to an entry: derived.ENDANGER_S, the
                          # time window within which one in or entering the vehicle's path is endangered
MAX_CANDIDATES = 10_000   # bounded work for any input
ENTER = "enter the junction"
BOX = "enter the box junction"
SPEEDING = "exceed the speed limit"


@dataclass(frozen=True)
class Candidate:
    """A moment of a road user's passage to rebuild, and the event it was seen in."""

    user: str
    action: str
    junction: str
    event: dict
    why: str

    @property
    def t(self) -> int:
        return self.event["t"]


@dataclass
class _Track:
    inside_t: int | None = None       # the last measurement inside the junction's area
    slowest: float = math.inf         # slowest speed measured outside since the last entry
    since: int | None = None          # ... from this time
    boxed: bool = False               # already a box candidate on this entry
    last: tuple[int, float] | None = None
    approach: str | None = None       # where the last measurement outside was: the arm it comes from


@dataclass
class Sweep:
    """Feed events in (t, seq, src) order with `add`; `candidates()` after the last."""

    map: Map
    by_monitor: dict[str, Junction] = field(default_factory=dict)
    _tracks: dict[tuple[str, str], _Track] = field(default_factory=dict)
    _entries: list[tuple[Junction, str, dict, bool]] = field(default_factory=list)   # (j, user, event, forcing)
    _braking: dict[str, list[tuple[int, str]]] = field(default_factory=dict)           # junction -> (t, user)
    _walking: dict[str, list[tuple[int, str]]] = field(default_factory=dict)           # junction -> (t, pedestrian)
    _found: list[Candidate] = field(default_factory=list)

    def __post_init__(self) -> None:
        self.by_monitor = {m: j for j in self.map.junctions for m in j.monitors}
        self._wanted = {j.id for j in self.map.junctions
                        if j.control in ("stop", "give_way", "lights") or _minor_lines(j) or j.boxed or j.major}
        self._tracked = {j.id for j in self.map.junctions
                         if j.control in ("stop", "give_way") or _minor_lines(j) or j.boxed or j.major}
        self._inside: dict[tuple[str, str], int] = {}    # (junction, road user) -> last time inside
        limits = [r.limit_mph for r in self.map.roads if r.limit_mph is not None]
        self._slowest_limit_mps = min(limits) / MPH_PER_MPS if limits else math.inf
        self._speeding: dict[str, int] = {}          # road user -> last time over the limit
        self._by_src = {m: self._route(j) for m, j in self.by_monitor.items()}

    def _route(self, j: Junction) -> tuple[Junction, bool, float]:
        """What a measurement near this junction is looked at for, settled once per junction
        rather than once per measurement: (the junction, tracked (every measurement counts),
        the reach within which an entry at a junction where only entries count is looked for;
        -1 where none is)."""
        tracked = j.id in self._tracked
        return j, tracked, j.extent_m if j.id in self._wanted and not tracked else -1.0

    def add(self, event: dict) -> None:
        """One measurement; a few comparisons for most (this runs once per observation)."""
        body = event["body"]
        if type(body) is not dict or not (self._wanted or self._slowest_limit_mps < math.inf):
            return
        if event.get("kind") == "monitor.observation":
            user, route = body.get("vehicle"), self._by_src.get(event["src"])
        else:
            user, route = str(event.get("src", "")).split("/", 1)[-1], None
        x: Any = body.get("x")      # the values as read: their types are checked below
        y: Any = body.get("y")
        v: Any = body.get("speed_mps")
        if type(user) is not str or type(x) not in _NUMBER or type(y) not in _NUMBER or x - x or y - y:
            return      # (x - x is 0 for a finite number, NaN otherwise)
        if type(v) not in _NUMBER or v - v:
            v = None
        elif v > self._slowest_limit_mps:
            self._over_limit(user, event, x, y, v)      # on any road, near a junction or not
        if route is None:
            near = self.map.near(x, y, 100.0)
            if not near:
                return
            route = self._route(near[0])
        j, tracked, reach = route
        if tracked:
            self._measure(j, user, event, x, y, v)
        elif -reach <= x - j.x <= reach and -reach <= y - j.y <= reach and j.inside(x, y):
            self._inside_at(j, user, event)     # (only a measurement within reach on both axes can be inside)

    def _over_limit(self, user: str, event: dict, x: float, y: float, v: float) -> None:
        road = self.map.road(event["body"].get("road"), x, y)
        if road is None or road.limit_mph is None or v * MPH_PER_MPS < road.limit_mph + 0.5:
            return
        last = self._speeding.get(user)
        self._speeding[user] = event["t"]
        if last is None or event["t"] - last > STRETCH_GAP_S * SECOND:
            self._keep(Candidate(user, SPEEDING, road.id, event,
                                 f"{v * MPH_PER_MPS:.0f} mph on road {road.id}, limit {road.limit_mph:g} mph"))

    def _measure(self, j: Junction, user: str, event: dict, x: float, y: float, v: float | None) -> None:
        t = event["t"]
        track = self._tracks.get((j.id, user))
        if track is None:
            track = self._tracks[j.id, user] = _Track()
        inside = j.inside(x, y)
        if v is not None and track.last is not None and 0 < t - track.last[0] <= 2 * SECOND \
                and (track.last[1] - v) / ((t - track.last[0]) / SECOND) >= FORCE_DECEL_MPS2 \
                and (inside or j.is_major(sector(x - j.x, y - j.y))):
            self._braking.setdefault(j.id, []).append((t, user))      # on the major road, or in the junction
        if inside and str(event.get("src", "")).startswith("pedestrian/"):
            self._walking.setdefault(j.id, []).append((t, user))       # a pedestrian in the junction's area
        if v is not None:
            track.last = (t, v)
        if not inside:
            track.approach = sector(x - j.x, y - j.y)
            if track.since is None or t - track.since > APPROACH_S * SECOND:
                track.slowest, track.since = math.inf, t
            if v is not None:
                track.slowest = min(track.slowest, v)
            return
        entry = track.inside_t is None or t - track.inside_t > EPISODE_GAP_S * SECOND
        track.inside_t = t
        if entry:
            track.boxed = False
            self._entry(j, user, event, track)
        if j.boxed and not track.boxed and v is not None and v <= STOPPED_MPS and j.in_box(x, y):
            track.boxed = True
            self._keep(Candidate(user, BOX, j.id, event, "standing still inside the yellow box"))

    def _inside_at(self, j: Junction, user: str, event: dict) -> None:
        """A measurement inside a junction where only entries matter (a signal junction)."""
        key, t = (j.id, user), event["t"]
        last = self._inside.get(key)
        self._inside[key] = t
        if (last is None or t - last > EPISODE_GAP_S * SECOND) and not _states_light(event, user):
            self._keep(Candidate(user, ENTER, j.id, event, "entered a signal junction; no light stated with it"))

    def _entry(self, j: Junction, user: str, event: dict, track: _Track) -> None:
        """An entry, looked at for what the arm it came from asks (a junction may have a Stop
        arm, a Give Way arm and a major road)."""
        control = j.control_from(track.approach)
        if control == "stop" and track.slowest > STILL_MPS:
            slowest = "none measured" if track.slowest == math.inf else f"slowest {track.slowest:.1f} m/s"
            self._keep(Candidate(user, ENTER, j.id, event, f"entered a Stop junction ({slowest} on its approach)"))
        forcing = (control == "give_way" or bool(j.major)) and not j.is_major(track.approach)
        if forcing or control in ("stop", "give_way"):
            self._entries.append((j, user, event, forcing))     # forcing: main-road braking is looked at
        if control == "lights" and not _states_light(event, user):
            self._keep(Candidate(user, ENTER, j.id, event, "entered a signal junction; no light stated with it"))
        track.slowest, track.since = math.inf, None

    def _keep(self, candidate: Candidate) -> None:
        if len(self._found) < MAX_CANDIDATES:
            self._found.append(candidate)

    def candidates(self) -> list[Candidate]:
        """Every candidate, the give-way ones matched against the braking seen near them."""
        window = int(FORCE_WINDOW_S * SECOND)
        for j, user, event, forcing in self._entries:
            braked = [(t, u) for t, u in self._braking.get(j.id, ()) if u != user and abs(t - event["t"]) <= window]
            walked = [(t, u) for t, u in self._walking.get(j.id, ()) if abs(t - event["t"]) <= WALKER_WINDOW_S * SECOND]
            if forcing and braked:
                self._keep(Candidate(user, ENTER, j.id, event,
                                     f"entered {j.id} while {braked[0][1]} braked at {FORCE_DECEL_MPS2:g} m/s² or harder"))
            elif walked:
                self._keep(Candidate(user, ENTER, j.id, event,
                                     f"entered {j.id} while pedestrian {walked[0][1]} was in the junction"))
            elif forcing and j.major and j.major & j.unwatched:
                arms = " and ".join(sorted(j.major & j.unwatched))
                self._keep(Candidate(user, ENTER, j.id, event,
                                     f"entered {j.id} from a minor arm; its major road's {arms} arm is in no "
                                     "monitor's view, so that traffic is measured from its own record"))
        return sorted(self._found, key=lambda c: (c.t, c.event["src"], c.event["seq"]))


def sweep(events: Iterable[dict], map_: Map) -> list[Candidate]:
    found = Sweep(map_)
    for event in events:
        found.add(event)
    return found.candidates()


_NUMBER = (int, float)


def _minor_lines(j: Junction) -> bool:
    return any(j.control_from(line.approach) in ("stop", "give_way") for line in j.lines)


def _states_light(event: dict, user: str) -> bool:
    facts = event["body"].get("facts")
    return type(facts) is list and any(type(f) is str and f.startswith(user + " ") and " light" in f for f in facts)
