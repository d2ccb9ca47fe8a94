"""One act, one offence, checked from the raw events (issue 36): no incident of a run duplicates
another. Each incident is placed, from the run's own entity.state and run.start map alone (none of
the reasoner's passages or stretches), in the act it is of:

- a junction rule's: the vehicle's visit to the junction nearest it at the incident's time (its
  samples within VISIT_M of the centre, a visit ended by VISIT_GAP_S outside);
- speeding: the vehicle's stretch of raw speeds over its road's limit (whole mph, half up, as the
  sentence states it) that the incident's time falls in or within STRETCH_GAP_S of (a stretch
  ended by STRETCH_GAP_S without a sample over the limit); an incident no stretch of the vehicle's
  own record is near (a camera's reading alone) is an act of its own.

Two incidents of one vehicle and action in one visit or stretch are a duplicate.

    .venv/bin/python scripts/one_act_check.py gaps.db demo-sumo     # exit 1 on a duplicate
"""
from __future__ import annotations

import math
import sys
from collections import defaultdict

from shapely.geometry import LineString, Point

MPH_PER_MPS = 2.2369362920544
VISIT_M = 40.0
VISIT_GAP_S = 5.0
STRETCH_GAP_S = 3.0
SNAP_M = 15.0
SECOND = 1e9


def _distance_to_road(road: dict, x: float, y: float) -> float:
    """How far (x, y) is from the road's centre line (shapely: a library's geometry, not the reasoner's)."""
    return LineString([road["from"], road["to"]]).distance(Point(x, y))


def _limit(the_map: dict, x: float, y: float, road: object) -> float | None:
    named = {r["id"]: r.get("speed_limit_mph") for r in the_map.get("roads", [])}
    if road in named:
        return named[road]
    roads = the_map.get("roads", [])
    if not roads:
        return None
    nearest = min(roads, key=lambda r: _distance_to_road(r, x, y))
    return nearest.get("speed_limit_mph") if _distance_to_road(nearest, x, y) <= SNAP_M else None


def _spans(samples: list[tuple], inside) -> list[list[int]]:
    out: list[list[int]] = []
    for t, x, y, v, road in samples:
        if inside(x, y, v, road):
            if not out or t - out[-1][1] > (VISIT_GAP_S if inside.__name__ == "near" else STRETCH_GAP_S) * SECOND:
                out.append([t, t])
            out[-1][1] = t
    return out


def _which(spans: list[list[int]], t: int, within: float | None = None) -> int | None:
    def distance(i: int) -> float:
        a, b = spans[i]
        return 0 if a <= t <= b else min(abs(t - a), abs(t - b))
    best = min(range(len(spans)), key=distance, default=None)
    return best if best is not None and (within is None or distance(best) <= within) else None


def check(db: str, run: str) -> int:
    import reasoner
    from store import Store
    with Store.open_read_only(db) as store:
        the_map = next(store.events(run, kinds=["run.start"]))["body"].get("map") or {}
        states: dict[str, list[tuple]] = defaultdict(list)
        for e in store.events(run, kinds=["entity.state"]):
            b = e["body"]
            if isinstance(b.get("x"), (int, float)) and isinstance(b.get("y"), (int, float)):
                states[e["src"].split("/", 1)[1]].append((e["t"], b["x"], b["y"], b.get("speed_mps"), b.get("road")))
    with reasoner.open(db) as case:
        incidents = case.incidents(run)
    acts: dict[tuple, list[str]] = defaultdict(list)
    for inc in incidents:
        mine = states.get(inc.vehicle, [])
        key: tuple = ("alone", inc.id)
        if inc.action == "exceed the speed limit":
            def over(x, y, v, road):
                limit = _limit(the_map, x, y, road)
                return isinstance(v, (int, float)) and limit is not None and v * MPH_PER_MPS >= limit + 0.5
            found = _which(_spans(mine, over), inc.t, STRETCH_GAP_S * SECOND)
            key = ("stretch", found) if found is not None else key
        elif mine:
            _, x, y, _, _ = min(mine, key=lambda s: abs(s[0] - inc.t))
            j = min(the_map.get("junctions", []), key=lambda j: math.hypot(x - j["x"], y - j["y"]), default=None)
            if j is not None:
                def near(x, y, v, road, j=j):
                    return math.hypot(x - j["x"], y - j["y"]) <= VISIT_M
                found = _which(_spans(mine, near), inc.t)
                key = ("visit", j["id"], found) if found is not None else key
        acts[(inc.vehicle, inc.action, key)].append(inc.id)
    duplicates = {k: v for k, v in acts.items() if len(v) > 1}
    own = sum(1 for i in incidents if getattr(i, "found_in", "") == "own-record")
    several = sum(1 for i in incidents if len(getattr(i, "sources", ())) > 1)
    print(f"{run}: {len(incidents)} incidents, {own} found only in the vehicle's own record, {several} of several "
          f"records; duplicates by the raw-event check: {len(duplicates)}")
    for (vehicle, action, key), ids in duplicates.items():
        print(f"  duplicate: vehicle {vehicle} {action} {key}: {', '.join(ids)}")
    return 1 if duplicates else 0


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    sys.exit(check(sys.argv[1], sys.argv[2]))
