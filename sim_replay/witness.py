"""The ground truth's witness: what each road user did, measured from the world, written as acts.

The simulation loop tells the witness when a vehicle crossed a stop line (it knows the passage:
who drove, why, what the vehicle decided) and shows it every tick; the witness writes to the
sim_replay.truth.Truth:

    crossings     who crossed which line when, on what light, at what speed, whether it had stood
                  at the line, its turn, who was approaching, and how hard each of them braked in
                  the REACTION_S after (braking for a light of its own that is not green, behind a
                  vehicle it follows, or on a way through the junction that neither crosses nor
                  joins the vehicle's is not counted: it has other causes)
    box stops     standing still inside a yellow box, with what it stood behind and who queued on
                  its exit
    speeding      each stretch over the limit of the road, with its top speed and the monitors that
                  saw it

Measurements only: whether an act was lawful is for the tests' table and the reasoner.
"""
from __future__ import annotations

import math
from typing import Any

from reasoner.history import MPH_PER_MPS, sector
from sim_replay.agent import Agent
from sim_replay.monitors import Monitor
from sim_replay.senses import Around, Other
from sim_replay.crossing_paths import Geometry, PathWatch, Recent
from sim_replay.sumo_net import Network
from sim_replay.truth import EXIT_M, REACTION_S, Act, Truth
from sim_replay.watchers import Line
from sim_replay.world_state import Snapshot, VehicleState

__all__ = ["FOLLOW_M", "Witness"]

FOLLOW_M = 25.0              # a road user this close behind another is following it
ABREAST_M = 4.0              # and no further to one side of its heading (the same lane)
STILL_MPS = 0.1
_CLOCKWISE = ("north", "east", "south", "west")
EXIT_ARM_M = 10.0            # an exit's arm is read this far out along its road


class Witness:
    def __init__(self, truth: Truth, network: Network, monitors: tuple[Monitor, ...]) -> None:
        self.truth, self.network, self.monitors = truth, network, monitors
        self._limits = {e.getID(): round(e.getSpeed() * MPH_PER_MPS) for e in network.net.getEdges(withInternal=False)}
        self.limit_mph: dict[str, int] = {}                 # the limit of the road each vehicle is on
        self._pending: list[dict[str, Any]] = []            # crossings waiting for the reactions about them
        self._over: dict[str, dict[str, Any]] = {}          # stretches over the limit in progress
        self._boxed: dict[str, dict[str, Any]] = {}         # standing in a yellow box
        self.paths = False           # ask SUMO which pedestrians were in a crossing vehicle's path (crossing_paths)
        self._geometry = Geometry()
        self._recent = Recent()                             # pedestrians on crossings just before an act
        self._closing: list[tuple[dict[str, Any], PathWatch]] = []   # acts written when their path watch closes

    def _seen_by(self, v: VehicleState) -> tuple[str, ...]:
        return tuple(m.id for m in self.monitors if m.sees(v.x, v.y))

    # --- crossings ------------------------------------------------------------------------------

    def crossed(self, agent: Agent, v: VehicleState, t: float, line: Line, colour: str | None,
                around: Around) -> None:
        """v's front is over its line in this tick (agent.passage: the passage that led there)."""
        p = agent.passage
        others = around.about(v.junction, v.id, line.approach)
        fault = None
        if p is not None and p.draws.get("misread"):
            fault = f"misperceived_light: saw {p.draws['misread']}"
        elif p is not None and p.missed:
            fault = "missed_road_user: " + ", ".join(sorted(p.missed))
        watch = {o.id: 0.0 for o in others if not o.pedestrian}
        path = PathWatch(self._geometry, v, t, self._recent) if self.paths else None
        self._pending.append({"path": path, "until": t + REACTION_S, "watch": watch, "known": {o.id for o in others},
                              "where": (v.id, line.junction, line.approach),
                              "way": self._way(agent, line.junction), "act": dict(
            kind="crossed the stop line", vehicle=v.id, type=agent.d.kind, driver=agent.driving(), t_s=t,
            junction=line.junction, approach=line.approach, line=line.kind, light=colour,
            speed_mps=round(v.speed_mps, 2), speed_mph=round(v.speed_mps * MPH_PER_MPS),
            limit_mph=self.limit_mph.get(v.id), stopped_at_line=bool(p and p.stopped_at_line), on_call=agent.on_call,
            approaching=tuple(_approaching(o, 0.0) for o in others),
            turn=self._turn(agent, line.junction, line.approach), at_amber=p.draws.get("at_amber") if p else None,
            seen_by=self._seen_by(v),
            why=(p.why if p else "no passage") + f" [{agent.profile.name}]", decision=p.decision if p else None,
            fault=fault)})

    def _react(self, snap: Snapshot | None, around: Around | None, t: float,
               agents: dict[str, Agent] | None = None) -> None:
        """The braking of the road users about each recent crossing, until REACTION_S after it (None:
        the run has ended, every pending act is written)."""
        closing = []
        for act, path in self._closing:     # acts whose reactions are settled, their path watch still open
            if snap is not None:
                path.tick(t, snap.vehicle(act["vehicle"]), snap.pedestrians)
                if path.open(t):
                    closing.append((act, path))
                    continue
            self._write(act, path)
        self._closing = closing
        still = []
        for pending in self._pending:
            if snap is not None:
                vid, junction, approach = pending["where"]
                me = snap.vehicle(vid)
                if pending["path"] is not None:
                    pending["path"].tick(t, me, snap.pedestrians)
                if me is not None and me.junction == junction and around is not None:   # still crossing: who comes up
                    for o in around.about(junction, vid, approach):
                        if o.id not in pending["known"]:
                            pending["known"].add(o.id)
                            pending["act"]["approaching"] += (_approaching(o, t - pending["act"]["t_s"]),)
                            if not o.pedestrian:
                                pending["watch"][o.id] = 0.0
                watch = pending["watch"]
                for ident, hardest in watch.items():      # the tests only where it brakes harder than yet
                    other = snap.vehicle(ident)
                    if other is None:
                        continue
                    braking = round(-other.accel_mps2, 2)
                    if braking > hardest and other.light in (None, "green") \
                            and self._may_meet(pending, ident, (agents or {}).get(ident), junction) \
                            and not _following(other, snap, vid):      # the dear test last: it looks about
                        watch[ident] = braking
            if snap is not None and t < pending["until"]:
                still.append(pending)
                continue
            act = dict(pending["act"], reactions=tuple(sorted(pending["watch"].items())))
            if pending["path"] is not None and snap is not None and pending["path"].open(t):
                self._closing.append((act, pending["path"]))     # its reactions are settled; its path not yet
            else:
                self._write(act, pending["path"])
        self._pending = still

    def _write(self, act: dict[str, Any], path: PathWatch | None) -> None:
        self.truth.act(Act(**act, in_path=tuple(path.found()) if path is not None else ()))

    def _exit(self, agent: Agent, junction: str, approach: str) -> str | None:
        """The edge its route leaves a junction by, after the approach it came in on."""
        a = self.network.junctions[junction].approach(approach)
        if a is None or a.edge not in agent.route:
            return None
        i = agent.route.index(a.edge)
        return agent.route[i + 1] if i + 1 < len(agent.route) else None

    def _way(self, agent: Agent | None, junction: str) -> tuple[str, str] | None:
        """The arms a road user's route comes in by and leaves by at a junction (None: unknown)."""
        j = self.network.junctions.get(junction)
        if agent is None or j is None:
            return None
        for a in j.approaches:
            out = self._exit(agent, junction, a.name)
            if out is not None:
                return a.name, self._arm(j.x, j.y, out)
        return None

    def _arm(self, x: float, y: float, edge: str) -> str:
        """The arm of a junction at (x, y) an outgoing edge leaves by, read EXIT_ARM_M out."""
        shape = self.network.net.getEdge(edge).getShape()
        far = next((p for p in shape if math.hypot(p[0] - x, p[1] - y) >= EXIT_ARM_M), shape[-1])
        return sector(far[0] - x, far[1] - y)

    def _may_meet(self, pending: dict[str, Any], ident: str, other: Agent | None, junction: str) -> bool:
        """Whether the other's way through the junction crosses or joins the vehicle's (and so
        braking may be for it); where either way is unknown, it may. Settled once per road user
        and act, not at every tick of the reaction window."""
        meets = pending.setdefault("meets", {})
        if ident not in meets:
            mine, theirs = pending["way"], self._way(other, junction)
            meets[ident] = mine is None or theirs is None or ways_meet(mine, theirs, self.network.lefthand)
        return meets[ident]

    def _turn(self, agent: Agent, junction: str, approach: str) -> str | None:
        """Left, straight or right at a junction, from its route's edges in and out."""
        a = self.network.junctions[junction].approach(approach)
        out = self._exit(agent, junction, approach)
        if a is None or out is None:
            return None
        net = self.network.net
        e_in, e_out = net.getEdge(a.edge), net.getEdge(out)
        (x0, y0), (x1, y1) = e_in.getFromNode().getCoord()[:2], e_in.getToNode().getCoord()[:2]
        (x2, y2), (x3, y3) = e_out.getFromNode().getCoord()[:2], e_out.getToNode().getCoord()[:2]
        turn = (math.degrees(math.atan2(y3 - y2, x3 - x2) - math.atan2(y1 - y0, x1 - x0)) + 180.0) % 360.0 - 180.0
        return "straight" if abs(turn) < 30 else "left" if turn > 0 else "right"

    # --- every tick -----------------------------------------------------------------------------

    def tick(self, snap: Snapshot, around: Around, t: float, agents: dict[str, Agent],
             lines: dict[str, Line]) -> None:
        """Every vehicle's speed against its road's limit, a box stand begun or ended, the reactions
        to recent crossings. The look at the limit is made here for the thousand vehicles of a tick
        (the limit of the road it is on, or of the last one it was on), and `_speeding` is called
        only for one over it or with a stretch over it to end."""
        boxed, limits, limit_mph, over = self._boxed, self._limits, self.limit_mph, self._over
        for v in snap.vehicles:
            ident = v[0]
            agent = agents.get(ident)
            if agent is None:
                continue
            junction = v.junction
            limit = limits.get(v.edge) if junction is None else None
            if limit is not None:
                limit_mph[ident] = limit
            else:
                limit = limit_mph.get(ident)
            if limit is not None:
                mph = round(v.speed_mps * MPH_PER_MPS)
                if mph > limit or ident in over:
                    self._speeding(agent, v, t, limit, mph)
            if junction is not None or ident in boxed:     # outside a junction, only a box stand can end
                self._box(agent, v, t, snap, lines.get(ident))
        self._react(snap, around, t, agents)
        if self.paths:
            self._recent.tick(t, snap.pedestrians)

    def seen(self, pairs: set[tuple[str, str]]) -> None:
        """The (monitor, vehicle) pairs the monitors observed this round."""
        for monitor, vid in pairs:
            if vid in self._over:
                self._over[vid]["seen_by"].add(monitor)

    def gone(self, agent: Agent, t: float) -> None:
        """The vehicle left the map."""
        if agent.id in self._over:
            self._end_stretch(agent, t)
        if agent.id in self._boxed:
            self._end_box(agent.id, t)

    def close(self, agents: dict[str, Agent], t: float) -> None:
        """The run has ended: every act in progress is written."""
        self._react(None, None, t)
        for agent in agents.values():
            self.gone(agent, t)

    # --- the yellow box -------------------------------------------------------------------------

    def _box(self, agent: Agent, v: VehicleState, t: float, snap: Snapshot, line: Line | None) -> None:
        box = self.network.junctions[v.junction].box if v.junction is not None else None
        inside = box is not None and v.speed_mps < STILL_MPS and _inside(v.x, v.y, box)
        if inside and v.junction is not None and v.id not in self._boxed:      # (only a junction has a box)
            ahead = [o.id for o in snap.vehicles if o.id != v.id and _ahead(v, o)]
            walkers = [p.id for p in snap.pedestrians if p.junction == v.junction and p.crossing is not None]
            out = self._exit(agent, v.junction, line.approach) if line else None
            queue = tuple(o.id for o in snap.vehicles if out is not None and o.edge == out
                          and o.lane_pos_m <= EXIT_M + 5.0 and o.speed_mps < 1.0)
            self._boxed[v.id] = dict(
                kind="stopped in the box", vehicle=v.id, type=agent.d.kind, driver=agent.driving(), t_s=t,
                junction=v.junction, approach=line.approach if line else None, light=line.crossed_on if line else None,
                on_call=agent.on_call, approaching=tuple(ahead + walkers), exit_queue=queue,
                turn=self._turn(agent, v.junction, line.approach) if line else None, seen_by=self._seen_by(v),
                why="stood still in the box behind " + (", ".join(ahead + walkers) or "nothing it could see"))
        elif not inside and v.id in self._boxed:
            self._end_box(v.id, t)

    def _end_box(self, vid: str, t: float) -> None:
        self.truth.act(Act(**self._boxed.pop(vid), until_s=t))

    # --- the speed limit ----------------------------------------------------------------------

    def _speeding(self, agent: Agent, v: VehicleState, t: float, limit: int, mph: int) -> None:
        """v at `mph` (rounded) where the limit is `limit`: a stretch over it begun, carried on or
        ended (`tick` calls it only where v is over the limit or a stretch of v's is open)."""
        over = self._over.get(v.id)
        if mph > limit:
            if over is None:
                over = self._over[v.id] = {"t_s": t, "max_mph": mph, "seen_by": set(), "on_call": agent.on_call,
                                           "driving": agent.driving(), "limit": limit}
            over["max_mph"] = max(over["max_mph"], mph)
        elif over is not None:
            self._end_stretch(agent, t)

    def _end_stretch(self, agent: Agent, t: float) -> None:
        o = self._over.pop(agent.id)
        self.truth.act(Act("exceeded the speed limit", agent.id, agent.d.kind, o["driving"], o["t_s"], until_s=t,
                           speed_mph=o["max_mph"], limit_mph=o["limit"], on_call=o["on_call"],
                           seen_by=tuple(sorted(o["seen_by"])),
                           why=f"speed factor {agent.speed_factor} [{agent.profile.name}]"
                           + (" on a call" if o["on_call"] else "")))


def ways_meet(a: tuple[str, str], b: tuple[str, str], lefthand: bool = True) -> bool:
    """Whether two ways through a four-arm junction, (arm in, arm out) each, cross or join: the
    same exit (one joins the other), or chords that cross with each arm's two lanes placed round
    the junction clockwise (left-hand traffic: the lane out, then the lane in; right-hand: in, out).
    Two ways in by the same arm are one queue, not a conflict (the queue is `_following`'s)."""
    if a[1] == b[1]:
        return True
    if a[0] == b[0] or not all(arm in _CLOCKWISE for arm in (*a, *b)):
        return a[0] != b[0]

    def place(arm: str, inbound: bool) -> int:
        return 2 * _CLOCKWISE.index(arm) + (inbound == lefthand)

    p1, p2 = sorted((place(a[0], True), place(a[1], False)))
    q1, q2 = place(b[0], True), place(b[1], False)
    return (p1 < q1 < p2) != (p1 < q2 < p2)


def _approaching(o: Other, after_s: float) -> str:
    """A road user about an act, as the truth lists it: "118 car main eta 3.8s (+1.2s)" (main: on
    the major road; +: came up that long after the act, while the vehicle was in the junction)."""
    return f"{o.id} {o.type}{' main' if o.main_road else ''} eta {o.eta_s:.1f}s" + \
        (f" (+{after_s:.1f}s)" if after_s > 0 else "")


def _inside(x: float, y: float, polygon: tuple[tuple[float, float], ...]) -> bool:
    """Whether a point is inside a polygon (even-odd rule)."""
    inside = False
    for (x1, y1), (x2, y2) in zip(polygon, polygon[1:] + polygon[:1]):
        if (y1 > y) != (y2 > y) and x < x1 + (y - y1) * (x2 - x1) / (y2 - y1):
            inside = not inside
    return inside


def _following(v: VehicleState, snap: Snapshot, besides: str) -> bool:
    """Whether v follows a road user (other than `besides`) closely: its braking is then the queue's."""
    return any(_ahead(v, o, FOLLOW_M) for o in snap.near(v.x, v.y, math.hypot(FOLLOW_M, ABREAST_M))
               if o.id not in (v.id, besides))


def _ahead(v: VehicleState, o: VehicleState, within_m: float = 12.0) -> bool:
    """Whether o is within a few metres in front of v (what v stands behind)."""
    dx, dy = o.x - v.x, o.y - v.y
    h = math.radians(v.heading_deg)
    along = dx * math.cos(h) + dy * math.sin(h)
    return 0.0 < along <= within_m and abs(-dx * math.sin(h) + dy * math.cos(h)) < ABREAST_M
