"""Every margin within its stated uncertainty of a check computed from the raw events (issue 36).

Each incident's margin (red light, amber, speeding, the Stop line, give way, box junction) is measured again here from the run's own
events, read through the store's public API alone: the vehicle's entity.state samples, the
signal.state events and the run.start map. None of the reasoner's passages, stretches or margin
code is used; the reasoner is asked only for its incidents and the margins they state.

- red light ("seconds after red the stop line was crossed"): the moment the vehicle's path
  crosses a stop line of the junction the act names (the segment between two consecutive
  samples that meets the line, moving towards the junction's centre), linearly interpolated
  between those two samples; red's onset is the first of the unbroken red / red-and-amber reports
  of that approach's signal before it. On red-and-amber ("seconds into red-and-amber") the onset
  is the first red-and-amber report of that run. The signal's first report of the approach being
  red means red began at or before it: the margin is then "at least".
- amber ("metres from the stop line when amber came"): the last change of that approach's signal
  to amber before the crossing; the vehicle's position then, linearly interpolated between its
  two samples around it, and its perpendicular distance to the stop line (positive before it).
- speeding ("mph over the speed limit"): the vehicle's entity.state samples on the road the act
  names (its `road` field where that is a road of the map, else the map road nearest, within
  SNAP_M), over that road's speed_limit_mph, in runs no more than STRETCH_GAP_S
  apart; the run that meets the act's span where the act is a speeding stretch (else the
  incident's moment), within STRETCH_GAP_S; its fastest speed in mph less the limit. Where no such
  run is near, the raw events show no excess near the act: the margin is then within when it
  states none either (not over by more than its uncertainty), whatever the exact shortfall (the
  fastest sample on the road within STRETCH_GAP_S of the act is shown).

- Stop line, never stood ("slowest measured speed before the Stop line"): the vehicle's crossing
  of a stop line of the act's junction as for red; its entity.state samples before it (and those
  after it still within ON_LINE_M of the line, the position tolerance: they may be on it), two
  consecutive ones whose way meets the stretch from LINE_REACH_M past that line to AT_LINE_M before
  it; their slowest speed in mph.
- Stop line, stood ("seconds stationary at the Stop line"): the longest run of consecutive
  samples under 0.5 mph before the crossing whose last is from LINE_REACH_M past the line to
  AT_LINE_M before it; its first to its last sample.
- give way ("deceleration of the other road user"): the two samples of the other road user the
  margin cites, read again from the raw events (its own entity.state at those moments, or the
  camera's observation by its source and seq): the drop in speed over the time between them.
- box junction ("seconds stopped in the box junction"): the vehicle's samples under 0.5 mph inside
  the act's junction's yellow box polygon (the map's `box`; a box given as `true` is unchecked),
  near the incident's moment: the unbroken run of them around it, its first to its last sample.

A margin is within when |script - reasoner| <= the reasoner's uncertainty + SLACK (the script's
own rounding and interpolation: the reasoner rounds seconds to 1 ms, metres to 1 cm, mph to 0.1).
An "at least" bound is contradicted where the raw events show red's onset (a report of another
colour before it) or give less than the bound by more than the uncertainty.

    .venv/bin/python scripts/margin_check.py gaps.db demo-sumo      # exit 1 on a margin outside
    .venv/bin/python scripts/margin_check.py gaps.db RUN judged.json  # the incidents as `gaps incidents
                                                                      # --run RUN --json` gave them
"""
from __future__ import annotations

import math
import sys
from collections import defaultdict
from dataclasses import dataclass, field
from typing import Any

from shapely.geometry import LineString, Point

MPH_PER_MPS = 2.2369362920544
SECOND = 1e9
STRETCH_GAP_S = 3.0
NEVER_OVER = "never over the limit within STRETCH_GAP_S of the act"
SNAP_M = 15.0                 # a sample without a road of the map is on the nearest road this close
LINE_REACH_M = 1.0            # a path meeting a stop line within this of its ends still crosses it
SLACK = {"s": 0.002, "m": 0.02, "mph": 0.06, "m/s²": 0.01}
STILL_MPS = 0.5 / MPH_PER_MPS  # a speed that rounds to 0 mph
AT_LINE_M = 5.0               # a standstill whose last sample is this close before the line is at it
ON_LINE_M = 0.1               # a sample this close past a line (the default position tolerance) may be on it
BOX_NEAR_S = 30.0             # a box standstill this close to the incident's moment is its act
RED = ("red", "red_amber")


@dataclass
class Raw:
    """What the check reads of a run: its map, each vehicle's samples (t, x, y, speed, road), and
    each approach's signal reports (t, colour) in order."""
    the_map: dict
    tracks: dict[str, list[tuple]] = field(default_factory=lambda: defaultdict(list))
    signals: dict[tuple[str, str], list[tuple[int, str]]] = field(default_factory=lambda: defaultdict(list))
    measured: dict[tuple[str, int], tuple[int, float]] = field(default_factory=dict)   # a camera's (src, seq): t, speed


@dataclass(frozen=True)
class Result:
    incident: str
    kind: str
    reasoner: float
    uncertainty: float | None
    bound: str | None
    script: float | None
    within: bool | None           # None: the raw events hold nothing to check it by
    note: str = ""

    def line(self) -> str:
        got = "-" if self.script is None else f"{self.script:.3f}"
        u = "-" if self.uncertainty is None else f"{self.uncertainty:g}"
        return (f"  {self.incident:<28} {self.kind:<10} reasoner {self.reasoner:>9.3f}{' (at least)' if self.bound else ''}"
                f" ± {u:<6} script {got:>9}  {self.note}")


def read(store: Any, run: str) -> Raw:
    """The run's map, samples and signal reports, through the store's public API."""
    start = next(store.events(run, kinds=["run.start"]), None)
    raw = Raw((start or {}).get("body", {}).get("map") or {})
    for e in store.events(run, kinds=["entity.state", "signal.state", "monitor.observation"]):
        b = e["body"]
        if e["kind"] == "monitor.observation":
            if isinstance(b.get("speed_mps"), (int, float)):
                raw.measured[(e["src"], e["seq"])] = (e["t"], b["speed_mps"])
        elif e["kind"] == "signal.state":
            raw.signals[(str(b.get("junction")), str(b.get("approach")))].append((e["t"], b.get("colour")))
        elif isinstance(b.get("x"), (int, float)) and isinstance(b.get("y"), (int, float)):
            raw.tracks[e["src"].split("/", 1)[1]].append((e["t"], b["x"], b["y"], b.get("speed_mps"), b.get("road")))
    for samples in list(raw.tracks.values()) + list(raw.signals.values()):
        samples.sort(key=lambda s: s[0])
    return raw


# --- geometry --------------------------------------------------------------------------------------

def _meet(p: tuple, q: tuple, a: list, b: list) -> float | None:
    """The fraction along p->q where it meets the line a-b (reached LINE_REACH_M past its ends)."""
    rx, ry = q[0] - p[0], q[1] - p[1]
    sx, sy = b[0] - a[0], b[1] - a[1]
    den = rx * sy - ry * sx
    if den == 0:
        return None
    f = ((a[0] - p[0]) * sy - (a[1] - p[1]) * sx) / den
    g = ((a[0] - p[0]) * ry - (a[1] - p[1]) * rx) / den
    reach = LINE_REACH_M / max(math.hypot(sx, sy), 1e-9)
    return f if 0.0 <= f <= 1.0 and -reach <= g <= 1.0 + reach else None


def _to_line(x: float, y: float, line: dict, centre: tuple[float, float]) -> float:
    """Perpendicular metres from (x, y) to the stop line, positive on the side away from the centre."""
    (ax, ay), (bx, by) = line["from"], line["to"]
    nx, ny = -(by - ay), bx - ax
    n = math.hypot(nx, ny)
    d = ((x - ax) * nx + (y - ay) * ny) / n
    side = ((centre[0] - ax) * nx + (centre[1] - ay) * ny) / n
    return -d if side > 0 else d


def _junctions(raw: Raw, name: str | None) -> list[dict]:
    js = raw.the_map.get("junctions", [])
    return [j for j in js if str(j.get("id")) == name] or js


def crossing(raw: Raw, vehicle: str, junction: str | None, near_t: int) -> tuple[int, dict, dict] | None:
    """(moment, stop line, junction) of the vehicle's crossing of a stop line towards the
    junction's centre nearest `near_t`."""
    track, found = raw.tracks.get(vehicle, []), []
    for j in _junctions(raw, junction):
        centre = (j["x"], j["y"])
        for line in j.get("stop_lines", []):
            for p, q in zip(track, track[1:]):
                f = _meet((p[1], p[2]), (q[1], q[2]), line["from"], line["to"])
                if f is None or math.dist((q[1], q[2]), centre) >= math.dist((p[1], p[2]), centre):
                    continue
                found.append((round(p[0] + f * (q[0] - p[0])), line, j))
    return min(found, key=lambda c: abs(c[0] - near_t), default=None)


def position_at(track: list[tuple], t: int) -> tuple[float, float] | None:
    for p, q in zip(track, track[1:]):
        if p[0] <= t <= q[0]:
            f = 0.0 if q[0] == p[0] else (t - p[0]) / (q[0] - p[0])
            return p[1] + f * (q[1] - p[1]), p[2] + f * (q[2] - p[2])
    return None


# --- the three margins -----------------------------------------------------------------------------

def red(raw: Raw, inc: dict, into_red_amber: bool) -> tuple[float | None, bool, str]:
    """(seconds, red showing at the signal's first report, note)."""
    c = crossing(raw, inc["vehicle"], _where(inc), inc["t"])
    if c is None:
        return None, False, "no stop-line crossing in the vehicle's entity.state"
    t, line, j = c
    reports = raw.signals.get((str(j["id"]), str(line.get("approach"))), [])
    before = [r for r in reports if r[0] <= t]
    if not before or before[-1][1] not in RED:
        return None, False, f"light at the crossing: {before[-1][1] if before else 'none reported'}"
    colours = RED if not into_red_amber else ("red_amber",)
    i = len(before) - 1
    while i > 0 and before[i - 1][1] in colours:
        i -= 1
    return (t - before[i][0]) / SECOND, i == 0, f"crossed {j['id']}/{line.get('approach')}"


def amber(raw: Raw, inc: dict) -> tuple[float | None, str]:
    c = crossing(raw, inc["vehicle"], _where(inc), inc["t"])
    if c is None:
        return None, "no stop-line crossing in the vehicle's entity.state"
    t, line, j = c
    reports = [r for r in raw.signals.get((str(j["id"]), str(line.get("approach"))), []) if r[0] <= t]
    changes = [r for k, r in enumerate(reports) if r[1] == "amber" and (k == 0 or reports[k - 1][1] != "amber")]
    if not changes:
        return None, "no change to amber before the crossing"
    at = position_at(raw.tracks[inc["vehicle"]], changes[-1][0])
    if at is None:
        return None, "no samples around amber's onset"
    return _to_line(at[0], at[1], line, (j["x"], j["y"])), f"amber on {j['id']}/{line.get('approach')}"


def speeding(raw: Raw, inc: dict, road: str | None) -> tuple[float | None, str]:
    limits = {str(r["id"]): r.get("speed_limit_mph") for r in raw.the_map.get("roads", [])}
    limit = limits.get(str(road))
    if limit is None:
        return None, f"road {road} has no limit in the map"
    over = [s for s in raw.tracks.get(inc["vehicle"], [])
            if on_road(raw, s) == str(road) and isinstance(s[3], (int, float)) and s[3] * MPH_PER_MPS > limit]
    stretches: list[list[tuple]] = []
    for s in over:
        if not stretches or s[0] - stretches[-1][-1][0] > STRETCH_GAP_S * SECOND:
            stretches.append([])
        stretches[-1].append(s)
    act = inc.get("act") or {}
    stretch = act.get("kind") == "speeding stretch"
    lo, hi = (act["start"], act["end"]) if stretch else (inc["t"], inc["t"])

    def apart(st: list[tuple]) -> float:
        return max(0, st[0][0] - hi, lo - st[-1][0])
    best = min(stretches, key=apart, default=None)
    if best is None or apart(best) > STRETCH_GAP_S * SECOND:       # never over: its fastest near the act
        near = [s for s in raw.tracks.get(inc["vehicle"], []) if on_road(raw, s) == str(road)
                and lo - STRETCH_GAP_S * SECOND <= s[0] <= hi + STRETCH_GAP_S * SECOND and isinstance(s[3], (int, float))]
        if not near:
            return None, f"no entity.state on road {road} in or near the act"
        return max(s[3] for s in near) * MPH_PER_MPS - limit, NEVER_OVER + f" ({len(near)} samples on road {road})"
    return max(s[3] for s in best) * MPH_PER_MPS - limit, f"{len(best)} samples over on road {road}"


def on_road(raw: Raw, sample: tuple) -> str | None:
    """The road a sample is on: its own `road` field where that names a road of the map, else the
    map's road nearest its position (within SNAP_M)."""
    roads = raw.the_map.get("roads", [])
    if any(str(r["id"]) == str(sample[4]) for r in roads):
        return str(sample[4])
    nearest = min(roads, key=lambda r: _off_road(r, sample[1], sample[2]), default=None)
    return str(nearest["id"]) if nearest is not None and _off_road(nearest, sample[1], sample[2]) <= SNAP_M else None


def _off_road(road: dict, x: float, y: float) -> float:
    """How far (x, y) is from the road's centre line (shapely: a library's geometry, not the reasoner's)."""
    return LineString([road["from"], road["to"]]).distance(Point(x, y))


def _where(inc: dict) -> str | None:
    act = inc.get("act") or {}
    return act.get("where") if act.get("kind") == "junction passage" else None


def _road(inc: dict) -> str | None:
    act = inc.get("act") or {}
    if act.get("kind") == "speeding stretch" and act.get("where") is not None:
        return str(act["where"])
    method = inc["margin"].get("method", "")
    for marker in (" on road ", "against road "):
        if marker in method:
            return method.split(marker, 1)[1].split(",")[0].split("'")[0].strip()
    return None


# --- the Stop line, Give Way and box margins ---------------------------------------------------------

def _approach(raw: Raw, inc: dict) -> tuple[list[tuple], dict, dict, int] | str:
    """The vehicle's samples before its crossing of a stop line of the act's junction, with the
    line, the junction and the moment; else why there are none."""
    c = crossing(raw, inc["vehicle"], _where(inc), inc["t"])
    if c is None:
        return "no stop-line crossing in the vehicle's entity.state"
    t, line, j = c
    return [s for s in raw.tracks[inc["vehicle"]] if s[0] <= t], line, j, t


def stop_slowest(raw: Raw, inc: dict) -> tuple[float | None, str]:
    found = _approach(raw, inc)
    if isinstance(found, str):
        return None, found
    before, line, j, t = found
    centre = (j["x"], j["y"])
    after = [s for s in raw.tracks[inc["vehicle"]] if s[0] > t]
    while after and _to_line(after[0][1], after[0][2], line, centre) >= -ON_LINE_M:
        before.append(after.pop(0))          # within the position tolerance of the line: not yet past it
    timed = [s for s in before if isinstance(s[3], (int, float))]
    near = set()
    for p, q in zip(timed, timed[1:]):
        dp, dq = _to_line(p[1], p[2], line, centre), _to_line(q[1], q[2], line, centre)
        if min(dp, dq) <= AT_LINE_M and max(dp, dq) >= -LINE_REACH_M:
            near |= {p, q}
    if not near:
        return None, "no interval between samples reaches the line's stretch"
    return min(s[3] for s in near) * MPH_PER_MPS, f"{len(near)} samples around {j['id']}'s line"


def stop_stood(raw: Raw, inc: dict) -> tuple[float | None, str]:
    found = _approach(raw, inc)
    if isinstance(found, str):
        return None, found
    before, line, j, _ = found
    runs: list[list[tuple]] = []
    still = False
    for s in before:
        now = isinstance(s[3], (int, float)) and s[3] <= STILL_MPS
        if now and still:
            runs[-1].append(s)
        elif now:
            runs.append([s])
        still = now
    centre = (j["x"], j["y"])
    at = [r for r in runs if -LINE_REACH_M <= _to_line(r[-1][1], r[-1][2], line, centre) <= AT_LINE_M]
    if not at:
        return None, "no standstill at the line in the raw events"
    return max((r[-1][0] - r[0][0]) / SECOND for r in at), f"{len(at)} standstill(s) at {j['id']}"


def give_way(raw: Raw, inc: dict) -> tuple[float | None, str]:
    cited = inc["margin"].get("evidence") or []
    if len(cited) != 2:
        return None, "the margin cites no two samples"
    speeds = []
    for e in cited:
        src = str(e.get("src", ""))
        if src.startswith("monitor/"):
            speeds.append(raw.measured.get((src, e.get("seq"))))
        else:
            found = next((s for s in raw.tracks.get(src.split("/", 1)[-1], []) if s[0] == e.get("t")), None)
            speeds.append((found[0], found[3]) if found and isinstance(found[3], (int, float)) else None)
    a, b = speeds
    if a is None or b is None or b[0] <= a[0]:
        return None, "the cited samples are not in the run's entity.state or observations"
    return (a[1] - b[1]) / ((b[0] - a[0]) / SECOND), f"{cited[0]['src']} over {(b[0] - a[0]) / SECOND:g} s"


def box(raw: Raw, inc: dict) -> tuple[float | None, str]:
    js = _junctions(raw, _where(inc))
    polygons = [j["box"] for j in js if isinstance(j.get("box"), list)]
    if not polygons:
        return None, "no box polygon in the map"
    runs: list[list[tuple]] = []
    still = False
    for s in raw.tracks.get(inc["vehicle"], []):
        now = (isinstance(s[3], (int, float)) and s[3] <= STILL_MPS
               and any(_in_polygon(s[1], s[2], poly) for poly in polygons))
        if now and still:
            runs[-1].append(s)
        elif now:
            runs.append([s])
        still = now
    near = [r for r in runs if r[0][0] - BOX_NEAR_S * SECOND <= inc["t"] <= r[-1][0] + BOX_NEAR_S * SECOND]
    if not near:
        return None, "no standstill in the box near the act"
    best = min(near, key=lambda r: 0 if r[0][0] <= inc["t"] <= r[-1][0] else min(abs(inc["t"] - r[0][0]),
                                                                                 abs(inc["t"] - r[-1][0])))
    return (best[-1][0] - best[0][0]) / SECOND, f"{len(best)} still samples in the box"


def _in_polygon(x: float, y: float, poly: list) -> bool:
    inside = False
    for (ax, ay), (bx, by) in zip(poly, poly[1:] + poly[:1]):
        if (ay > y) != (by > y) and x < ax + (y - ay) * (bx - ax) / (by - ay):
            inside = not inside
    return inside


# --- judging one margin ----------------------------------------------------------------------------

def check_one(raw: Raw, inc: dict) -> Result | None:
    """The margin of one incident (its to_json) checked against the raw events; None for a
    margin kind this script does not measure."""
    m = inc.get("margin")
    if not m:
        return None
    q, value, u, bound = m["quantity"], m["value"], m.get("uncertainty"), m.get("bound")
    first = False
    if q.startswith("seconds after red") or q.startswith("seconds into red-and-amber"):
        kind = "red"
        script, first, note = red(raw, inc, q.startswith("seconds into"))
    elif q.startswith("metres from the stop line when amber"):
        kind, (script, note) = "amber", amber(raw, inc)
    elif q.startswith("mph over the speed limit"):
        kind, (script, note) = "speeding", speeding(raw, inc, _road(inc))
    elif q == "slowest measured speed before the Stop line":
        kind, (script, note) = "stop", stop_slowest(raw, inc)
    elif q == "seconds stationary at the Stop line":
        kind, (script, note) = "stood", stop_stood(raw, inc)
    elif q == "deceleration of the other road user":
        kind, (script, note) = "give way", give_way(raw, inc)
    elif q == "seconds stopped in the box junction":
        kind, (script, note) = "box", box(raw, inc)
    else:
        return None
    if script is None:
        return Result(inc["id"], kind, value, u, bound, None, None, note)
    room = (u or 0.0) + SLACK[m["unit"]]
    within = abs(script - value) <= room
    if note.startswith(NEVER_OVER):             # the raw events show no excess: the margin must not either
        within = value <= room
    if bound and kind == "red" and not first:
        within, note = False, note + "; 'at least' but the raw events show red's onset"
    elif bound and value > script + room:
        within, note = False, note + "; 'at least' more than the raw events give"
    elif bound and kind != "red":
        within = script >= value - room         # "at least": the raw stretch may be the act's whole
    if not bound and kind == "red" and first:
        note += "; red at the signal's first report, yet no 'at least'"
    return Result(inc["id"], kind, value, u, bound, script, within, note)


KINDS = ("red", "amber", "speeding", "stop", "stood", "give way", "box")


def check_all(raw: Raw, incidents: list[dict]) -> list[Result]:
    return [r for r in (check_one(raw, i) for i in incidents) if r is not None]


def table(run: str, total: int, results: list[Result]) -> str:
    rows = [f"{run}: {total} incidents, {len(results)} with a margin this script checks",
            f"  {'kind':<10} {'margins':>7} {'checked':>7} {'within':>6} {'outside':>7} {'unchecked':>9} "
            f"{'max |diff|':>10} {'max u':>6}"]
    for kind in KINDS:
        mine = [r for r in results if r.kind == kind]
        checked = [r for r in mine if r.within is not None]
        inside = sum(1 for r in checked if r.within)
        diff = max((abs(r.script - r.reasoner) for r in checked), default=0.0)
        u = max((r.uncertainty or 0.0 for r in checked), default=0.0)
        rows.append(f"  {kind:<10} {len(mine):>7} {len(checked):>7} {inside:>6} {len(checked) - inside:>7} "
                    f"{len(mine) - len(checked):>9} {diff:>10.3f} {u:>6g}")
    outside = [r for r in results if r.within is False]
    if outside:
        rows.append("  outside:")
        rows += [r.line() for r in outside]
    unchecked = [r for r in results if r.within is None]
    if unchecked:
        rows.append("  unchecked (nothing in the raw events to check by):")
        rows += [r.line() for r in unchecked]
    return "\n".join(rows)


def main(db: str, run: str, judged: str | None = None) -> int:
    import json
    from store import Store
    with Store.open_read_only(db) as store:
        raw = read(store, run)
    if judged is not None:                      # `gaps incidents --run RUN --json` output, judged once
        with open(judged, encoding="utf-8") as f:
            incidents = json.load(f)
    else:
        import reasoner
        with reasoner.open(db) as case:
            incidents = [i.to_json() for i in case.incidents(run)]
    results = check_all(raw, incidents)
    print(table(run, len(incidents), results))
    return 1 if any(r.within is False for r in results) else 0


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    sys.exit(main(*sys.argv[1:]))
