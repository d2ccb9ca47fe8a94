"""Who takes part in a run, and when and where each sets off: drawn once, from the seed, before the run.

Vehicles enter at the network's edges that come in from outside (a road end that is not a
junction) and leave by one that goes out, never back the way they came; a network with no road
ends (a closed grid) lets them set off on any edge and leave by any other. The mix of kinds and
drivers follows the config's shares. A routes file of the user's replaces the drawing
(sim_replay.routes_file), with the same kinds of Departure and Walk. Pedestrians walk between two arms of a junction, which takes
them over its crossings. Each road user gets a random stream of its own, so adding one does not
change the others' behaviour.
"""
from __future__ import annotations

import random
from dataclasses import dataclass

from sim_replay.sim_config import SimConfig
from sim_replay.sumo_net import Network

__all__ = ["Departure", "Walk", "plan"]

EMERGENCY_KINDS = ("ambulance", "fire_engine", "police_car", "unmarked")


@dataclass(frozen=True)
class Departure:
    id: str
    depart_s: float
    kind: str              # road_users type (an unmarked police car is a "car")
    role: str              # human, autonomous, emergency
    unmarked: bool
    entry: str             # edge ids
    exit: str
    route: tuple[str, ...] = ()   # the whole route where it is given (a routes file); else SUMO finds one


@dataclass(frozen=True)
class Walk:
    id: str
    depart_s: float
    from_edge: str
    to_edge: str


def _ends(network: Network) -> tuple[list[str], list[str], bool]:
    """Where vehicles enter and leave, and whether the network is closed (has no road ends)."""
    entries, exits = [], []
    for edge in sorted(network.net.getEdges(withInternal=False), key=lambda e: e.getID()):
        if not any(lane.allows("passenger") for lane in edge.getLanes()):
            continue
        if edge.getFromNode().getID() not in network.junctions:
            entries.append(edge.getID())
        if edge.getToNode().getID() not in network.junctions:
            exits.append(edge.getID())
    if not entries or not exits:           # a closed network: anywhere to anywhere else it leads to
        every = [e.getID() for e in sorted(network.net.getEdges(withInternal=False), key=lambda e: e.getID())
                 if any(lane.allows("passenger") for lane in e.getLanes())]
        return [e for e in every if len(_reachable(network, e)) > 1], every, True
    return entries, exits, False


def _reachable(network: Network, start: str) -> set[str]:
    """The edges a car can drive to from an edge (itself included), by the network's connections."""
    seen, todo = {start}, [network.net.getEdge(start)]
    while todo:
        edge = todo.pop()
        for nxt, connections in edge.getOutgoing().items():
            if nxt.getID() not in seen and any(c.getFromLane().allows("passenger") and c.getToLane().allows("passenger")
                                               for c in connections):
                seen.add(nxt.getID())
                todo.append(nxt)
    return seen


def plan(config: SimConfig, network: Network, rng: random.Random) -> tuple[list[Departure], list[Walk]]:
    """Every departure and walk of the run, in time order."""
    entries, exits, closed = _ends(network)
    window = max(1.0, config.duration_s * config.depart_within)
    departures = []
    for n in range(config.vehicles):
        r = rng.random()
        unmarked = False
        if r < config.emergency_share:
            kind, role = rng.choice(EMERGENCY_KINDS), "emergency"
            unmarked = kind == "unmarked"
            kind = "car" if unmarked else kind
        elif r < config.emergency_share + config.bus_share:
            kind, role = "bus", "human"
        elif r < config.emergency_share + config.bus_share + config.cyclist_share:
            kind, role = "cyclist", "human"
        else:
            kind, role = "car", "autonomous" if rng.random() < config.av_share else "human"
        entry = rng.choice(entries)
        back = network.net.getEdge(entry).getFromNode().getID()
        if closed:
            reach = _reachable(network, entry) - {entry}
            exit_ = rng.choice([e for e in exits if e in reach and network.net.getEdge(e).getToNode().getID() != back]
                               or sorted(reach))
        else:
            exit_ = rng.choice([e for e in exits if network.net.getEdge(e).getToNode().getID() != back])
        departures.append(Departure(str(101 + n), round(rng.uniform(0.0, window), 1), kind, role, unmarked,
                                    entry, exit_))
    departures.sort(key=lambda d: (d.depart_s, d.id))
    arms = {}
    for j in network.junctions.values():
        arms[j.id] = sorted({a.edge for a in j.approaches})
    walks = []
    junctions = sorted(j for j, its in arms.items() if len(its) >= 2)
    for n in range(config.pedestrians if junctions else 0):
        at = rng.choice(junctions)
        a, b = rng.sample(arms[at], 2)
        walks.append(Walk(f"p{n + 1}", round(rng.uniform(0.0, window), 1), a, _out_edge(network, b)))
    walks.sort(key=lambda w: (w.depart_s, w.id))
    return departures, walks


def _out_edge(network: Network, incoming: str) -> str:
    """The edge leaving the junction along the same arm as an incoming one (its other direction)."""
    edge = network.net.getEdge(incoming)
    src, dst = edge.getFromNode(), edge.getToNode()
    for out in dst.getOutgoing():
        if out.getToNode() is src:
            return out.getID()
    return incoming
