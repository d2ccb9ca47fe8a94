"""A SUMO user's own files for `gaps sim --map`: which network and routes a path names, and whether
the audit can judge that network at all.

`--map` takes a bundled map's name (sim_replay.maps), a `.net.xml`, or a `.sumocfg` whose
`net-file` and `route-files` are read as SUMO reads them (paths relative to the configuration's
folder, lists separated by commas or spaces). A network is judged only where its junctions mean
what the UK's rules are about; `refusal` says, in one line, the first reason one is not:

- it is built for right-hand traffic (SUMO's default; `netconvert --lefthand` rebuilds it): the
  rules are the Highway Code's, written for traffic on the left (turning right crosses the oncoming
  traffic, HC 170-183), and a right-hand network is not judged as if it were left-hand;
- a junction of a SUMO type with no UK counterpart: priority to the right or left
  (`right_before_left`, `left_before_right`), an all-way Stop, a turn on red, a level crossing, a
  zipper merge, a junction where SUMO lets everyone through (`unregulated`, and signals without
  conflict protection, `traffic_light_unregulated`). The types judged are `traffic_light` (its
  stop lines are TSRGD diagram 1001's), `priority` (the minor arms' Give Way lines, diagram 1003)
  and `priority_stop` (Stop lines, 1002.1);
- two approaches of one junction that come from the same compass sector: the events and the
  reasoner name an approach by where its traffic comes from (north, east, south, west), one each.
"""
from __future__ import annotations

import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

from sim_replay.sumo_net import Network
from store import GapsError

__all__ = ["OwnFiles", "OwnFilesError", "JUDGED_TYPES", "own_files", "read_sumocfg", "refusal"]

JUDGED_TYPES = ("traffic_light", "priority", "priority_stop")
NOT_UK = {
    "unregulated": "where SUMO lets every vehicle through without braking for another, which no UK junction "
                   "is (an unmarked crossroads still asks drivers to give way, HC 146), and where libsumo 1.28 "
                   "crashes when asked who yields to whom",
    "traffic_light_unregulated": "signals where SUMO lets a vehicle through on green without minding the "
                                 "vehicles it crosses, and where libsumo 1.28 crashes when asked who yields to whom",
    "right_before_left": "priority to traffic from the right, which no UK junction gives",
    "left_before_right": "priority to traffic from the left, which no UK junction gives",
    "allway_stop": "an all-way Stop, which the UK has not (a Stop line gives way to a major road, HC 171)",
    "traffic_light_right_on_red": "a turn against a red light, which is not lawful in the UK",
    "rail_signal": "a railway signal, which the audit does not model",
    "rail_crossing": "a level crossing, which the audit does not model",
    "zipper": "a zipper merge, which the audit does not model",
}


class OwnFilesError(GapsError, ValueError):
    """A user's network, configuration or routes file that cannot be used, with what and where."""


@dataclass(frozen=True)
class OwnFiles:
    """The files a `--map` path names: a network, the routes to drive on it (none: drawn) and its
    monitors file (None: no cameras)."""

    net: Path
    routes: tuple[Path, ...]
    monitors: Path | None


def own_files(map_arg: str, routes: tuple[Path, ...] = (), monitors: Path | None = None) -> OwnFiles | None:
    """The files of a `--map` value that is a path (None: a bundled map's name). `routes` given
    (`--routes`) replace a configuration's own; without `monitors`, NAME.monitors.json beside
    NAME.net.xml is the network's, as a bundled map's is."""
    path = Path(map_arg)
    if not (map_arg.endswith((".xml", ".sumocfg", ".cfg")) or "/" in map_arg):
        return None
    config = map_arg.endswith((".sumocfg", ".cfg"))
    if not path.is_file():
        raise OwnFilesError(f"no such {'configuration' if config else 'network'} file: {path} (--map takes a "
                            "bundled map, a FILE.net.xml or a FILE.sumocfg)")
    net, cfg_routes = read_sumocfg(path) if config else (path, ())
    if monitors is None:
        beside = net.with_name(net.name.removesuffix(".xml").removesuffix(".net") + ".monitors.json")
        monitors = beside if beside.is_file() else None
    return OwnFiles(net, routes or cfg_routes, monitors)


def read_sumocfg(path: Path) -> tuple[Path, tuple[Path, ...]]:
    """A SUMO configuration's network and route files, as SUMO resolves them (relative to the
    configuration's folder). Additional files are refused: they may change the signal programmes
    or write outputs, and `gaps sim` would not run what the configuration describes."""
    try:
        root = ET.parse(path).getroot()
    except (ET.ParseError, OSError) as e:
        raise OwnFilesError(f"{path}: not a SUMO configuration ({e})") from e
    values: dict[str, list[str]] = {}
    for element in root.iter():
        value = element.get("value")
        if value is not None:
            values.setdefault(element.tag, []).extend(v for v in value.replace(",", " ").split() if v)
    base = path.resolve().parent
    nets = values.get("net-file", [])
    if len(nets) != 1:
        raise OwnFilesError(f"{path}: names {'no' if not nets else len(nets)} net-file; a configuration for "
                            "gaps sim names one network (<net-file value=\"FILE.net.xml\"/>)")
    extra = values.get("additional-files", [])
    if extra:
        raise OwnFilesError(f"{path}: additional-files ({', '.join(extra)}) are not read by gaps sim, which runs "
                            "a network and its routes only; leave them out, or give --map FILE.net.xml --routes "
                            "FILE.rou.xml")
    net = base / nets[0]
    if not net.is_file():
        raise OwnFilesError(f"{path}: its net-file {nets[0]} is not there ({net})")
    routes = tuple(base / r for r in values.get("route-files", []))
    for r in routes:
        if not r.is_file():
            raise OwnFilesError(f"{path}: its route file {r.name} is not there ({r})")
    return net, routes


def refusal(network: Network) -> str | None:
    """Why the audit cannot judge a network (one line, naming the file and the junction), or None."""
    name = network.path.name
    if not network.lefthand:
        return (f"{name} is built for right-hand traffic; the rules judged are the UK's, for traffic on the left: "
                f"rebuild it with netconvert --sumo-net-file {name} --lefthand -o NEW.net.xml")
    for j in network.junctions.values():
        if j.sumo_type not in JUDGED_TYPES:
            why = NOT_UK.get(j.sumo_type, "which the audit does not judge")
            return (f"{name}: junction {j.id} is of SUMO's type {j.sumo_type}, {why}; give it the type "
                    "traffic_light, priority or priority_stop")
        seen: dict[str, str] = {}
        for a in j.approaches:
            if a.name in seen:
                return (f"{name}: junction {j.id}: the approaches on edges {seen[a.name]} and {a.edge} both come "
                        f"from the {a.name}; the events name a junction's approaches by compass sector (north, "
                        "east, south, west), one each, so two arms less than 90 degrees apart can fall in one")
            seen[a.name] = a.edge
    return None


def load_network(path: Path) -> Network:
    """A network file read as the simulation reads it, or OwnFilesError saying it is not one (sumolib
    raises whatever its parser met; a user's file is reported, not a traceback)."""
    from xml.sax import SAXException

    from sim_replay.sumo_net import read_network
    try:
        network = read_network(path)
    except (SAXException, OSError, ValueError, KeyError, IndexError, AttributeError, TypeError) as e:
        raise OwnFilesError(f"{path}: not a SUMO network ({type(e).__name__}: {e})") from e
    if not network.net.getEdges(withInternal=False):
        raise OwnFilesError(f"{path}: not a SUMO network (it has no edges; --map takes a FILE.net.xml that "
                            "netconvert or netgenerate made, or a FILE.sumocfg)")
    return network


def check(net: Path, routes: tuple[Path, ...], config) -> tuple[int, int] | None:
    """Before a run on a user's files: the network is readable and judged (`refusal`), and its
    routes files name what the network has. Returns the routes' (vehicles, pedestrians), or None
    where the demand is drawn."""
    from sim_replay.faults import stream
    from sim_replay.routes_file import read_routes

    network = load_network(net)
    why_not = refusal(network)
    if why_not is not None:
        raise OwnFilesError(why_not)
    if not routes:
        return None
    demand = read_routes(list(routes), network, config, stream(config.seed, "demand"))
    if not demand.departures and not demand.walks:
        raise OwnFilesError(f"{', '.join(p.name for p in routes)}: no vehicle or person to simulate")
    return len(demand.departures), len(demand.walks)
