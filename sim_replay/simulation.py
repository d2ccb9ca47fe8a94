"""The multi-agent junction simulation: SUMO's world stepped, the agents deciding, every event built.

    sim = Simulation(SimConfig(vehicles=40, duration_s=180, seed=7))
    for event in sim.events():        # DESIGN's events, in publication order; publishes nothing
        ...
    sim.truth.write("run.truth.json") # what happened (never into the store)
    print(sim.summary)                # vehicles, events, rulebook queries, potential violations

One tick (0.1 s of world time): SUMO steps; signals that changed are published per approach;
road users that entered the network are spawned; each vehicle within its decision distance of a
stop line has its agent decide (automated and emergency vehicles ask highway_code.le, human
drivers do what their profile makes them do) and the world carries the decision out (hold,
release, speed factor); crossings of stop lines and stretches over the limit go into the ground
truth; at the configured rate each road user's entity.state is published and every monitor
observes what is in its cone. Events of a tick share its t (a fixed epoch start plus world time)
and are ordered by source sequence numbers.

Determinism: SUMO is seeded, every draw comes from a random.Random stream named for its purpose
(sim_replay.faults.stream), and nothing reads the wall clock except the summary's timing; the
same config gives the same events byte for byte.
"""
from __future__ import annotations

import tempfile
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any, cast

import orjson

from reasoner.vocabulary import CAN, IS_OF_TYPE, IS_ON_AN_EMERGENCY_CALL
from sim_replay import av, drivers
from sim_replay.agent import Agent
from sim_replay.approach import Moment, Passage
from sim_replay.asking import Rulebooks
from sim_replay.collector import fewer_collections
from sim_replay.demand import Departure, Walk, plan
from sim_replay.faults import Faults, stream
from sim_replay.maps import map_files
from sim_replay.monitors import read_monitors
from sim_replay.net_map import world_map
from sim_replay.own_network import refusal
from sim_replay.routes_file import read_routes
from sim_replay.senses import Around
from sim_replay.rounding import hundredths, rounded_rows, tenths
from sim_replay.sim_config import SimConfig
from sim_replay.sim_events import Envelopes, Tick
from sim_replay.sumo_account import Account, read_ssm, ssm_options
from sim_replay.sumo_world import World, WorldError
from sim_replay.truth import Truth
from sim_replay.watchers import Line, Watchers
from sim_replay.witness import Witness
from sim_replay.world_state import Snapshot, VehicleState
from store import canonical_json
from store.wire import key_for

__all__ = ["Progress", "Simulation", "Summary", "simulate"]

Progress = Callable[[float, float], None]      # (world seconds done, world seconds in all)
PLAIN_BELOW = 1e14           # a finite measurement smaller than this, rounded to tenths or hundredths, is a float
                             # orjson writes as the canonical form does (store/canonical.py: zero or 1e-4 <= |x| < 1e16)
_SORT_KEYS = orjson.OPT_SORT_KEYS
_DIGITS = (2, 2, 1, 2, 2)     # an entity.state's x, y, heading_deg, speed_mps, accel_mps2: hundredths, tenths
ON_CALL_SPEED_FACTOR = 1.25
MRM_SPEED_FACTOR = 0.3
CRAWL_FACTOR = 0.3           # an emergency vehicle on a call approaches a red light at this share of the limit,
                             # as its drivers are trained to, so that it can still stop if the rulebook says no
SOFTWARE = {"ads": "gaps-sim-ads 1.0", "rulebook": "highway_code.le"}


@dataclass(frozen=True)
class Summary:
    vehicles: int
    pedestrians: int
    events: int
    lost_events: int
    by_kind: dict[str, int]
    rulebook_queries: int
    potential_violations: int
    acts: int
    collisions: int
    world_s: float
    wall_s: float

    @property
    def events_per_s(self) -> float:
        return self.events / self.wall_s if self.wall_s else 0.0

    def to_json(self) -> dict[str, Any]:
        return {"vehicles": self.vehicles, "pedestrians": self.pedestrians, "events": self.events,
                "lost_events": self.lost_events, "by_kind": dict(self.by_kind),
                "rulebook_queries": self.rulebook_queries, "potential_violations": self.potential_violations,
                "acts": self.acts, "collisions": self.collisions, "world_s": self.world_s,
                "wall_s": round(self.wall_s, 3)}


class Simulation:
    """One run of the simulation for a config; iterate `events()` once."""

    def __init__(self, config: SimConfig, progress: Progress | None = None, *,
                 departures: list[Departure] | None = None, walks: list[Walk] | None = None,
                 account: bool = False) -> None:
        """`departures` and `walks` replace the drawn demand (sim_replay.demand.plan): a scenario
        written by hand, as the tests write the paper's red-light situations. `account` keeps
        SUMO's own account of who braked for whom in the truth (sim_replay.sumo_account: its
        SSM device and its answers about each braking vehicle; the events are the same either
        way, the run a little slower)."""
        self.config = config
        self.account = account
        self.progress = progress
        self._given = (departures, walks)
        if config.net:
            files, self.net_path = None, Path(config.net)
        else:
            files = map_files(config.map)
            self.net_path = files.net
        # a network of the user's has the cameras its monitors file says, none without one
        self.monitors_path = Path(config.monitors) if config.monitors else files.monitors if files else None
        self.truth = Truth(config.run, config.seed, config.to_json())
        self.faults = Faults(config.faults, config.seed, self.truth)
        self.books = Rulebooks()
        self.env = Envelopes(config.run, self.faults.lose if config.faults.lost_event > 0 else None)
        self.by_kind: dict[str, int] = {}
        self.summary: Summary | None = None
        self._collisions: set[tuple[str, ...]] = set()
        self._rounded: dict[str, tuple] = {}    # per vehicle: its latest raw measurements and their rounding
        self._out: list[dict[str, Any]] = []     # the tick's events so far
        self._written: list[bytes | None] = []   # per event of _out: its canonical bytes, where _states wrote them
        self._keys: list[str | None] = []        # ... and its key, where _states had it at hand
        self._unwritten: list[int] = []          # the places in _out of the events _batch writes
        self._writing = True                     # whether _states writes them (batches' `written`)

    # --- the run ------------------------------------------------------------------------------

    def events(self) -> Iterator[dict[str, Any]]:
        """The run's events one by one, in publication order."""
        for batch in self.batches(written=False):
            yield from batch

    def batches(self, written: bool = True) -> Iterator[Tick]:
        """The run's events a tick at a time (run.start, each tick's, run.end), for an outlet that
        puts a tick's events together (Outlets.put_all). Empty ticks are left out. `written`: each
        with its events' canonical bytes (Tick.payloads), which Outlets.put_all publishes as they
        are; without, payloads is None (for a reader of the events that publishes nothing)."""
        self._writing = written
        started = time.perf_counter()
        c = self.config
        kept = tempfile.TemporaryDirectory(prefix="gaps-ssm-") if self.account else None
        ssm_file = Path(kept.name) / "ssm.xml" if kept else None
        routes: dict[str, tuple[str, ...]] = {}
        self._routes = routes
        with fewer_collections(), World(self.net_path, seed=c.seed,
                                         extra=ssm_options(ssm_file) if ssm_file else ()) as world:
            self.world = world
            account = Account(routes, world.modes) if self.account else None
            network = world.network
            why_not = refusal(network)
            if why_not is not None:
                raise WorldError(why_not)
            monitors = read_monitors(self.monitors_path, set(network.junctions)) \
                if self.monitors_path is not None and self.monitors_path.is_file() else ()
            self.watchers = Watchers(monitors, self.books, self.faults)
            departures, walks = self._demand(network)
            if self._given[0] is not None:
                departures = sorted(self._given[0], key=lambda d: (d.depart_s, d.id))
            if self._given[1] is not None:
                walks = sorted(self._given[1], key=lambda w: (w.depart_s, w.id))
            self.agents: dict[str, Agent] = {}
            self.lines: dict[str, Line] = {}
            self.witness = Witness(self.truth, network, monitors)
            self.witness.paths = self.account
            out: list[dict[str, Any]] = []
            self._out = out
            self._written = []
            self._keys = []
            self._unwritten = []
            self._emit("sim/world", 0.0, "run.start", {
                "map": world_map(network, monitors), "rulebooks": self.books.records(), "seed": c.seed,
                "config": c.to_json()})
            yield from self._batch()
            steps = round(c.duration_s / world.step_s)
            di = wi = 0
            self._calls = stream(c.seed, "calls")
            self._ads_rng = stream(c.seed, "ads")
            for step in range(1, steps + 1):
                t_before = world.t_s
                while di < len(departures) and departures[di].depart_s <= t_before:
                    self._add(departures[di])
                    di += 1
                while wi < len(walks) and walks[wi].depart_s <= t_before:
                    self._walk(walks[wi])
                    wi += 1
                snap = world.step()
                if account is not None:
                    account.tick(snap)
                self.faults.t_s = snap.t_s
                self._tick(snap, step % c.step_every == 0)
                yield from self._batch()
                if self.progress is not None and step % 100 == 0:
                    self.progress(snap.t_s, c.duration_s)
            self.witness.close(self.agents, world.t_s)
            self._emit("sim/world", world.t_s, "run.end", {"reason": "duration reached"})
            yield from self._batch()
            world_s = world.t_s
        if account is not None:            # SUMO writes the SSM file as it closes
            assert kept is not None and ssm_file is not None    # made with the account, above
            account.close()
            self.truth.account([y.to_json() for y in account.yields], read_ssm(ssm_file))
            kept.cleanup()
        self.summary = Summary(len(self.agents), len(walks), self.env.count, self.env.lost, dict(self.by_kind),
                               self.books.queries, self.watchers.potential_violations, len(self.truth.acts),
                               len(self._collisions), world_s, time.perf_counter() - started)
        if self.progress is not None:
            self.progress(world_s, c.duration_s)

    def _emit(self, src: str, t_s: float, kind: str, body: dict[str, Any]) -> dict[str, Any] | None:
        ev = self.env.make(src, t_s, kind, body)
        if ev is not None:
            self._unwritten.append(len(self._out))
            self._out.append(ev)
            self._written.append(None)
            self._keys.append(None)
            self.by_kind[kind] = self.by_kind.get(kind, 0) + 1
        return ev

    def _batch(self) -> Iterator[Tick]:
        """What the latest tick made, as one batch (none if it made nothing), with each event's
        canonical bytes (Tick.payloads) and key (Tick.zenoh_keys): those _states wrote, the others
        made here."""
        out = self._out
        if out:
            if self._writing:
                written, keys = self._written, self._keys
                for i in self._unwritten:
                    written[i] = canonical_json(out[i])
                    if keys[i] is None:
                        keys[i] = key_for(out[i])
                # every place filled just above: the lists hold no None now
                events = Tick(out, cast(list[bytes], written), cast(list[str], keys))
                self._written, self._keys = [], []
            else:
                events = Tick(out)
                self._written.clear()
                self._keys.clear()
            out.clear()
            self._unwritten.clear()
            yield events

    # --- putting road users on the network ----------------------------------------------------

    def _demand(self, network) -> tuple[list[Departure], list[Walk]]:
        """Who sets off when: drawn from the seed, or the routes files' (the truth keeps each road
        user's id in its file)."""
        c = self.config
        self._file_ids: dict[str, str] = {}
        if not c.routes:
            return plan(c, network, stream(c.seed, "demand"))
        demand = read_routes([Path(r) for r in c.routes], network, c, stream(c.seed, "demand"))
        self._file_ids = demand.file_ids
        return demand.departures, demand.walks

    def _add(self, d: Departure) -> None:
        c = self.config
        rng = stream(c.seed, f"vehicle:{d.id}")
        profile = drivers.draw_profile(rng, c.behaviour)
        if d.role != "human":
            profile = drivers.Profile("careful", profile.reaction_s, recorder=True)
        try:
            route = d.route or self.world.route(d.entry, d.exit, d.kind)
            self.world.add_vehicle(d.id, d.kind, route, depart_pos=0.0, depart_speed="max")
        except WorldError:
            return
        self._routes[d.id] = route
        agent = Agent(d, rng, profile, asks=d.role in ("autonomous", "emergency"), recorder=profile.recorder,
                       route=route)
        if d.role == "autonomous":
            agent.ads = av.Ads(level=rng.choice((3, 4)))
        if d.role == "emergency":
            agent.on_call = rng.random() < c.on_call_share
        if agent.recorder:
            agent.recorder_stops_s = self.faults.recorder_stop(d.id, d.depart_s, c.duration_s)
        self.agents[d.id] = agent
        self.truth.road_user(d.id, type=d.kind, driver=agent.driver, role=d.role, unmarked=d.unmarked,
                             profile=profile.name, recorder=agent.recorder, entry=d.entry, exit=d.exit,
                             automation_level=agent.ads.level if agent.ads else 0, on_call_at_start=agent.on_call)
        if d.id in self._file_ids:
            self.truth.road_user(d.id, routes_file_id=self._file_ids[d.id], route=list(route))

    def _walk(self, w: Walk) -> None:
        edge = self.world.network.net.getEdge(w.from_edge)
        try:
            self.world.add_person(w.id, w.from_edge, w.to_edge, depart_pos=max(0.0, edge.getLength() - 25.0),
                                  arrival_pos=20.0)
        except WorldError:
            return
        self.truth.road_user(w.id, type="pedestrian", driver="none", walk=[w.from_edge, w.to_edge])
        if w.id in self._file_ids:
            self.truth.road_user(w.id, routes_file_id=self._file_ids[w.id])

    # --- one tick -----------------------------------------------------------------------------

    def _tick(self, snap: Snapshot, publish: bool) -> None:
        t = snap.t_s
        began = max(0.0, round(t - self.world.step_s, 9))
        for s in snap.changed:      # SUMO switched the light at the start of this step, and moved everyone under it
            if s.crossing is None:
                self._emit(f"signal/{s.junction}-{s.approach}", began, "signal.state",
                           {"junction": s.junction, "approach": s.approach, "colour": s.colour})
        lights = {(s.junction, s.approach): s.colour for s in snap.signals if s.crossing is None}
        for ident in snap.departed:
            self._spawn(ident, t)
        around = Around(snap, self.world.network)
        second = round(t * 10) % 10 == 0
        agents, lines, decide_m = self.agents, self.lines, self.config.decide_m
        for v in snap.vehicles:
            ident = v[0]
            agent = agents.get(ident)
            if agent is None:
                continue
            if second:
                self._each_second(agent, v, t)
            if agent.passage is None and v.junction is None:     # what _lines would find nothing to do for
                to_line = v.to_line_m
                if to_line is None or v.line_kind is None or not v.next_junction:
                    if ident not in lines:
                        continue            # no line ahead, none behind
                elif to_line > decide_m:
                    line = lines.get(ident)
                    if line is not None and line.crossed_on is None:
                        continue            # its line known, too far off to decide yet
            self._lines(agent, v, t, lights, around)
        self.witness.tick(snap, around, t, self.agents, self.lines)
        if publish:
            self._states(snap, t)
            for p in snap.pedestrians:
                self._emit(f"pedestrian/{p.id}", t, "entity.state", {
                    "x": hundredths(p.x), "y": hundredths(p.y), "heading_deg": tenths(p.heading_deg),
                    "speed_mps": hundredths(p.speed_mps), "road": None if p.junction else p.edge,
                    "junction": p.junction})
            seen = self.watchers.observe(t, around, self.lines, lights, self.witness.limit_mph,
                                         lambda src, kind, body: self._emit(src, t, kind, body))
            self.witness.seen(seen)
        for c in snap.collisions:
            pair = tuple(sorted((c.collider, c.victim)))
            if pair not in self._collisions:
                self._collisions.add(pair)
                self._emit("sim/world", t, "collision", {"entities": list(pair), "kind": c.kind, "lane": c.lane})
        for ident in snap.arrived:
            role = "pedestrian" if ident.startswith("p") and ident not in self.agents else "vehicle"
            agent = self.agents.get(ident)
            if agent is not None:
                self.witness.gone(agent, t)
            self.lines.pop(ident, None)
            self._rounded.pop(ident, None)
            self._emit(f"{role}/{ident}", t, "entity.despawn", {"reason": "left the map"})

    def _states(self, snap: Snapshot, t: float) -> None:
        """Every vehicle's entity.state of this tick (the bulk of the events: one per vehicle per
        tick). Rounding is the dearest part of a body (sim_replay.rounding: round()'s floats without
        its decimal text, a tick's vehicles at once: `_round`), and a third of the vehicles at a thousand stand still in queues,
        reporting the same measurements tick after tick: their rounded values are kept
        (`_rounded`, with the source's name) and used again while SUMO reports exactly the same
        numbers.

        Each state's canonical bytes are written here too, by orjson straight away, where its
        measurements were found plain as they were rounded (finite and below PLAIN_BELOW: their
        rounded floats are zero or at least 0.01, which orjson writes as the canonical form does,
        store/canonical.py); the rest of a state is the envelope's ints and strs, a str or None per
        place and a bool. Anything orjson refuses (a str that is not valid Unicode) is left to
        canonical_json, as is every state with a measurement that is not plain."""
        env, agents, rounded = self.env, self.agents, self._rounded
        if env.lossy or not self._writing:
            self._states_made(snap, t)
            return
        seqs, run, stamp = env.seqs, env.run, env.stamp(t)      # Envelopes.make_all's envelope, made in the one pass
        out, written = self._out, self._written
        add, add_written, add_key, dumps = out.append, written.append, self._keys.append, orjson.dumps
        self._round(snap.vehicles)
        for v in snap.vehicles:
            ident = v[0]
            kept = rounded[ident]
            agent = agents.get(ident)
            src = kept[1]
            seq = seqs.get(src, 0)
            seqs[src] = seq + 1
            ev = {"v": 1, "run": run, "src": src, "seq": seq, "t": stamp, "kind": "entity.state", "body": {
                "x": kept[2], "y": kept[3], "heading_deg": kept[4], "speed_mps": kept[5], "accel_mps2": kept[6],
                "road": v.road, "lane": v.lane, "junction": v.junction, "emergency": agent is not None and agent.on_call}}
            payload = None
            if kept[7]:
                try:
                    payload = dumps(ev, option=_SORT_KEYS)
                except orjson.JSONEncodeError:
                    pass
            if payload is None:
                self._unwritten.append(len(out))
            add(ev)
            add_written(payload)
            add_key(kept[9])
        if snap.vehicles:
            env.count += len(snap.vehicles)
            self.by_kind["entity.state"] = self.by_kind.get("entity.state", 0) + len(snap.vehicles)

    def _round(self, vehicles: tuple[VehicleState, ...]) -> None:
        """Each vehicle's measurements of this tick rounded into `_rounded`, where they are not the
        ones kept (a standing vehicle's): all of them at once (rounding.rounded_rows)."""
        rounded, run = self._rounded, self.env.run
        changed = []
        for v in vehicles:
            kept = rounded.get(v[0])
            if kept is None or kept[0] != v[2:7]:  # x, y, heading_deg, speed_mps, accel_mps2 (VehicleState's order)
                changed.append(v)
        if not changed:
            return
        raws = [v[2:7] for v in changed]
        for v, raw, (x, y, heading, speed, accel) in zip(changed, raws, rounded_rows(raws, _DIGITS)):
            ident = v[0]
            kept = rounded.get(ident)
            names = _names(ident, run) if kept is None else kept[8]
            rounded[ident] = (raw, names[0], x, y, heading, speed, accel, _plain(raw), names, names[1])

    def _states_made(self, snap: Snapshot, t: float) -> None:
        """_states where events may be lost (Envelopes.make_all decides which) or none is written."""
        agents, rounded = self.agents, self._rounded
        bodies: list[tuple[str, dict[str, Any]]] = []
        add = bodies.append
        self._round(snap.vehicles)
        for v in snap.vehicles:
            ident = v[0]
            kept = rounded[ident]
            agent = agents.get(ident)
            add((kept[1], {"x": kept[2], "y": kept[3], "heading_deg": kept[4], "speed_mps": kept[5],
                           "accel_mps2": kept[6], "road": v.road, "lane": v.lane, "junction": v.junction,
                           "emergency": agent is not None and agent.on_call}))
        made = self.env.make_all(t, "entity.state", bodies)
        self._unwritten.extend(range(len(self._out), len(self._out) + len(made)))
        self._out.extend(made)
        self._written.extend([None] * len(made))
        self._keys.extend([None] * len(made))
        if made:
            self.by_kind["entity.state"] = self.by_kind.get("entity.state", 0) + len(made)

    def _spawn(self, ident: str, t: float) -> None:
        agent = self.agents.get(ident)
        if agent is None:
            self._emit(f"pedestrian/{ident}", t, "entity.spawn", {"type": "pedestrian", "driver": "none"})
            return
        d = agent.d
        self._emit(f"vehicle/{ident}", t, "entity.spawn", {
            "type": d.kind, "driver": agent.driver, "automation_level": agent.ads.level if agent.ads else 0,
            "plate": f"GP{int(ident) % 100:02d} SIM", "emergency": agent.on_call})
        factor = agent.profile.speed_factor
        if agent.on_call:
            factor = ON_CALL_SPEED_FACTOR
            self.world.set_blue_lights(ident, True)
        self._set_factor(agent, factor)
        if agent.ads is not None:
            self._record(agent, t, "ads.event", {"event": "activated", "reason": "journey start",
                                                 "software": SOFTWARE})

    def _set_factor(self, agent: Agent, factor: float) -> None:
        if factor != agent.speed_factor:
            self.world.set_speed_factor(agent.id, factor)
            agent.speed_factor = factor

    def _record(self, agent: Agent, t: float, kind: str, body: dict[str, Any]) -> dict[str, Any] | None:
        """An event of the vehicle's own recorder (none once the recorder has stopped)."""
        if not agent.recorder or (agent.recorder_stops_s is not None and t >= agent.recorder_stops_s):
            return None
        return self._emit(f"vehicle/{agent.id}", t, kind, body)

    def _each_second(self, agent: Agent, v: VehicleState, t: float) -> None:
        c = self.config
        if agent.d.role == "emergency" and self._calls.random() < c.call_change_per_min / 60.0:
            agent.on_call = not agent.on_call
            self.world.set_blue_lights(agent.id, agent.on_call)
            if agent.asks:               # the crew's recorder notes the call as it begins or ends
                facts = [IS_OF_TYPE.text(agent.id, agent.d.kind)] + \
                    ([IS_ON_AN_EMERGENCY_CALL.text(agent.id)] if agent.on_call else [])
                self._record(agent, t, "vehicle.perception", {"facts": facts})
                agent.asked_facts = ()
            self._set_factor(agent, ON_CALL_SPEED_FACTOR if agent.on_call else 1.0)
            self.truth.road_user(agent.id, calls=self.truth.road_users[agent.id].get("calls", []) +
                                 [{"t_s": t, "on_call": agent.on_call}])
        if agent.ads is not None:
            for event, reason in agent.ads.tick(t, self._ads_rng, c.ads_event_per_min / 60.0):
                self._record(agent, t, "ads.event", {"event": event, "reason": reason})
                self.truth.road_user(agent.id, ads=self.truth.road_users[agent.id].get("ads", []) +
                                     [{"t_s": t, "event": event}])
                if event == "minimal_risk_manoeuvre":
                    self._set_factor(agent, MRM_SPEED_FACTOR)
                elif event == "activated":
                    self._set_factor(agent, 1.0)

    # --- stop lines ---------------------------------------------------------------------------

    def _lines(self, agent: Agent, v: VehicleState, t: float, lights: dict[tuple[str, str], str],
               around: Around) -> None:
        line = self.lines.get(v.id)
        if v.junction is None and v.to_line_m is not None and v.line_kind is not None and v.next_junction \
                and v.approach is not None:     # (a lane with a line's kind has its approach)
            if line is None or line.crossed_on is not None:
                line = self.lines[v.id] = Line(v.next_junction, v.approach, v.line_kind)
            p = agent.passage
            if p is None and v.to_line_m <= self.config.decide_m:
                p = agent.passage = Passage(v.id, line.junction, line.approach, line.kind, t)
                self.world.take_control(v.id)
            if p is not None:
                p.observe(v, t)
                light = lights.get((line.junction, line.approach)) if line.kind == "signal" else None
                if light == "amber" and p.draws.get("light") != "amber":      # the amber it may cross under
                    p.draws["at_amber"] = (round(v.to_line_m, 2), round(v.speed_mps, 2))
                p.draws["light"] = light
                if agent.on_call and light in ("red", "red_amber") and "crawl" not in p.draws:
                    p.draws["crawl"] = True         # blue lights against a red: up to the line at a crawl
                    self._set_factor(agent, CRAWL_FACTOR)
                if self._looks(agent, p, t):
                    self._decide(agent, p, Moment(t, v, light, tuple(around.near(v)), p.stopped_at_line))
            return
        if line is None:
            return
        if line.crossed_on is None and v.junction == line.junction:
            colour = lights.get((line.junction, line.approach)) if line.kind == "signal" else None
            self.lines[v.id] = Line(line.junction, line.approach, line.kind, colour or "none")
            self.witness.crossed(agent, v, t, self.lines[v.id], colour, around)
            self._crossed(agent)
            self.world.hand_back(v.id)              # over the line: SUMO's physics keeps it out of others' way
        elif line.crossed_on is not None and v.junction is None:
            self.lines.pop(v.id, None)

    @staticmethod
    def _looks(agent: Agent, p: Passage, t: float) -> bool:
        """Whether the agent looks at this tick: at once, then every half second for those that ask,
        every reaction time for humans. Asked before the moment is put together, which most ticks
        of a passage then skip (at 1,000 vehicles, half of them are within a passage)."""
        if p.go is None:
            return True
        every = 5 if agent.asks and agent.driving() != "user" else max(1, round(agent.profile.reaction_s * 10))
        return round((t - p.began_s) * 10) % every == 0

    def _decide(self, agent: Agent, p: Passage, m: Moment) -> None:
        """The agent's look at this tick (`_looks`): a rulebook question for those that ask, a habit
        for humans."""
        if agent.asks and agent.driving() != "user":
            engaged = agent.driving() == "autonomous"
            facts = av.perceive(agent.id, agent.d.kind, p, m, engaged=engaged, on_call=agent.on_call,
                                faults=self.faults)
            if tuple(facts) == agent.asked_facts and p.go is not None:
                return
            agent.asked_facts = tuple(facts)
            asked = av.ask_to_enter(self.books, agent.id, facts)
            go = self._carry_out(agent, p, asked.holds, lawful=asked.holds)
            why = ("rulebook: can enter" if asked.holds else "rulebook: cannot enter") + \
                  ("" if go == asked.holds else " (too close to stop: went on)")
            self._record(agent, m.t_s, "vehicle.perception", {"facts": facts})
            self._publish_decision(agent, p, m.t_s, go, asked)
        else:
            go, why = drivers.human_decision(agent.profile, p, m, agent.rng, self.config.behaviour.propensity)
            changed = go != p.go
            if changed:
                wanted = go
                go = self._carry_out(agent, p, go, lawful=drivers.lawful(why))
                if go != wanted:
                    why += " (too close to stop: went on)"
                if go and why.startswith("stop roller"):
                    self._set_factor(agent, drivers.ROLL_FACTOR)
            if agent.recorder:           # what the driver saw, whenever it changed; what it did, when that changed
                facts = av.perceive(agent.id, agent.d.kind, p, m, engaged=False, on_call=agent.on_call, faults=None,
                                    predicts=False)
                if changed or tuple(facts) != agent.asked_facts:
                    agent.asked_facts = tuple(facts)
                    self._record(agent, m.t_s, "vehicle.perception", {"facts": facts})
                if changed:
                    self._publish_decision(agent, p, m.t_s, go, None)
        p.why = why                      # the latest reason it goes or waits (a habit may take over at amber)

    def _carry_out(self, agent: Agent, p: Passage, go: bool, lawful: bool) -> bool:
        """Hold or release in the world; returns whether the vehicle goes (a hold may come too late).
        A lawful go through traffic lights also yields to foes with right of way (World.mind_foes):
        oncoming traffic on a right turn on green, cross traffic in front of a vehicle on a call. At
        a Stop or Give Way line the driver's own look for a gap is the act judged, and SUMO's is
        not asked for."""
        if go:
            self.world.mind_foes(agent.id, lawful and p.line == "signal")
            if p.held:
                self.world.release(agent.id)
                p.held = False
        elif not p.held:
            if self.world.hold(agent.id):
                p.held = True
            else:
                go = True
        p.go = go
        return go

    def _publish_decision(self, agent: Agent, p: Passage, t: float, go: bool, asked: av.Asked | None) -> None:
        """vehicle.trace (the question, its answer and proof) where it asked, then vehicle.decision."""
        body: dict[str, Any] = {"goal": CAN.text(agent.id, av.ACTION), "action": av.ACTION, "proceeds": go}
        if asked is not None:
            trace = self._record(agent, t, "vehicle.trace", {"query": asked.question, "answer": asked.holds,
                                                               "proof": asked.proof})
            body.update({"permitted": asked.holds, "rulebook": self.books.sha256(av.RULEBOOK)})
            if trace is not None:
                body["trace"] = trace["seq"]
        if self._record(agent, t, "vehicle.decision", body) is not None or asked is not None:
            p.decision = body

    def _crossed(self, agent: Agent) -> None:
        """Its passage is over: habits that change its speed for a line end with it."""
        p = agent.passage
        agent.passage = None
        agent.asked_facts = ()
        if p is not None and (p.draws.get("rolls_stop") or p.draws.get("crawl")):
            self._set_factor(agent, ON_CALL_SPEED_FACTOR if agent.on_call else agent.profile.speed_factor)


def _names(ident: str, run: str) -> tuple[str, str]:
    """A vehicle's entity.state source and its key (store.key_for's), written once per vehicle."""
    src = f"vehicle/{ident}"
    return src, f"gaps/{run}/{src}/entity.state"


def _plain(raw: tuple[float, ...]) -> bool:
    """Whether a vehicle's measurements are plain: each below PLAIN_BELOW in size (a NaN or an
    infinity is not). What _round keeps of them: them, its source, their rounding, this, its
    names (_names) and its key."""
    x, y, heading, speed, accel = raw
    return (-PLAIN_BELOW < x < PLAIN_BELOW and -PLAIN_BELOW < y < PLAIN_BELOW and -PLAIN_BELOW < heading < PLAIN_BELOW
            and -PLAIN_BELOW < speed < PLAIN_BELOW and -PLAIN_BELOW < accel < PLAIN_BELOW)


def simulate(config: SimConfig, progress: Progress | None = None) -> Iterator[dict[str, Any]]:
    """The events of a run (see Simulation for the truth and the summary)."""
    return Simulation(config, progress).events()
