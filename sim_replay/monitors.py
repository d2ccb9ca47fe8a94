"""Monitors as a map places them: where each camera stands, where it looks and how far and wide it sees.

A SUMO network has no cameras, so a network comes with a monitors file (`NAME.monitors.json` beside
`NAME.net.xml`; `gaps sim --monitors FILE` for another network):

    {"monitors": [
        {"id": "m1", "junction": "j1", "x": -15.0, "y": 10.0, "heading_deg": 315.0,
         "range_m": 60.0, "fov_deg": 100.0, "watches": ["west"], "note": "..."}
    ]}

`id` names the source `monitor/<id>`; `junction` is the junction it records; `x`, `y` metres in the
network's coordinates; `heading_deg` where the middle of its field of view points (degrees
counter-clockwise from east, the map's convention); `range_m` and `fov_deg` its cone (the paper's
"cone of vision"). `watches` (the approaches it is aimed at) and `note` are for people reading the
file and for tests; run.start's map carries every field.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from store import GapsError

__all__ = ["Monitor", "MonitorsError", "read_monitors"]

_ID = set("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789._-")


class MonitorsError(GapsError, ValueError):
    """A monitors file that cannot be used, with what is wrong and where."""


@dataclass(frozen=True)
class Monitor:
    id: str
    junction: str
    x: float
    y: float
    heading_deg: float
    range_m: float
    fov_deg: float
    watches: tuple[str, ...] = ()
    note: str = ""

    def sees(self, x: float, y: float) -> bool:
        """Whether a point lies inside the cone: within range and within half the field of view of
        the heading. Geometry only; what a camera can tell about what it sees is the agents'."""
        dx, dy = x - self.x, y - self.y
        distance = math.hypot(dx, dy)
        if distance > self.range_m:
            return False
        if distance == 0.0 or self.fov_deg >= 360.0:
            return True
        off = (math.degrees(math.atan2(dy, dx)) - self.heading_deg + 180.0) % 360.0 - 180.0
        return abs(off) <= self.fov_deg / 2

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"id": self.id, "junction": self.junction, "x": self.x, "y": self.y,
                               "heading_deg": self.heading_deg, "range_m": self.range_m, "fov_deg": self.fov_deg}
        if self.watches:
            out["watches"] = list(self.watches)
        if self.note:
            out["note"] = self.note
        return out


def read_monitors(path: str | Path, junctions: set[str] | None = None) -> tuple[Monitor, ...]:
    """The monitors of a file; with `junctions`, each must name one of them."""
    path = Path(path)
    try:
        raw = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, ValueError) as e:
        raise MonitorsError(f"{path}: {e}") from e
    items = raw.get("monitors") if isinstance(raw, dict) else None
    if not isinstance(items, list):
        raise MonitorsError(f"{path}: expected {{\"monitors\": [...]}}")
    monitors = tuple(_monitor(item, f"{path}: monitor {n + 1}", junctions) for n, item in enumerate(items))
    seen: set[str] = set()
    for m in monitors:
        if m.id in seen:
            raise MonitorsError(f"{path}: two monitors are called {m.id!r}")
        seen.add(m.id)
    return monitors


def _monitor(item: Any, where: str, junctions: set[str] | None) -> Monitor:
    if not isinstance(item, dict):
        raise MonitorsError(f"{where}: not an object")
    ident, junction = item.get("id"), item.get("junction")
    if not isinstance(ident, str) or not ident or len(ident) > 64 or not set(ident) <= _ID:
        raise MonitorsError(f"{where}: id must be 1-64 of [A-Za-z0-9._-]")
    if not isinstance(junction, str) or (junctions is not None and junction not in junctions):
        raise MonitorsError(f"{where} ({ident}): junction {junction!r} is not a junction of the network"
                            + (f" ({', '.join(sorted(junctions))})" if junctions else ""))
    numbers = {}
    for key, low, high in (("x", -1e7, 1e7), ("y", -1e7, 1e7), ("heading_deg", -360.0, 360.0),
                           ("range_m", 0.0, 10_000.0), ("fov_deg", 0.0, 360.0)):
        value = item.get(key)
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not low <= value <= high or (key in ("range_m", "fov_deg") and value == 0):
            raise MonitorsError(f"{where} ({ident}): {key} must be a number in ({low:g}, {high:g}]")
        numbers[key] = float(value)
    watches = item.get("watches", [])
    if not isinstance(watches, list) or not all(isinstance(w, str) for w in watches):
        raise MonitorsError(f"{where} ({ident}): watches must be a list of approach names")
    note = item.get("note", "")
    return Monitor(ident, junction, numbers["x"], numbers["y"], numbers["heading_deg"] % 360.0,
                   numbers["range_m"], numbers["fov_deg"], tuple(watches), note if isinstance(note, str) else "")
