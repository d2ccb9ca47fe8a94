"""A SUMO routes file (`.rou.xml`) as the run's demand: who sets off when, on which route.

`gaps sim --routes FILE.rou.xml` (or a `.sumocfg`'s route-files) replaces the drawn demand
(sim_replay.demand.plan) with the user's. Read here, before the run, so that a route the network
cannot carry is an error naming the vehicle and the edge, not a vehicle silently left out:

    <vType id vClass>                 the kind of road user (VCLASS_KINDS); no vClass: a car
    <route id edges>                  a named route for vehicles to refer to
    <vehicle id depart route|<route>> one vehicle on a whole route
    <trip id depart from to [via]>    one vehicle; the route is the shortest for its class
    <flow id begin end number|period|vehsPerHour|probability ...>
                                      vehicles `ID.0`, `ID.1`, ... as SUMO names them, evenly
                                      spaced (`probability`: each second, drawn from the run's seed)
    <person id depart><walk edges|from to/></person>, <personTrip from to>
                                      one pedestrian, one walk

The road users are renumbered as the simulation names its own (vehicles 101, 102, ... and
pedestrians p1, p2, ... in order of departure), and the ground truth keeps each one's id in the
file. Who drives (a person, an automated driving system) and whether an emergency vehicle is on a
call are drawn from the run's config as for drawn demand: SUMO's files do not say. Anything else
in the file (distributions, containers, stops, departures at a time SUMO decides) is refused.
"""
from __future__ import annotations

import math
import random
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

from sim_replay.demand import Departure, Walk
from sim_replay.own_network import OwnFilesError
from sim_replay.sim_config import SimConfig
from sim_replay.sumo_net import Network

__all__ = ["FileDemand", "read_routes"]

# SUMO's vehicle classes as the simulation's kinds of road user (road_users.TYPES): a van
# (`delivery`) or taxi is driven under the same rules as a car
VCLASS_KINDS = {"passenger": "car", "private": "car", "taxi": "car", "delivery": "car", "hov": "car",
                "evehicle": "car", "custom1": "car", "custom2": "car", "bus": "bus", "coach": "bus",
                "bicycle": "cyclist", "emergency": "ambulance", "authority": "police_car"}
DEFAULT_TYPES = {"DEFAULT_VEHTYPE": "passenger", "DEFAULT_BIKETYPE": "bicycle", "DEFAULT_TAXITYPE": "taxi"}
IGNORED = ("param",)
MAX_VEHICLES = 100_000     # as gaps sim --vehicles


@dataclass(frozen=True)
class FileDemand:
    """The departures and walks of the routes files, with each road user's id in its file."""

    departures: list[Departure]
    walks: list[Walk]
    file_ids: dict[str, str]           # our id -> the file's


@dataclass(frozen=True)
class _Vehicle:
    file_id: str
    depart_s: float
    vclass: str
    route: tuple[str, ...]
    where: str


def read_routes(paths: tuple[Path, ...] | list[Path], network: Network, config: SimConfig,
                rng: random.Random) -> FileDemand:
    """Every vehicle and pedestrian of the routes files, checked against the network."""
    vehicles: list[_Vehicle] = []
    persons: list[tuple[str, float, str, str]] = []
    for path in paths:
        _read(Path(path), network, config, rng, vehicles, persons)
    if len(vehicles) > MAX_VEHICLES:
        raise OwnFilesError(f"{len(vehicles):,} vehicles in the routes files; gaps sim takes up to {MAX_VEHICLES:,}")
    vehicles.sort(key=lambda v: v.depart_s)
    persons.sort(key=lambda p: p[1])
    departures, file_ids = [], {}
    for n, v in enumerate(vehicles):
        ident = str(101 + n)
        kind, role, unmarked = _who(v.vclass, config, rng)
        departures.append(Departure(ident, round(v.depart_s, 1), kind, role, unmarked, v.route[0], v.route[-1],
                                    v.route))
        file_ids[ident] = v.file_id
    walks = []
    for n, (file_id, depart_s, a, b) in enumerate(persons):
        walks.append(Walk(f"p{n + 1}", round(depart_s, 1), a, b))
        file_ids[f"p{n + 1}"] = file_id
    return FileDemand(departures, walks, file_ids)


def _who(vclass: str, config: SimConfig, rng: random.Random) -> tuple[str, str, bool]:
    """The kind, role and unmarked flag of a vehicle of a SUMO class."""
    kind = VCLASS_KINDS[vclass]
    if kind in ("ambulance", "police_car"):
        return kind, "emergency", False
    if kind == "car":
        return kind, "autonomous" if rng.random() < config.av_share else "human", False
    return kind, "human", False


def _read(path: Path, network: Network, config: SimConfig, rng: random.Random, vehicles: list[_Vehicle],
          persons: list[tuple[str, float, str, str]]) -> None:
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        raise OwnFilesError(f"{path}: not a SUMO routes file ({e})") from e
    if root.tag != "routes":
        raise OwnFilesError(f"{path}: not a SUMO routes file (its root is <{root.tag}>, not <routes>)")
    types = dict(DEFAULT_TYPES)
    named: dict[str, tuple[str, ...]] = {}
    name = path.name
    for element in root:
        tag, ident = element.tag, element.get("id", "")
        where = f"{name}: {tag} {ident!r}"
        if tag == "vType":
            vclass = element.get("vClass", "passenger")
            if vclass not in VCLASS_KINDS:
                raise OwnFilesError(f"{where}: vehicle class {vclass!r} is not one the simulation has (it has "
                                    f"{', '.join(sorted(set(VCLASS_KINDS)))})")
            types[ident] = vclass
        elif tag == "route":
            named[ident] = _edges(element.get("edges", ""), where)
        elif tag in ("vehicle", "trip", "flow"):
            other = sorted({e.tag for e in element} - {"route", "param"})
            if other:
                raise OwnFilesError(f"{where}: <{other[0]}> in a {tag} is not read by gaps sim (its agents decide "
                                    "where it stops)")
            vclass = _vclass(element, types, where)
            route = _route(element, named, network, vclass, where)
            for n, depart in enumerate(_departs(element, config, rng, where)):
                file_id = f"{ident}.{n}" if tag == "flow" else ident
                vehicles.append(_Vehicle(file_id, depart, vclass, route, where))
        elif tag == "person":
            persons.append((ident, _depart(element.get("depart"), where), *_walk(element, network, where)))
        elif tag not in IGNORED:
            raise OwnFilesError(f"{where}: <{tag}> is not read by gaps sim (it reads vType, route, vehicle, trip, "
                                "flow and person)")


def _vclass(element: ET.Element, types: dict[str, str], where: str) -> str:
    vtype = element.get("type", "DEFAULT_VEHTYPE")
    if vtype not in types:
        raise OwnFilesError(f"{where}: type {vtype!r} is not defined before it in the file")
    return types[vtype]


def _edges(text: str, where: str) -> tuple[str, ...]:
    edges = tuple(text.split())
    if not edges:
        raise OwnFilesError(f"{where}: a route with no edges")
    return edges


def _route(element: ET.Element, named: dict[str, tuple[str, ...]], network: Network, vclass: str,
           where: str) -> tuple[str, ...]:
    """The vehicle's whole route, every edge in the network and each leading to the next for its class."""
    inner = element.find("route")
    if inner is not None:
        edges = _edges(inner.get("edges", ""), where)
    elif (name := element.get("route")) is not None:
        if name not in named:
            raise OwnFilesError(f"{where}: route {name!r} is not defined before it in the file")
        edges = named[name]
    elif (start := element.get("from")) and (end := element.get("to")):
        stops = [start, *element.get("via", "").split(), end]
        for e in stops:
            _edge(network, e, where)
        edges = (stops[0],)
        for a, b in zip(stops, stops[1:]):
            found, _ = network.net.getShortestPath(network.net.getEdge(a), network.net.getEdge(b), vClass=vclass)
            if not found:
                raise OwnFilesError(f"{where}: no way from edge {a!r} to {b!r} for a {vclass} vehicle")
            edges += tuple(e.getID() for e in found[1:])
    else:
        raise OwnFilesError(f"{where}: no route (give route=, a <route edges=...>, or from= and to=)")
    for a, b in zip(edges, edges[1:]):
        ea, eb = _edge(network, a, where), _edge(network, b, where)
        if not any(c.getFromLane().allows(vclass) and c.getToLane().allows(vclass)
                   for c in ea.getOutgoing().get(eb, ())):
            raise OwnFilesError(f"{where}: edge {a!r} does not lead to {b!r} for a {vclass} vehicle")
    _edge(network, edges[0], where)
    return edges


def _edge(network: Network, ident: str, where: str):
    if not network.net.hasEdge(ident) or network.net.getEdge(ident).isSpecial():
        raise OwnFilesError(f"{where}: the network {network.path.name} has no edge {ident!r}")
    return network.net.getEdge(ident)


def _depart(value: str | None, where: str) -> float:
    try:
        depart = float(value) if value is not None else math.nan
    except ValueError:
        depart = math.nan
    if not 0.0 <= depart < 1e7:
        raise OwnFilesError(f"{where}: depart {value!r} is not a time in seconds (gaps sim departs each road user "
                            "at a time the file gives)")
    return depart


def _departs(element: ET.Element, config: SimConfig, rng: random.Random, where: str) -> list[float]:
    """When each vehicle of a vehicle, trip or flow sets off: a flow's as SUMO spaces them, from
    `begin` to `end` (default: the run's end), those after the run's end left out."""
    if element.tag != "flow":
        return [_depart(element.get("depart"), where)]
    begin = _depart(element.get("begin", "0"), where)
    end = _depart(element.get("end"), where) if element.get("end") is not None else config.duration_s
    if end <= begin:
        raise OwnFilesError(f"{where}: its end {end:g} s is not after its begin {begin:g} s")
    key, x = _rate(element, where)
    stop = min(end, config.duration_s)
    if key == "probability":
        return [float(t) for t in range(math.ceil(begin), math.ceil(stop)) if rng.random() < x]
    period = {"number": (end - begin) / x, "period": x, "vehsPerHour": 3600.0 / x}[key]
    count = max(0, math.ceil((stop - begin) / period))
    if key == "number":
        count = min(count, int(x))
    if count > MAX_VEHICLES:
        raise OwnFilesError(f"{where}: more than {MAX_VEHICLES:,} vehicles within the run, which gaps sim takes "
                            "at most")
    return [begin + n * period for n in range(count)]


def _rate(element: ET.Element, where: str) -> tuple[str, float]:
    """A flow's one way of saying how many: number, period, vehsPerHour or probability."""
    for key in ("number", "period", "vehsPerHour", "probability"):
        value = element.get(key)
        if value is None:
            continue
        try:
            x = float(value)
        except ValueError:
            x = -1.0
        if not 0 < x < math.inf or (key == "probability" and x > 1):
            raise OwnFilesError(f"{where}: {key} {value!r} is not a positive number" +
                                (" up to 1" if key == "probability" else ""))
        return key, x
    raise OwnFilesError(f"{where}: a flow needs number, period, vehsPerHour or probability")


def _walk(element: ET.Element, network: Network, where: str) -> tuple[str, str]:
    """A person's one walk: from its first edge to its last."""
    stages = [e for e in element if e.tag != "param"]
    if len(stages) != 1 or stages[0].tag not in ("walk", "personTrip"):
        raise OwnFilesError(f"{where}: gaps sim reads a person with one <walk> or <personTrip>, not "
                            f"{', '.join('<' + s.tag + '>' for s in stages) or 'none'}")
    stage = stages[0]
    edges = stage.get("edges", "").split() or [stage.get("from", ""), stage.get("to", "")]
    if not all(edges):
        raise OwnFilesError(f"{where}: a walk needs edges= or from= and to=")
    for e in edges:
        _edge(network, e, where)
    return edges[0], edges[-1]
