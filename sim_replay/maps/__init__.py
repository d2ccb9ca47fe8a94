"""The simulation's maps: each a folder of SUMO plain files, the network built from them and its monitors.

A map `NAME` is `maps/NAME/NAME.net.xml` (built by scripts/build-net.py from the plain files beside it)
and `maps/NAME/NAME.monitors.json` (sim_replay.monitors). `paper` is the paper's map and the default;
`town` is twenty junctions of the same kinds, room for the two hundred vehicles of a long run (the
benchmarks' run, bench/sim_runs.py).
"""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

__all__ = ["MAPS", "MapFiles", "map_files"]

MAPS = Path(__file__).resolve().parent


@dataclass(frozen=True)
class MapFiles:
    name: str
    net: Path
    monitors: Path


def map_files(name: str = "paper") -> MapFiles:
    """The network and monitors file of a bundled map."""
    folder = MAPS / name
    net, monitors = folder / f"{name}.net.xml", folder / f"{name}.monitors.json"
    if not net.is_file():
        known = sorted(p.name for p in MAPS.iterdir() if (p / f"{p.name}.net.xml").is_file())
        raise FileNotFoundError(f"no bundled map {name!r}; there are: {', '.join(known)} (or give a SUMO network "
                                "FILE.net.xml or configuration FILE.sumocfg)")
    return MapFiles(name, net, monitors)
