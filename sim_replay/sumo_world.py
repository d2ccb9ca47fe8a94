"""The simulation's world: SUMO running in this process through libsumo, read by subscriptions.

SUMO does the physics (car following, lane changes, no two vehicles in one place, pedestrians on
crossings, signal programmes); the agents do the law, as in the paper, where NetLogo held only the
physical constraints and the rules came from Prolog (DESIGN "Simulation"). So this module decides
nothing: it starts SUMO, puts road users on the network, reports each tick as frozen values
(sim_replay.world_state) and carries out what an agent decided:

- `take_control(v)` switches off SUMO's obedience to red lights and right of way for v (its speed
  mode): v would now drive through a red light unless its agent holds it;
- `hold(v)` stops v behind the stop line ahead of it (a SUMO stop at the end of its lane), `release(v)`
  lets it go;
- `set_speed_factor(v, f)` makes v drive at f times the limit (a speeder).

Each tick is read with subscriptions, not one call per value: the simulation's departures and
arrivals, each road user's position, speed, heading and lane (subscribed once, when it departs), and
each traffic light's state. SUMO runs with a fixed step, a seed, no teleporting (a vehicle stuck
behind a collision stays where the evidence says it is) and collisions detected in junctions too.

libsumo holds one simulation per process, so one World is open at a time.
"""
from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import libsumo

from sim_replay.road_users import PEDESTRIAN, TYPES, define_types
from sim_replay.sumo_net import Network, read_network
from sim_replay.world_state import COLOURS, Collision, PedestrianState, SignalState, Snapshot, VehicleState
from store import GapsError

__all__ = ["BLUE_LIGHT", "SPEED_MODE_MINDFUL", "SPEED_MODE_OURS", "SPEED_MODE_SUMO", "World", "WorldError"]

tc = libsumo.constants
# SUMO's speed mode bits: 1 safe speed (never into the vehicle ahead), 2 maximum acceleration,
# 4 maximum deceleration, 8 right of way of foes approaching the junction, 16 brake for a red
# light, 32 (set: disregard) foes already inside the junction.
SPEED_MODE_SUMO = 0b011111   # SUMO's default: it obeys signals and right of way itself
SPEED_MODE_OURS = 0b000111   # physics only: no red lights, no right of way; it still keeps its distance
SPEED_MODE_MINDFUL = 0b001111   # ours, going lawfully: it passes a red light only on a call, and yields to foes
BLUE_LIGHT = 1 << 11         # SUMO's VEH_SIGNAL_EMERGENCY_BLUE
HOLD_GAP_M = 0.3             # a held vehicle stops with its front this far behind the line
HOLD_S = 1e7                 # how long a hold lasts unless released (for ever, in practice)
VEHICLE_VARS = (tc.VAR_POSITION, tc.VAR_ANGLE, tc.VAR_SPEED, tc.VAR_ACCELERATION, tc.VAR_LANE_ID,
                tc.VAR_LANEPOSITION, tc.VAR_SIGNALS)
PERSON_VARS = (tc.VAR_POSITION, tc.VAR_ANGLE, tc.VAR_SPEED, tc.VAR_ROAD_ID)
SIM_VARS = (tc.VAR_DEPARTED_VEHICLES_IDS, tc.VAR_ARRIVED_VEHICLES_IDS, tc.VAR_DEPARTED_PERSONS_IDS,
            tc.VAR_ARRIVED_PERSONS_IDS)
_POS, _ANGLE, _SPEED, _ACCEL, _LANE, _LANEPOS, _SIGNALS = VEHICLE_VARS
_ROAD = tc.VAR_ROAD_ID
_new = tuple.__new__          # a NamedTuple from its fields in order, without its Python-level __new__ (half the time)
_open: World | None = None


class WorldError(GapsError, RuntimeError):
    """SUMO refused something, or a World is used wrongly (a second one open, one already closed)."""


def _unknown(lane_id: str) -> tuple:
    """A lane the network does not list (none should be): its edge by SUMO's naming, nothing else."""
    return (lane_id.rsplit("_", 1)[0], None, None, None, None, None, 0.0)


class World:
    """One SUMO simulation of a network, stepped by the caller.

    `net` is a .net.xml (sim_replay/maps/paper/paper.net.xml is the paper's map); `step_s` the fixed
    step (0.1 s: entity.state at 10 Hz); `seed` SUMO's random seed (the same seed and the same calls
    give the same snapshots); `quiet` keeps SUMO's warnings off the terminal; `extra` more SUMO
    options."""

    def __init__(self, net: str | Path, *, seed: int = 0, step_s: float = 0.1, quiet: bool = True,
                 extra: Sequence[str] = ()) -> None:
        global _open
        if _open is not None:
            raise WorldError("a SUMO world is already open in this process (libsumo runs one); close it first")
        self.network: Network = read_network(net)
        self.step_s = step_s
        self.seed = seed
        args = ["sumo", "--net-file", str(self.network.path), "--step-length", repr(step_s),
                "--seed", str(seed), "--time-to-teleport", "-1", "--collision.action", "warn",
                "--collision.check-junctions", "true", "--no-step-log", "true", "--duration-log.disable", "true",
                "--pedestrian.model", "striping", *(("--no-warnings", "true") if quiet else ()), *extra]
        try:
            libsumo.start(args)
        except libsumo.TraCIException as e:
            raise WorldError(f"SUMO did not start on {net}: {e}") from e
        _open = self
        self._closed = False
        try:
            define_types(libsumo)
            libsumo.simulation.subscribe(SIM_VARS)
            self._tls = sorted(self.network.links)
            for tls in self._tls:
                libsumo.trafficlight.subscribe(tls, (tc.TL_RED_YELLOW_GREEN_STATE,))
        except libsumo.TraCIException as e:
            self.close()
            raise WorldError(f"SUMO refused the world's set-up on {net}: {e}") from e
        self._signal_keys = self._signal_layout()
        self._colours: dict[tuple[str, str, str | None], SignalState] = {}
        self._types: dict[str, str] = {}
        self._routes: dict[tuple[str, ...], str] = {}
        self._controlled: dict[str, int] = {}   # vehicles whose decisions are ours -> their speed mode
        self._held: dict[str, tuple[str, float, int]] = {}
        self._lanes = self.network.lanes
        self._edges = {lane.edge: lane for lane in self._lanes.values()}
        self._by_lane = {lane.id: (lane.edge, lane.road, lane.junction, lane.ahead, lane.approach, lane.line_kind,
                                   lane.length_m) for lane in self._lanes.values()}
        self._step = 0
        self.last: Snapshot | None = None            # the latest tick's snapshot

    @property
    def modes(self) -> dict[str, int]:
        """The speed mode of each vehicle whose decisions are ours (the others have SUMO's
        default, SPEED_MODE_SUMO): a live view, for SUMO's own account of why one brakes."""
        return self._controlled

    # --- putting road users on the network ------------------------------------------------------

    def route(self, from_edge: str, to_edge: str, kind: str = "car") -> tuple[str, ...]:
        """The fastest route between two edges for a type of vehicle (SUMO's router)."""
        try:
            found = libsumo.simulation.findRoute(from_edge, to_edge, vType=kind)
        except libsumo.TraCIException as e:
            raise WorldError(f"no route for a {kind} from {from_edge} to {to_edge}: {e}") from e
        if not found.edges:
            raise WorldError(f"no route for a {kind} from {from_edge} to {to_edge}")
        return tuple(found.edges)

    def add_vehicle(self, ident: str, kind: str, route: Sequence[str], *, depart_pos: float | str = "base",
                    depart_speed: float | str = "max", depart_lane: str = "best") -> None:
        """Put a vehicle of a type (road_users.TYPES) on a route (edge ids); it enters the network at
        the next step where there is room (Snapshot.departed says when)."""
        if kind not in TYPES or kind == PEDESTRIAN:
            raise WorldError(f"unknown vehicle type {kind!r}; one of {', '.join(t for t in TYPES if t != PEDESTRIAN)}")
        edges = tuple(route)
        try:
            rid = self._routes.get(edges)
            if rid is None:
                rid = f"route{len(self._routes)}"
                libsumo.route.add(rid, list(edges))
                self._routes[edges] = rid
            libsumo.vehicle.add(ident, rid, typeID=kind, depart="now", departLane=depart_lane,
                                departPos=str(depart_pos), departSpeed=str(depart_speed))
            if not libsumo.vehicle.isRouteValid(ident):     # else SUMO stops the whole simulation at insertion
                libsumo.vehicle.remove(ident)
                raise WorldError(f"vehicle {ident}: its route {' '.join(edges)} is not connected for a {kind}")
        except libsumo.TraCIException as e:
            raise WorldError(f"vehicle {ident}: {e}") from e
        self._types[ident] = kind

    def add_person(self, ident: str, from_edge: str, to_edge: str, *, depart_pos: float = 0.0,
                   arrival_pos: float | None = None) -> tuple[str, ...]:
        """Put a pedestrian on a pavement, walking to another edge by the pavements and crossings
        SUMO's router picks; returns the edges of the walk."""
        try:
            stages = libsumo.simulation.findIntermodalRoute(
                from_edge, to_edge, departPos=depart_pos, pType=PEDESTRIAN,
                **({"arrivalPos": arrival_pos} if arrival_pos is not None else {}))
        except libsumo.TraCIException as e:
            raise WorldError(f"no walk for pedestrian {ident} from {from_edge} to {to_edge}: {e}") from e
        if not stages or not stages[0].edges:
            raise WorldError(f"no walk for pedestrian {ident} from {from_edge} to {to_edge}")
        try:
            libsumo.person.add(ident, from_edge, depart_pos, typeID=PEDESTRIAN)
            for stage in stages:
                libsumo.person.appendStage(ident, stage)
        except libsumo.TraCIException as e:
            raise WorldError(f"pedestrian {ident}: {e}") from e
        self._types[ident] = PEDESTRIAN
        return tuple(e for s in stages for e in s.edges)

    # --- carrying out decisions -------------------------------------------------------------------

    def take_control(self, ident: str) -> None:
        """Make the vehicle's law-deciding ours: SUMO no longer stops it for red lights or gives way
        for it; it still keeps its distance from what is ahead."""
        self._vehicle_call(ident, libsumo.vehicle.setSpeedMode, SPEED_MODE_OURS)
        self._controlled[ident] = SPEED_MODE_OURS

    def mind_foes(self, ident: str, mindful: bool = True) -> None:
        """The vehicle goes lawfully: let SUMO keep it out of the way of foes that have right of way
        (oncoming traffic on a right turn on green, cross traffic an emergency vehicle crosses a red
        light in front of), as a lawful driver watching the road would. A vehicle that breaks a
        rule keeps SPEED_MODE_OURS (mindful False): it goes regardless, and what follows is the
        evidence. Called at every go; SUMO is asked only when the mode changes."""
        mode = SPEED_MODE_MINDFUL if mindful else SPEED_MODE_OURS
        if self._controlled.get(ident, mode) != mode:
            self._vehicle_call(ident, libsumo.vehicle.setSpeedMode, mode)
            self._controlled[ident] = mode

    def hand_back(self, ident: str) -> None:
        """Let SUMO decide for the vehicle again (it obeys signals and right of way)."""
        self._vehicle_call(ident, libsumo.vehicle.setSpeedMode, SPEED_MODE_SUMO)
        self._controlled.pop(ident, None)

    def hold(self, ident: str) -> bool:
        """Stop the vehicle behind the stop line (the end of its lane) ahead of it, until released.

        False where it cannot: it is not on the network yet (a tick must have reported it), it is
        inside a junction or on a lane that leads to none, or it is already too close to the line to
        stop there with its braking (SUMO refuses; the agent then knows the vehicle will cross)."""
        seen = self.last.vehicle(ident) if self.last is not None else None
        lane = self._lanes.get(seen.lane) if seen is not None else None
        if lane is None or lane.ahead is None:
            return False
        if ident in self._held:
            return True
        pos = max(0.0, lane.length_m - HOLD_GAP_M)
        try:
            libsumo.vehicle.setStop(ident, lane.edge, pos=pos, laneIndex=lane.index, duration=HOLD_S)
        except libsumo.TraCIException:
            return False
        self._held[ident] = (lane.edge, pos, lane.index)
        return True

    def release(self, ident: str) -> None:
        """Let a held vehicle go (whether it has come to a stop at the line yet or not)."""
        if self._held.pop(ident, None) is None:
            return
        try:
            if libsumo.vehicle.getStopState(ident) & 1:     # standing at the stop
                libsumo.vehicle.resume(ident)
            else:
                libsumo.vehicle.replaceStop(ident, 0, "")      # not there yet: the stop is dropped
        except libsumo.TraCIException as e:
            raise WorldError(f"vehicle {ident} could not be released: {e}") from e

    def set_speed_factor(self, ident: str, factor: float) -> None:
        """Drive at `factor` times the speed limit where the road is clear (1: at the limit)."""
        self._vehicle_call(ident, libsumo.vehicle.setSpeedFactor, factor)

    def set_blue_lights(self, ident: str, on: bool) -> None:
        """Switch an emergency vehicle's blue lights on or off (SUMO's signal bit 11, reported back
        in VehicleState.signals); off hands the signals back to SUMO."""
        self._vehicle_call(ident, libsumo.vehicle.setSignals, BLUE_LIGHT if on else -1)

    def _vehicle_call(self, ident: str, call, *args) -> None:
        try:
            call(ident, *args)
        except libsumo.TraCIException as e:
            raise WorldError(f"vehicle {ident}: {e}") from e

    # --- the tick ---------------------------------------------------------------------------------

    @property
    def t_s(self) -> float:
        return round(self._step * self.step_s, 9)

    def step(self) -> Snapshot:
        """Advance one step and report it."""
        if self._closed:
            raise WorldError("the world is closed")
        libsumo.simulationStep()
        self._step += 1
        sim = libsumo.simulation.getSubscriptionResults()
        departed_v, arrived_v = sim[tc.VAR_DEPARTED_VEHICLES_IDS], sim[tc.VAR_ARRIVED_VEHICLES_IDS]
        departed_p, arrived_p = sim[tc.VAR_DEPARTED_PERSONS_IDS], sim[tc.VAR_ARRIVED_PERSONS_IDS]
        for ident in departed_v:
            libsumo.vehicle.subscribe(ident, VEHICLE_VARS)
        for ident in departed_p:
            libsumo.person.subscribe(ident, PERSON_VARS)
        for ident in arrived_v:
            self._forget(ident)
        for ident in arrived_p:
            self._types.pop(ident, None)
        t = self.t_s
        signals, changed, lights = self._signals(t)
        vehicles = self._vehicles(libsumo.vehicle.getAllSubscriptionResults(), lights)
        pedestrians = self._pedestrians(libsumo.person.getAllSubscriptionResults())
        collisions = tuple(Collision(c.collider, c.victim, c.type, c.lane, c.pos)
                           for c in libsumo.simulation.getCollisions())
        self.last = Snapshot(self._step, t, vehicles, pedestrians, signals, changed,
                             tuple(departed_v) + tuple(departed_p), tuple(arrived_v) + tuple(arrived_p), collisions,
                             {v.id: v for v in vehicles}, {p.id: p for p in pedestrians})
        return self.last

    def _forget(self, ident: str) -> None:
        self._types.pop(ident, None)
        self._controlled.pop(ident, None)
        self._held.pop(ident, None)

    def _signal_layout(self) -> list[tuple[str, int, tuple[str, str, str | None]]]:
        """Per traffic light, which index of its state each approach and crossing shows."""
        layout: list[tuple[str, int, tuple[str, str, str | None]]] = []
        for tls in self._tls:
            for key, index in sorted(self.network.approach_links(tls).items()):
                junction, approach = key.split("/", 1)
                layout.append((tls, index, (junction, approach, None)))
            for link in self.network.links[tls]:
                if link.crossing is not None:
                    crossing = next(c for c in self.network.junctions[link.junction].crossings if c.id == link.crossing)
                    layout.append((tls, link.index, (link.junction, crossing.arm, link.crossing)))
        return layout

    def _signals(self, t: float) -> tuple[tuple[SignalState, ...], tuple[SignalState, ...], dict[tuple[str, str], str]]:
        states = {tls: r[tc.TL_RED_YELLOW_GREEN_STATE]
                  for tls, r in libsumo.trafficlight.getAllSubscriptionResults().items()}
        current, changed, lights = [], [], {}
        for tls, index, key in self._signal_keys:
            colour = COLOURS.get(states[tls][index], "off")
            before = self._colours.get(key)
            if before is None or before.colour != colour:
                before = self._colours[key] = SignalState(key[0], key[1], colour, t, key[2])
                changed.append(before)
            current.append(before)
            if key[2] is None:
                lights[key[0], key[1]] = colour
        return tuple(current), tuple(changed), lights

    def _vehicles(self, results: dict, lights: dict[tuple[str, str], str]) -> tuple[VehicleState, ...]:
        """Each subscribed vehicle as a VehicleState (the hot loop of a tick: a thousand vehicles)."""
        out: list[VehicleState] = []
        append, by_lane = out.append, self._by_lane
        types, controlled, held = self._types, self._controlled, self._held
        for ident, r in results.items():           # libsumo's order: by id
            lane_id, pos = r[_LANE], r[_LANEPOS]
            edge, road, junction, ahead, approach, kind, length = by_lane.get(lane_id) or _unknown(lane_id)
            if ahead is None:
                to_junction = to_line = light = None
            else:
                to_junction = length - pos
                to_line = to_junction if kind is not None else None
                light = lights.get((ahead, approach))
            x, y = r[_POS]
            kind_of = types.get(ident) or self._type_of(ident)
            append(_new(VehicleState, (ident, kind_of, x, y, (90.0 - r[_ANGLE]) % 360.0, r[_SPEED], r[_ACCEL], road,
                                       edge, lane_id, pos, r[_SIGNALS], junction, ahead, approach, to_junction,
                                       to_line, kind, light, ident in controlled, ident in held)))
        return tuple(out)

    def _type_of(self, ident: str) -> str:
        """The type of a vehicle SUMO put on the network itself (from a route file): asked once."""
        kind = self._types[ident] = libsumo.vehicle.getTypeID(ident)
        return kind

    def _pedestrians(self, results: dict) -> tuple[PedestrianState, ...]:
        out = []
        for ident, r in results.items():
            edge = r[_ROAD]
            lane = self._edges.get(edge)
            junction = lane.junction if lane else None
            crossing = edge if lane is not None and lane.kind == "crossing" else None
            x, y = r[_POS]
            out.append(PedestrianState(ident, x, y, (90.0 - r[_ANGLE]) % 360.0, r[_SPEED], edge, junction, crossing))
        return tuple(out)

    # --- the end --------------------------------------------------------------------------------

    def close(self) -> None:
        """Stop SUMO. Safe to call twice."""
        global _open
        if self._closed:
            return
        self._closed = True
        try:
            libsumo.close()
        finally:
            if _open is self:
                _open = None

    def __enter__(self) -> World:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
