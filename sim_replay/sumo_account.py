"""SUMO's own account of who braked for whom: the ground truth's yields and conflicts.

The witness (sim_replay/witness.py) measures acts from the world; this module asks SUMO itself,
never the reasoner's code, why a road user slowed down, so that tests can hold the reasoner's
"forced" and "endangered" against an account it did not write (DESIGN "Simulation", issue 35).

Yields. Each tick, every vehicle decelerating at BRAKING_MPS2 or harder near a junction is asked
about with SUMO's own calls: its leader (`vehicle.getLeader`), its next traffic light
(`getNextTLS`), the junction foes on its way with SUMO's right-of-way answer for each pair
(`getJunctionFoes`: egoResponse, the foe matrix of the junction), the stop it is held at (the
world's hold is a SUMO stop), the vehicles ahead of it that left by the same incoming lane and
went another way, where SUMO's junction model still follows them (`lane.getInternalFoes`: a foe
lane of the same source; `getLeader` names one leader only), the speed of the junction lane it
turns by (`getNextLinks`), the minor links ahead of it (`lane.getLinks`) and the speed it may
drive at all (`getAllowedSpeed`:
its speed factor on its lane). SUMO's car-following model then says what speed each of those
constraints allows now (`getFollowSpeed` behind the leader, `getStopSpeed` before a red light, a
held stop line or a foe it must let pass, braking at its own deceleration down to a turn's
speed), and its junction model what it allows for a vehicle already in the junction across its
way (MSVehicle::adaptToJunctionLeader at MSLink::getLeaderInfo's gap: followed, or, with no room
left, stopped for at the line or the internal junction before their ways meet) and for a minor
link it cannot yet see the foes of (its cautious approach, stopping speed until within the
link's foe visibility distance: "link", its own control); each one allowing
less than the speed the vehicle braked from in the tick is one it braked for, and the slowing it
asked for in the tick (the speed braked from less the speed it allows, no more than the vehicle
shed) is counted to it. Two at once (its own turn and a foe crossing) each count: either alone
would have made it brake. Constraints SUMO was told to disregard for the vehicle (its speed mode:
red lights and right of way are off while the vehicle's decisions are the agents') are not
asked. A foe coming from the lane the vehicle comes by (turning off another way at the junction)
is followed as a leader, as SUMO's junction model does, not let pass as a foe. A run of such
ticks is one `Yield`, with each cause it had: its hardest tick under it, and the speed shed under
it held over a second (HELD_S: the way the 2 m/s² threshold of a considerable change of speed is
stated; a one-tick peak of 4.5 m/s² sheds 0.45 m/s).

Conflicts. With `ssm_options` SUMO's SSM device logs each encounter of two vehicles within
SSM_RANGE_M whose time to collision, deceleration to avoid a crash or post-encroachment time
crosses SUMO's default thresholds (TTC 3 s, DRAC 3 m/s², PET 2 s), classified with the junctions'
right-of-way foe matrix (crossing, merging, following); `read_ssm` reads its file after the run.

Pedestrians are not in SUMO's vehicle calls: a braking vehicle is asked about those on a crossing
that SUMO's junction model makes a foe of its junction lane (`lane.getInternalFoes`), or on the
corner about to step onto one (`person.getNextEdge`). Which pedestrians were in a crossing
vehicle's path (not merely on a crossing of its lane) is sim_replay/crossing_paths.py's.
"""
from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import libsumo
from shapely.geometry import LineString
from shapely.ops import unary_union

from sim_replay.world_state import PedestrianState, Snapshot, VehicleState

__all__ = ["BRAKING_MPS2", "COMING_S", "ENCOUNTERS", "SSM_RANGE_M", "VISIBILITY_M", "Account", "Yield", "read_ssm",
           "ssm_options"]

BRAKING_MPS2 = 0.5       # decelerating at least this hard is braking (below: coasting, SUMO's own dawdle)
NEAR_M = 80.0            # a vehicle this close to its next junction (or in one) is asked why it brakes
LOOK_M = 80.0            # how far ahead SUMO is asked for the leader and junction foes
SSM_RANGE_M = 50.0       # SSM device: vehicles this close are traced for conflicts
HELD_S = 1.0             # a braking's strength is the speed shed under one cause over a second (2 m/s² held
                         # over a second, as the threshold of a considerable change of speed is stated: Hupfer
                         # 1997; the reasoner averages over the same span, reasoner.motion.MIN_DECEL_SPAN_S)
COMING_S = 4.0          # in a junction, a foe this many seconds from entering it at its speed is one to wait for
                         # (not one standing, held at its line, or bound to stop at its Stop sign first: _coming)
_OVER_MPS = 0.05         # a vehicle this much over the speed it may drive is slowing down to it
_CLEAR_M = 5.0           # in a junction, a foe this far off (centre to front) is where its path is blocked
_RED = set("rRyYu")      # SUMO's link states a vehicle that obeys signals stops for (red, amber, red-amber)
_OBEYS_RED = 16          # SUMO's speed-mode bits (sim_replay/sumo_world.py)
_OBEYS_FOES = 8
_OWN = {"signal", "line", "turn", "speed", "link"}   # a vehicle's own control: its light, its line, its turn, its
                                                     # speed, its cautious approach to a minor link
_REACH_EPS_MPS = 1e-3    # a constraint allowing what the vehicle can reach in a tick, less this, allows it all
_STOOD_MPS = 0.1         # SUMO's halting speed: slower is standing
_AT_LINE_M = 3.0          # ... this close to the end of its lane: at its line
_STOP_LINK = "s"          # SUMO's link state for a Stop sign: a vehicle obeying it stands at the line before it goes
VISIBILITY_M = 4.5        # SUMO's foe visibility distance of a link (the default: neither bundled net sets one): short of
                          # it, a vehicle cannot yet see whether foes come, and approaches a minor link so that it can stop
_POSITION_EPS_M = 0.1     # SUMO's POSITION_EPS: where it stops a vehicle short of the next lane (MSVehicle::adaptToJunctionLeader)
_PART_STEP_M = 0.05       # the step along a junction lane at which where it parts from another is looked for
_NOT_MINOR = set("rRyYu")  # link states a minor link's cautious approach is not asked for (the light's, asked as `signal`)

# SUMO's SSM encounter types (MSDevice_SSM.h EncounterType), as its output's `type` codes
ENCOUNTERS = {0: "no conflict ahead", 1: "following", 2: "following (ego follows)", 3: "following (ego leads)",
              4: "on adjacent lanes", 5: "merging", 6: "merging (ego first)", 7: "merging (foe first)",
              8: "merging adjacent", 9: "crossing", 10: "crossing (ego first)", 11: "crossing (foe first)",
              12: "ego entered the conflict area", 13: "foe entered the conflict area",
              14: "ego left the conflict area", 15: "foe left the conflict area",
              16: "both entered the conflict area", 17: "both left the conflict area",
              18: "following passed", 19: "merging passed", 20: "oncoming", 111: "collision"}


def ssm_options(path: str | Path) -> list[str]:
    """SUMO options equipping every vehicle with an SSM device writing into one file."""
    return ["--device.ssm.probability", "1", "--device.ssm.deterministic", "true",
            "--device.ssm.measures", "TTC DRAC PET", "--device.ssm.range", repr(SSM_RANGE_M),
            "--device.ssm.file", str(path)]


def read_ssm(path: str | Path) -> list[dict[str, Any]]:
    """The SSM device's conflicts: ego, foe, begin, end and each measure's extreme (time, value,
    where, SUMO's encounter type), NA left out."""
    path = Path(path)
    if not path.is_file() or path.stat().st_size == 0:
        return []
    out = []
    for c in ET.parse(path).getroot().iter("conflict"):
        row: dict[str, Any] = {"ego": c.get("ego"), "foe": c.get("foe"), "begin_s": float(c.attrib["begin"]),
                               "end_s": float(c.attrib["end"])}
        for m in c:
            if m.get("value") in (None, "NA"):
                continue
            kind = m.get("type")
            code = int(kind) if kind is not None and kind != "NA" else None
            row[m.tag] = {"t_s": float(m.attrib["time"]), "value": float(m.attrib["value"]),
                          "x_y": [float(p) for p in m.attrib["position"].split(",")],
                          "type": ENCOUNTERS.get(code, str(code)) if code is not None else str(code)}
        out.append(row)
    return sorted(out, key=lambda r: (r["begin_s"], r["ego"], r["foe"]))


@dataclass
class Yield:
    """One stretch of braking by one vehicle, with SUMO's causes for it.

    cause: "foe" (a vehicle crossing or joining its way at the junction: it must let it pass
    (SUMO's right of way) or it is already in its path), "leader" (the vehicle ahead in its lane;
    `merged`: the leader joined its road at the junction from another arm), "signal" (its own light
    red or amber), "line" (held at its own Stop or Give Way line), "turn" (slowing to the speed of
    the junction lane it turns by), "pedestrian" (on or stepping onto a crossing of its path),
    "speed" (its own speed: factor, limit), "link" (SUMO's cautious approach to a minor link
    whose foes it cannot yet see: its own control), or "none" (none of these binds)."""

    vehicle: str
    t_s: float
    until_s: float
    junction: str | None
    lane: str
    speed_mps: float                 # when it began to brake
    min_speed_mps: float
    peak_decel_mps2: float
    cause: str                       # the cause it braked hardest under ("none" only if it had no other)
    by: str | None
    causes: dict[str, dict[str, Any]] = field(default_factory=dict)   # "foe 134" -> {t_s, decel, min speed, ...}
    _shed: list[tuple[float, float, str]] = field(default_factory=list, repr=False)   # (t, m/s shed, cause) a tick

    def held(self, t: float, drop: float, key: str) -> float:
        """The speed shed under `key` over the HELD_S up to t (this tick's `drop` with it), per
        second: how hard it braked for that cause held over a second. A one-tick peak of 4.5 m/s²
        sheds 0.45 m/s, which is 0.45 m/s² held; a stretch shorter than HELD_S counts over HELD_S."""
        self._shed.append((t, drop, key))
        while self._shed and self._shed[0][0] <= t - HELD_S + 1e-6:
            self._shed.pop(0)
        return round(sum(d for _, d, k in self._shed if k == key) / HELD_S, 2)

    def record(self, t: float, before: float, speed: float, step_s: float,
               binding: list[tuple[float, str, str | None, dict[str, Any]]]) -> None:
        """One tick of this braking, from `before` to `speed` over `step_s`, under the constraints
        SUMO's model says bind (Account._why): each cause's share (`shares`), its hardest tick and
        its share held over a second; and, for a road user that is a foe or a merged leader of
        the vehicle, what it made the vehicle shed under any of its causes held over a second
        (`road_user_held_mps2` on each of those causes)."""
        drop = before - speed
        sheds = shares(binding, before, drop)
        for (_, cause, by, detail), shed in zip(binding, sheds):
            decel = round(shed / step_s, 2)
            key = f"{cause} {by}" if by else cause
            seen = self.causes.setdefault(key, {"t_s": t, "decel_mps2": 0.0, "min_speed_mps": round(before, 2),
                                                "from_mps": round(before, 2), "held_mps2": 0.0, **detail})
            if shed > 0:                    # speeds under it: only where it asked for slowing
                if seen["decel_mps2"] == 0.0:
                    seen["from_mps"] = round(before, 2)
                seen["min_speed_mps"] = round(min(seen["min_speed_mps"], speed), 2)
            seen["decel_mps2"] = max(seen["decel_mps2"], decel)
            seen["until_s"] = t
            seen["held_mps2"] = max(seen["held_mps2"], self.held(t, shed, key))
            if cause != "none" and (self.cause == "none" or decel >= self.causes[f"{self.cause} {self.by}" if self.by
                                                                                 else self.cause]["decel_mps2"]):
                self.cause, self.by = cause, by
        for by, shed in by_road_user(binding, sheds).items():
            # one road user under several causes in one braking (a foe crossing its way, then the
            # leader it became on its road): SUMO's model keeps one speed, so one cause, held as one
            held = self.held(t, shed, f"road user {by}")
            for key, seen in self.causes.items():
                cause, _, who = key.partition(" ")
                if who == by and (cause == "foe" or (cause == "leader" and seen.get("merged"))):
                    seen["road_user_held_mps2"] = max(seen.get("road_user_held_mps2", 0.0), held)

    def to_json(self) -> dict[str, Any]:
        return {"vehicle": self.vehicle, "t_s": self.t_s, "until_s": self.until_s, "junction": self.junction,
                "lane": self.lane, "speed_mps": round(self.speed_mps, 2), "min_speed_mps": round(self.min_speed_mps, 2),
                "peak_decel_mps2": round(self.peak_decel_mps2, 2), "cause": self.cause, "by": self.by,
                "causes": self.causes}


class Account:
    """Asks SUMO, tick by tick, why each braking vehicle brakes; `yields` when closed."""

    def __init__(self, routes: dict[str, tuple[str, ...]], modes: dict[str, int]) -> None:
        self.routes = routes                       # vehicle -> its route's edges (the agents')
        self.modes = modes                         # vehicle -> its speed mode where not SUMO's default
        self.yields: list[Yield] = []
        self._open: dict[str, Yield] = {}
        self._last_t: float | None = None
        self._source: dict[str, str] | None = None     # junction lane -> the incoming lane it leaves from
        self._stood: set[tuple[str, str | None]] = set()   # (vehicle, junction) it has stood at the Stop line of
        self._asked: dict[str, list] = {}     # vehicle -> what binds its next tick, asked at the end of this one
        self._parts: dict[tuple[str, str, float], float] = {}   # (junction lane, one parting from it, half width) -> m
        self._before: dict[str, tuple[str, ...]] | None = None    # junction lane -> the junction lanes before it

    def tick(self, snap: Snapshot) -> None:
        t = snap.t_s
        self.step_s = t - self._last_t if self._last_t is not None and t > self._last_t else 0.1
        self._last_t = t
        braking = set()
        asked, self._asked = self._asked, {}
        for v in snap.vehicles:
            if v.speed_mps < _STOOD_MPS and v.to_junction_m is not None and v.to_junction_m < _AT_LINE_M \
                    and not v.lane.startswith(":"):
                self._stood.add((v.id, v.next_junction))       # it has stood at its line: SUMO lets it go
            if v.accel_mps2 > -BRAKING_MPS2 or not _near(v):
                continue
            braking.add(v.id)
            before = v.speed_mps - v.accel_mps2 * self.step_s     # the speed it braked from in this tick
            y = self._open.get(v.id)
            if y is None:
                y = self._open[v.id] = Yield(v.id, t, t, v.junction or v.next_junction, v.lane,
                                             before, v.speed_mps, 0.0, "none", None)
            y.until_s, y.min_speed_mps = t, min(y.min_speed_mps, v.speed_mps)
            y.peak_decel_mps2 = max(y.peak_decel_mps2, round(-v.accel_mps2, 2))
            # SUMO chose this tick's speed on the state at the end of the last (its planMove): what
            # bound it then is what this tick's braking was for; the first tick of a braking, when
            # it was not asked, is read from the state at its end
            binding = asked.get(v.id) or self._why(v, snap, before)
            y.record(t, before, v.speed_mps, self.step_s, binding)
            self._asked[v.id] = self._why(v, snap, math.inf)
        for ident in [i for i in self._open if i not in braking]:
            self.yields.append(self._open.pop(ident))

    def close(self) -> None:
        self.yields.extend(self._open.values())
        self._open.clear()
        self.yields.sort(key=lambda y: (y.t_s, y.vehicle))

    # --- SUMO's account of one braking vehicle ------------------------------------------------

    def _why(self, v: VehicleState, snap: Snapshot,
             before: float) -> list[tuple[float, str, str | None, dict[str, Any]]]:
        """The constraints SUMO's car-following model gives the vehicle on the state at the end of a
        tick (the state its next tick's speed is chosen on): each holding it under what it can
        reach in a tick (`_reach`), and, for a first tick read from its own end, under `before`,
        the speed it braked from; with the speed it allows, lowest first. One allowing as much (a
        leader far ahead at its own speed) is no constraint it braked for. None binding: "none".
        SUMO stops a vehicle somewhat short of the points asked here (a red light's 1.0 m, below),
        so a stop it brakes to at its full deceleration allows about its speed: holding it under
        its reach is binding, as SUMO's model takes it."""
        ident, speed = v.id, v.speed_mps
        mode = self.modes.get(ident, 31)
        vehicle = libsumo.vehicle
        allowed: list[tuple[float, str, str | None, dict[str, Any]]] = []
        limit = vehicle.getAllowedSpeed(ident)
        if limit < speed - _OVER_MPS:            # only over its own speed does that speed make it slow down
            allowed.append((limit, "speed", None, {"allowed_mps": round(limit, 2)}))
        inside = v.lane.startswith(":")
        ahead_m = libsumo.lane.getLength(v.lane) - v.lane_pos_m if inside else v.to_junction_m
        # a vehicle not yet in the junction is a foe to wait for only at a link still to pass where
        # SUMO's junction model asks whether foes come (MSLink::opened): the entry link, or in the
        # junction the internal junction of its way still ahead (a turn's waiting point). Past it, or
        # with none, the vehicle has been let through; what it meets in the junction is a link leader
        # (below), and the ones coming wait for it: the town-11 run's 293, past j10's internal
        # junction, braked for its exit link alone (its speeds the same, tick for tick, with 458
        # coming 51 m off taken away), and 185, past j17's, the same without 511 coming 32 m off
        link_to_pass = not inside or self._internal_junction(v.lane) is not None
        link = vehicle.getNextLinks(ident)[:1] if not inside else ()
        via = v.lane if inside else next((lk[4] for lk in link), "")
        link_state = next((lk[5] for lk in link), "")
        leader = vehicle.getLeader(ident, LOOK_M)
        if leader and leader[0]:
            other = snap.vehicle(leader[0])
            gap = max(leader[1], 0.0)
            if other is not None and other.lane.startswith(":") and via and other.lane != via \
                    and other.lane in libsumo.lane.getInternalFoes(via) and not self._same_source(via, other.lane):
                # SUMO's leader across its path in the junction (a link leader, MSLink::getLeaderInfo's gap):
                # SUMO's junction model follows it (MSVehicle::adaptToJunctionLeader), below
                # (no room left, SUMO's gap below 0, `getLeader` gives as 0: held at its line, or, already
                # in the junction, stopped as soon as it can, as the paper's 236 braked at 9 m/s² for 182)
                room = gap if leader[1] > 0 else -1.0
                allowed.append((self._junction_leader(ident, speed, room, other, via,
                                                      line_m=0.0 if inside else v.to_junction_m), "foe", leader[0],
                                {"gap_m": round(gap, 1), "foe_lane": other.lane, "foe_in_junction": True}))
            else:
                lv = other.speed_mps if other is not None else vehicle.getSpeed(leader[0])
                allowed.append((vehicle.getFollowSpeed(ident, speed, gap, lv, vehicle.getDecel(leader[0]), leader[0]),
                                "leader", leader[0], {"gap_m": round(gap, 1), "leader_speed_mps": round(lv, 2),
                                                      **_joined(self._merged(ident, leader[0]))}))
        for other, gap in self._parting(v, snap, via, ahead_m, leader[0] if leader else None):
            allowed.append((vehicle.getFollowSpeed(ident, speed, max(gap, 0.0), other.speed_mps, vehicle.getDecel(other.id),
                                                   other.id), "leader", other.id,
                            {"gap_m": round(gap, 1), "leader_speed_mps": round(other.speed_mps, 2), "leader_lane": other.lane,
                             "merged": False, "diverging": True}))
        if v.held and v.to_line_m is not None:
            allowed.append((vehicle.getStopSpeed(ident, speed, max(v.to_line_m, 0.0)), "line", None,
                            {"to_line_m": round(v.to_line_m, 1), "line": v.line_kind}))
        elif mode & _OBEYS_FOES and not inside and v.to_junction_m is not None and link_state == _STOP_LINK \
                and (ident, v.next_junction) not in self._stood:
            allowed.append((vehicle.getStopSpeed(ident, speed, max(v.to_junction_m, 0.0)), "line", None,
                            {"to_line_m": round(v.to_junction_m, 1), "line": "stop (SUMO's link)"}))
        if mode & _OBEYS_RED:
            for tls, _, dist, state in vehicle.getNextTLS(ident)[:1]:
                if state in _RED and dist <= LOOK_M:
                    allowed.append((vehicle.getStopSpeed(ident, speed, max(dist, 0.0)), "signal", None,
                                    {"tls": tls, "state": state, "to_line_m": round(dist, 1)}))
        minor = self._minor_link(v, via, ahead_m) if mode & _OBEYS_FOES and via and ahead_m is not None else None
        if minor is not None:
            allowed.append(minor)
        if via and ahead_m is not None and not inside:
            turn = libsumo.lane.getMaxSpeed(via)
            allowed.append((math.sqrt(turn * turn + 2.0 * vehicle.getDecel(ident) * max(ahead_m, 0.0)), "turn",
                            None, {"via": via, "turn_speed_mps": round(turn, 2)}))
        waiting: list[tuple[float, float, str, dict[str, Any]]] = []
        for foe in vehicle.getJunctionFoes(ident, LOOK_M):
            other_id, ego_dist, foe_dist, _, foe_exit, ego_lane, foe_lane, must_yield, _ = foe
            other = snap.vehicle(other_id)
            if foe_exit + vehicle.getLength(other_id) < 0:
                continue                     # its back has left the conflict area: no longer in the way
            entered = other is not None and other.lane.startswith(":") and foe_dist < ego_dist + 5.0
            if (must_yield and mode & _OBEYS_FOES) or entered:
                gap = v.to_junction_m if must_yield and not entered and v.to_junction_m is not None else ego_dist
                detail = {"ego_to_conflict_m": round(ego_dist, 1), "foe_to_conflict_m": round(foe_dist, 1),
                          "must_yield": bool(must_yield), "foe_in_junction": entered}
                if self._same_source(ego_lane, foe_lane):
                    # from the lane it comes by, ahead of it and turning off another way: SUMO's
                    # junction model follows such a foe as a leader (its SSM device: "following")
                    allowed.append((vehicle.getStopSpeed(ident, speed, max(gap - 1.0, 0.0)), "leader", other_id,
                                    {**detail, "merged": False, "diverging": True}))
                    continue
                if must_yield and not entered:      # one it must let pass, still coming: within COMING_S
                    if not link_to_pass:
                        continue
                    arrives = foe_dist / max(other.speed_mps if other is not None else 0.0, 0.1)
                    if arrives <= COMING_S:         # (SUMO lists all that cross its link, one 480 m off too)
                        waits = self._to_internal_junction(v, via, ahead_m, ego_lane)   # held at it, if any
                        stop_m = waits - _POSITION_EPS_M if waits is not None else gap - 1.0
                        waiting.append((arrives, vehicle.getStopSpeed(ident, speed, max(stop_m, 0.0)),
                                        other_id, {**detail, "foe_arrives_s": round(arrives, 1)}))
                    continue
                # a foe already in its path: SUMO's junction leader (MSVehicle::adaptToJunctionLeader)
                waits = self._to_internal_junction(v, via, ahead_m, ego_lane)
                if waits is not None:
                    # its way crosses the foe's beyond the internal junction it comes to (a turn across
                    # oncoming traffic): SUMO holds it there (MSLink's CONFLICT_STOP_AT_INTERNAL_JUNCTION,
                    # adaptToJunctionLeader's stop before the next lane), not short of the crossing point
                    allowed.append((vehicle.getStopSpeed(ident, speed, max(waits - _POSITION_EPS_M, 0.0)), "foe",
                                    other_id, {**detail, "to_internal_junction_m": round(waits, 1)}))
                    continue
                assert other is not None    # entered (a foe still coming, not entered, was waited for above)
                # SUMO's gap to a link leader across its path (MSLink::getLeaderInfo): to the crossing
                # point less its minGap, the part of the foe still before it and the crossing's width
                sumo_gap = ego_dist - vehicle.getMinGap(ident) - (foe_exit + vehicle.getLength(other_id))
                line_m = v.to_junction_m if not inside and ego_lane == via else 0.0 if ego_lane == v.lane else None
                speed_allowed = self._junction_leader(ident, speed, sumo_gap, other, via, ego_dist, line_m)
                if must_yield and mode & _OBEYS_FOES and not inside and v.to_junction_m is not None \
                        and self._entering(other.lane):
                    # one it must let pass, still on the junction lane it came in by (approaching its
                    # link, as SUMO's junction keeps it): the vehicle's link is not open (MSLink::opened),
                    # and SUMO holds it at its line (vLinkWait) as well as behind the leader
                    speed_allowed = min(speed_allowed, vehicle.getStopSpeed(
                        ident, speed, max(v.to_junction_m - _POSITION_EPS_M, 0.0)))
                allowed.append((speed_allowed, "foe", other_id, {**detail, "sumo_gap_m": round(sumo_gap, 1)}))
        if waiting:     # of the foes it must let pass, it waits for the first to come; the others after it
            arrives, stop, other_id, detail = min(waiting, key=lambda w: w[0])
            allowed.append((stop, "foe", other_id, detail))
        if inside:                   # in the junction: vehicles on the lanes SUMO makes foes of its own,
            assert ahead_m is not None                            # (in it, metres to its lane's end)
            foes = set(libsumo.lane.getInternalFoes(v.lane))      # or about to drive onto one
            junction = v.lane[1:].rsplit("_", 2)[0]
            for other in snap.vehicles:
                if other.lane in foes and not self._same_source(v.lane, other.lane):
                    away = math.hypot(other.x - v.x, other.y - v.y)
                    allowed.append((vehicle.getStopSpeed(ident, speed, max(away - _CLEAR_M, 0.0)), "foe", other.id,
                                    {"foe_lane": other.lane, "away_m": round(away, 1), "foe_in_junction": True}))
                elif link_to_pass and other.next_junction == junction and not other.lane.startswith(":") \
                        and other.to_junction_m is not None and (theirs := self._coming(other)) is not None:
                    if theirs[4] in foes and not self._same_source(v.lane, theirs[4]):
                        allowed.append((vehicle.getStopSpeed(ident, speed, max(ahead_m - 1.0, 0.0)), "foe", other.id,
                                        {"foe_lane": theirs[4], "foe_to_junction_m": round(other.to_junction_m, 1),
                                         "foe_in_junction": False}))
        if mode & _OBEYS_FOES and via and ahead_m is not None:
            for who, crossing, p in _foe_crossers(via, snap.pedestrians, waiting=True):
                allowed.append((vehicle.getStopSpeed(ident, speed, max(ahead_m - 1.0, 0.0)), "pedestrian", who,
                                {"crossing": crossing, "away_m": round(math.hypot(p.x - v.x, p.y - v.y), 1)}))
        reach = self._reach(ident, speed) - _REACH_EPS_MPS
        binding: dict[str, tuple[float, str, str | None, dict[str, Any]]] = {}
        for speed_allowed, cause, by, detail in sorted(allowed, key=lambda a: a[0]):
            if speed_allowed < before and speed_allowed < reach:
                binding.setdefault(f"{cause} {by}", (speed_allowed, cause, by,
                                                     {**detail, "allowed_mps": round(speed_allowed, 2)}))
        return list(binding.values()) or [(before, "none", None, {})]

    def _junction_leader(self, ident: str, speed: float, gap: float, other: VehicleState, via: str,
                         crossing: float | None = None, line_m: float | None = None) -> float:
        """The speed SUMO's junction model allows the vehicle for a link leader, a vehicle in the
        junction whose way meets its own (MSVehicle::adaptToJunctionLeader), at SUMO's gap
        (MSLink::getLeaderInfo's: to the crossing point less the vehicle's minGap, the part of
        the leader still before it and the crossing's width; `getLeader` gives it, or it is
        reckoned from `getJunctionFoes`). With room left (gap >= 0) SUMO follows the leader:
        its follow speed at that gap, the leader's speed and deceleration. With none, it stops
        before the lane where their ways meet (`line_m`: from outside the junction, at its line;
        on that lane already, as soon as it can: stopSpeed(seen - lane length); else minGap short
        of the crossing point). A leader that joins the vehicle's road
        there (the same target lane) is held to that alone; one crossing its way only until the
        vehicle could instead reach the crossing point as the leader has gone past it (the larger
        of the two, and of the lesser of that speed and the stop speed minGap short of the point:
        `crossing`, the distance to it). The town's 578 braked at 4.5 m/s² behind 170 pulling
        out of j13's Stop arm onto its road (a stop speed at SUMO's gap allowed all 578 could
        reach, its follow speed 12.91 m/s); the paper's 102 stopped at its own line for 152
        across its way in j2 (SUMO's gap -10.8 m)."""
        vehicle = libsumo.vehicle
        min_gap = vehicle.getMinGap(ident)
        if gap >= 0:
            base = vehicle.getFollowSpeed(ident, speed, gap, other.speed_mps, vehicle.getDecel(other.id), other.id)
        elif line_m is not None:
            base = vehicle.getStopSpeed(ident, speed, max(line_m - _POSITION_EPS_M, 0.0))
        else:
            base = vehicle.getStopSpeed(ident, speed, max((crossing or 0.0) - min_gap, 0.0))
        if self._target(via) == self._target(other.lane):
            return base                                    # joining its road: SUMO's stopAsap, held to that
        if crossing is None:
            crossing = next((f[1] for f in vehicle.getJunctionFoes(ident, LOOK_M) if f[0] == other.id), None)
        if crossing is None or crossing < 0:
            return base
        stop = vehicle.getStopSpeed(ident, speed, max(crossing - min_gap, 0.0))
        past_s = max(crossing - gap, 0.0) / max(other.speed_mps, _STOOD_MPS)    # when the leader is past the point
        if past_s <= 0:
            return max(base, stop)
        final = max(speed, 2.0 * (crossing - min_gap) / past_s - speed)
        reach = speed + (final - speed) / past_s * self.step_s
        return max(base, min(reach, stop))

    def _parting(self, v: VehicleState, snap: Snapshot, via: str, ahead_m: float | None,
                 asked: str | None) -> list[tuple[VehicleState, float]]:
        """The vehicles ahead that left by the incoming lane the vehicle comes by and went another
        way through the junction, still where their junction lane and the vehicle's way overlap,
        with SUMO's gap to each (to its back, less the vehicle's minGap; one whose front is not
        ahead of the vehicle's is no leader of it): SUMO's junction model
        follows such a one as a leader it cannot ignore (MSLink::getLeaderInfo: a foe lane of the
        same source, no crossing width). `getLeader` names one leader only, the first link leader
        it finds, and that may be another road user: the town-12 run's 439 (turning right at j2)
        braked at 4.5 m/s² from 437.5 s to 439.7 s behind 534, standing in the junction on the
        straight lane from the same lane, while `getLeader` named 111, crossing ahead of 534 onto
        439's road (SUMO's next speed the same with 111 taken away, higher without 534, every
        tick; getFollowSpeed at this gap gives SUMO's next speed to 0.001 m/s). Only from the
        first lane of its way (the one the two share the start of) and the road before it."""
        if not via or ahead_m is None or (v.lane.startswith(":") and v.lane != via) or not self._entering(via):
            return []
        foes = set(libsumo.lane.getInternalFoes(via))
        done = -v.lane_pos_m if v.lane == via else ahead_m          # metres from the vehicle's front to the lanes' start
        out = []
        for other in snap.vehicles:
            if other.id in (v.id, asked) or other.lane == via or other.lane not in foes \
                    or not self._same_source(via, other.lane):
                continue
            front = sum(libsumo.lane.getLength(lane) for lane in self._lanes_before(other.lane)) + other.lane_pos_m
            if done + front <= 0.0:
                continue                  # only one ahead of it: its front beyond the vehicle's own
            back = front - libsumo.vehicle.getLength(other.id)
            if back < self._parted_at(via, other.lane, v.id, other.id):
                out.append((other, done + back - libsumo.vehicle.getMinGap(v.id)))
        return out

    def _lanes_before(self, lane: str) -> tuple[str, ...]:
        """The junction lanes before a junction lane on its way from the incoming lane (none for the
        first): a vehicle on it is that much further from where the lanes of one incoming lane start
        (the paper-11 run's 290 on :j2_15_0, past the right turn's internal junction, followed by 236
        going straight on from the same lane: SUMO's next speed higher without 290, 140.2-141.0 s)."""
        if self._before is None:
            self._before = {}
            for incoming in libsumo.lane.getIDList():
                if incoming.startswith(":"):
                    continue
                for link in libsumo.lane.getLinks(incoming):
                    way: list[str] = []
                    lane_now = link[4]
                    while lane_now.startswith(":") and lane_now not in way:
                        self._before.setdefault(lane_now, tuple(way))
                        way.append(lane_now)
                        out = libsumo.lane.getLinks(lane_now)
                        lane_now = (out[0][4] or out[0][0]) if out else ""
        return self._before.get(lane, ())

    def _parted_at(self, via: str, lane: str, ident: str, other: str) -> float:
        """Metres along a junction lane leaving by the same incoming lane as `via` (from the lanes'
        start: with the junction lanes before it, `_lanes_before`) to where its
        centre line is as far from the way on from `via` (it and the internal lanes it leads on
        to) as half the mean width of the two vehicles: short of it the other's back is still in
        the vehicle's way. SUMO's own point is not asked (no call gives it); where SUMO stopped
        following was measured twice, and falls where this reading puts it: the town-12 run's 439
        (an ambulance, 2.2 m wide) behind 534 (a car, 1.8 m) at j2, followed with 534's back 0.95 m
        from 439's way and no longer at 1.09 m (this reading: 1.0 m); a car behind a car at the
        paper map's j2, followed at 0.87 m and no longer at 0.95 m (0.9 m). It is a reading, not
        SUMO's rule (its crossing geometry for the pair of lanes): behind a right-turner past the
        internal junction SUMO was seen to follow with the turner's back 2 m from the way; where it
        lets a leader go early, the braking is left "none", naming nobody."""
        half = (libsumo.vehicle.getWidth(ident) + libsumo.vehicle.getWidth(other)) / 4.0
        if (via, lane, half) in self._parts:
            return self._parts[via, lane, half]
        way, lane_now = [], via
        while lane_now.startswith(":") and lane_now not in way:
            way.append(lane_now)
            links = libsumo.lane.getLinks(lane_now)
            lane_now = (links[0][4] or links[0][0]) if links else ""
        ours = unary_union([LineString(libsumo.lane.getShape(w)) for w in way])
        theirs = LineString([p for w in self._lanes_before(lane) + (lane,) for p in libsumo.lane.getShape(w)])
        along = 0.0
        while along < theirs.length and ours.distance(theirs.interpolate(along)) < half:
            along += _PART_STEP_M
        self._parts[via, lane, half] = along
        return along

    @staticmethod
    def _target(lane: str) -> str | None:
        """The normal lane a junction lane leads to (through the internal lanes after it)."""
        seen = set()
        while lane and lane.startswith(":") and lane not in seen:
            seen.add(lane)
            links = libsumo.lane.getLinks(lane)
            if not links:
                return None
            lane = links[0][0]
        return lane

    def _internal_junction(self, via: str) -> tuple[str, tuple] | None:
        """The internal junction a junction lane leads to (SUMO's waiting point of a turn across
        oncoming traffic, at the lane's end) and its link, or None: (the lane after it, the link)."""
        links = libsumo.lane.getLinks(via) if via.startswith(":") else ()
        if links and links[0][4].startswith(":"):
            return links[0][4], links[0]
        return None

    def _to_internal_junction(self, v: VehicleState, via: str, ahead_m: float | None, ego_lane: str) -> float | None:
        """Metres from the vehicle's front to the internal junction on its way where its way meets a
        foe's on `ego_lane`, the lane after it (None where there is none before that meeting)."""
        if not via or ahead_m is None:
            return None
        inner = self._internal_junction(via)
        if inner is None or inner[0] != ego_lane:
            return None
        return ahead_m if v.lane == via else ahead_m + libsumo.lane.getLength(via)

    def _minor_link(self, v: VehicleState, via: str, ahead_m: float) -> tuple | None:
        """SUMO's cautious approach to a minor link ahead (MSVehicle::processLinkApproaches: "vehicles
        should decelerate when approaching a minor link"): while further from it than the link's
        foe visibility distance (VISIBILITY_M) and able to brake before it, a vehicle cannot yet
        see whether foes come, and SUMO gives it the speed at which it could stop there
        (vLinkWait), whatever comes; within sight of it, it goes on if nothing does. A minor link
        is one without priority (a lower-case state) and not a light's red or amber; an entry link
        whose junction lane leads to an internal junction is a continuation (the vehicle may pass
        it and wait at the internal junction's link, the next one asked). The links ahead are
        taken in turn, as SUMO does: the first that holds the vehicle is the one. The paper's
        right-turners on r1 brake at 4.5 m/s² from 13.4 to 6.3 m/s towards j2's internal junction
        whoever comes, and speed up within sight of it (paper-11 228: SUMO's next speed the same
        with every other road user taken away), then again towards the link out over the north
        arm's pedestrian crossing."""
        links: list[tuple[str, str, float]] = []          # (the lane beyond the link, its state, metres to it)
        if not v.lane.startswith(":"):
            entry = libsumo.vehicle.getNextLinks(v.id)[:1]
            if not entry:
                return None
            links.append((via, entry[0][5], ahead_m))
        lane, seen = via, ahead_m if v.lane.startswith(":") else ahead_m + libsumo.lane.getLength(via)
        while lane.startswith(":"):
            out = libsumo.lane.getLinks(lane)[:1]
            if not out:
                break
            beyond = out[0][4] or out[0][0]
            links.append((beyond, out[0][5], seen))
            if not beyond.startswith(":"):
                break
            lane, seen = beyond, seen + libsumo.lane.getLength(beyond)
        gap = _brake_gap(v.speed_mps, libsumo.vehicle.getDecel(v.id), self.step_s)
        for i, (beyond, state, seen) in enumerate(links):
            cont = i + 1 < len(links) and beyond.startswith(":") and links[i + 1][0].startswith(":") \
                and i == 0 and not v.lane.startswith(":")       # an entry link on to an internal junction
            if cont or not state or state.isupper() or state in _NOT_MINOR:
                continue
            if seen <= VISIBILITY_M or seen <= gap:
                continue                   # within sight of its foes, or past braking before it: SUMO goes on
            stop = libsumo.vehicle.getStopSpeed(v.id, v.speed_mps, max(seen - _POSITION_EPS_M, 0.0))
            return (stop, "link", None, {"link_lane": beyond, "link_state": state, "to_link_m": round(seen, 1)})
        return None

    def _reach(self, ident: str, speed: float) -> float:
        """The speed the vehicle can reach from `speed` in a tick (SUMO's maxNextSpeed: speed + its
        acceleration over the step, at most its top speed). SUMO's follow and stop speeds are never
        above it (`getFollowSpeed` behind a leader 1000 m off, `getStopSpeed` 1000 m short of a
        stop, give exactly it): a constraint that allows this much asks for nothing. Asked while
        the vehicle brakes harder than it can accelerate (4.5 against 2.6 m/s²), every such
        constraint would otherwise seem to ask for the difference, 1.9 m/s² (the town's 269
        "braked for leader 146", 370 m ahead; the paper's 238 for foe 265 still coming)."""
        return min(speed + libsumo.vehicle.getAccel(ident) * self.step_s, libsumo.vehicle.getMaxSpeed(ident))

    def _coming(self, other: VehicleState) -> tuple | None:
        """SUMO's next link of a vehicle outside the junction that is coming into it within
        COMING_S at its speed (None where it is not). A vehicle is not coming while it stands
        (under SUMO's halting speed: 0 m to go at 0 m/s is no arrival), while the world holds it at
        its line (a SUMO stop there), or while its link is a Stop sign (SUMO's `s`) it obeys and it
        has not yet stood at the line: SUMO brings it to a stop there first, however close and fast
        it comes. A vehicle braking to stand at its own line is not coming; once it moves off the
        line it is."""
        if other.to_junction_m is None or other.speed_mps < _STOOD_MPS or other.held \
                or other.to_junction_m > other.speed_mps * COMING_S:
            return None
        link = libsumo.vehicle.getNextLinks(other.id)[:1]
        if not link:
            return None
        if link[0][5] == _STOP_LINK and self.modes.get(other.id, 31) & _OBEYS_FOES \
                and (other.id, other.next_junction) not in self._stood:
            return None
        return link[0]

    def _same_source(self, lane: str, other: str) -> bool:
        """Whether two junction lanes leave from one incoming lane (SUMO's links: `lane.getLinks`)."""
        if self._source is None:
            self._source = {}
            for incoming in libsumo.lane.getIDList():
                if incoming.startswith(":"):
                    continue
                todo = [link[4] for link in libsumo.lane.getLinks(incoming) if link[4]]
                while todo:                 # the junction lane and the internal lanes it goes on by
                    inner = todo.pop()
                    if inner.startswith(":") and inner not in self._source:
                        self._source[inner] = incoming
                        todo.extend(link[4] or link[0] for link in libsumo.lane.getLinks(inner))
        mine = self._source.get(lane)
        return mine is not None and mine == self._source.get(other)

    def _entering(self, lane: str) -> bool:
        """Whether a junction lane is the first on a way through the junction (the via lane of a
        link from an incoming lane): a vehicle on it still holds its link; past an internal
        junction it has left it (the town-12 run's 250 held at j1's line while the ambulance 499
        was on :j1_9_0, let go as it went on to :j1_18_0)."""
        self._same_source(lane, lane)                 # the junction lanes' incoming lanes, once
        incoming = self._source.get(lane) if self._source is not None else None
        return incoming is not None and any(link[4] == lane for link in libsumo.lane.getLinks(incoming))

    def _merged(self, ident: str, leader: str) -> str | None:
        """The junction where the leader joined the vehicle's road from another arm (their routes
        meet at a junction they come into by different edges), or None where it drove ahead of it
        all along."""
        mine, theirs = self.routes.get(ident), self.routes.get(leader)
        if not mine or not theirs:
            return None
        lane = libsumo.vehicle.getRoadID(ident)
        start = mine.index(lane) if lane in mine else 0
        for i in range(start, len(mine)):
            if mine[i] in theirs:
                j = theirs.index(mine[i])
                before_mine = mine[i - 1] if i > 0 else None
                before_theirs = theirs[j - 1] if j > 0 else None
                return libsumo.edge.getFromJunction(mine[i]) if before_mine != before_theirs else None
        return None


def shares(binding: list[tuple[float, str, str | None, dict[str, Any]]], before: float,
           drop: float) -> list[float]:
    """The speed each binding constraint made the vehicle shed in a tick (`binding` as Account._why
    gives it; `before`, the speed it braked from; `drop`, what it shed): the slowing the constraint
    asked for, no more than the vehicle shed. For a road user in its way, only what it asked beyond
    the vehicle's own control (its light, line, turn, speed) and any leader of another name (issue
    35: not for its own control). Two at once each count: either alone would have made it brake.
    The lowest is the one SUMO's model takes (its next speed is the lowest its constraints allow,
    braking no harder than it can): where nothing of the vehicle's own control or another leader
    binds beside it, the whole tick's braking is its, also the part its stop point as asked here
    would have spared (SUMO stops short of where `getStopSpeed` is asked to: the red light scene's
    car stood 1.0 m before getNextTLS's distance, braking at 4.5 m/s² throughout)."""
    own = min((a for a, cause, _, _ in binding if cause in _OWN), default=before)
    lowest = min(range(len(binding)), key=lambda i: binding[i][0], default=None)
    out = []
    for i, (allowed, cause, by, _) in enumerate(binding):
        floor = before if cause in _OWN else min([own] + [a for a, c, b, _ in binding if c == "leader" and b != by])
        if cause == "none" or (i == lowest and floor >= before):
            out.append(drop)          # the one SUMO's model takes (the lowest), nothing of its own beside it
        else:
            out.append(min(drop, max(0.0, min(floor, before) - allowed)))
    return out


def by_road_user(binding: list[tuple[float, str, str | None, dict[str, Any]]],
                 sheds: list[float]) -> dict[str, float]:
    """The speed shed in a tick for each road user that is a foe or a merged leader of the vehicle,
    under whichever of its causes asked for more: SUMO's model keeps one speed for a vehicle, the
    lowest its constraints allow, so a road user that is both (a foe in the junction, then the
    leader it became on the vehicle's road) made it shed what the harder of the two asked, once."""
    out: dict[str, float] = {}
    for (_, cause, by, detail), shed in zip(binding, sheds):
        if by and (cause == "foe" or (cause == "leader" and detail.get("merged"))):
            out[by] = max(out.get(by, 0.0), shed)
    return out


def _brake_gap(speed: float, decel: float, step_s: float) -> float:
    """The distance SUMO needs to stop from `speed` braking at `decel`, tick by tick as it moves
    (MSCFModel::brakeGap with the Euler update, no headway): 19.3 m from 13.41 m/s at 4.5 m/s²,
    where v²/2b gives 20.0."""
    per_tick = decel * step_s
    if speed <= per_tick:
        return 0.0
    steps = int(speed / per_tick)
    return step_s * (steps * speed - per_tick * steps * (steps + 1) / 2.0)


def _joined(junction: str | None) -> dict[str, Any]:
    """A leader's `merged` (it joined the vehicle's road from another arm) and where (`merged_at`)."""
    return {"merged": junction is not None, "merged_at": junction}


def _near(v: VehicleState) -> bool:
    return v.junction is not None or v.lane.startswith(":") or \
        (v.to_junction_m is not None and v.to_junction_m <= NEAR_M)


def _foe_crossers(lane: str, pedestrians: tuple[PedestrianState, ...],
                  waiting: bool = False) -> list[tuple[str, str, PedestrianState]]:
    """(pedestrian, crossing, state) of those on a crossing that is a foe of a junction lane (and,
    `waiting`, of those on a junction's corner whose next edge, SUMO says, is such a crossing)."""
    junction = lane[1:].rsplit("_", 2)[0] if lane.startswith(":") else None
    on = [p for p in pedestrians if p.crossing or (waiting and p.junction is not None
                                                   and p.edge.startswith(f":{junction}_w"))]
    if not lane or not on:
        return []
    foes = set(libsumo.lane.getInternalFoes(lane))
    out = []
    for p in on:
        crossing = p.crossing or libsumo.person.getNextEdge(p.id)
        if crossing and f"{crossing}_0" in foes:
            out.append((p.id, crossing, p))
    return out
