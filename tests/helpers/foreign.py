"""Events as a foreign producer writes them: a roadside-camera vendor or a second simulator that
knows DESIGN's event catalogue, its core vocabulary and its measured fields, nothing of ours.

    run = Foreign()                                  # run.start with crossroads() maps
    run.spawn("7")
    run.lights("J1", "west", [(0, "green"), (20, "amber"), (23, "red")])
    run.drive("7", Motion(-120, 13.4), "west", times=rate(2, 0, 14))       # entity.state at 2 Hz
    run.watch("7", Motion(...), "west", times=..., monitor="m1")          # a camera's measurements
    events = run.events

Motion is one-dimensional along an approach (metres from the junction's centre, negative before
it; the vehicle goes straight on), made of phases of constant acceleration, so that a test knows
exactly where the vehicle was and when it crossed its line. Lanes are on the left (UK): a vehicle
from the west drives east 1.75 m north of the centre line. Headings are degrees counter-clockwise
from east. No verdict and no project sentence is written here.
"""
from __future__ import annotations

import math
import random
from dataclasses import dataclass, field
from typing import Any, Callable, Iterable

T0 = 1_750_000_000_000_000_000          # 2025-06-15T15:06:40Z
SECOND = 1_000_000_000
LANE = 1.75
LINE_M = 12.0
DIRECTION = {"west": (1.0, 0.0), "east": (-1.0, 0.0), "south": (0.0, 1.0), "north": (0.0, -1.0)}  # of travel
LEFT = {"west": (0.0, 1.0), "east": (0.0, -1.0), "south": (-1.0, 0.0), "north": (1.0, 0.0)}       # lane offset


def ns(seconds: float) -> int:
    return T0 + round(seconds * SECOND)


def crossroads(ident: str, x: float, y: float, control: str, *, kinds: dict[str, str] | None = None,
               box: Any = None, line_m: float = LINE_M, major: list | None = None) -> dict:
    """A DESIGN junction with a stop line across each approach's lane (`kinds`: approach -> kind;
    an approach left out has no line, as a major road at a Give Way junction has none)."""
    kinds = {a: {"lights": "signal", "stop": "stop_sign", "give_way": "give_way"}.get(control, "")
             for a in DIRECTION} if kinds is None else kinds
    lines = []
    for approach, kind in kinds.items():
        (dx, dy), (lx, ly) = DIRECTION[approach], LEFT[approach]
        mx, my = x - dx * line_m, y - dy * line_m
        lines.append({"approach": approach, "from": [mx, my], "to": [mx + lx * 2 * LANE, my + ly * 2 * LANE],
                      "kind": kind})
    junction = {"id": ident, "x": x, "y": y, "control": control, "stop_lines": lines}
    if box is not None:
        junction["box"] = box
    if major is not None:
        junction["major"] = major
    return junction


def roads_through(x: float, y: float, limit_mph: float = 30, length: float = 300.0, tag: str = "") -> list[dict]:
    return [{"id": f"EW{tag}", "from": [x - length, y], "to": [x + length, y], "speed_limit_mph": limit_mph},
            {"id": f"NS{tag}", "from": [x, y - length], "to": [x, y + length], "speed_limit_mph": limit_mph}]


@dataclass
class Motion:
    """Position s (m from the centre along the route) and speed v over time: start at s0 with
    v0, then phases (duration s, acceleration m/s²); the speed never goes below zero."""

    s0: float
    v0: float
    phases: list[tuple[float, float]] = field(default_factory=list)

    def at(self, t: float) -> tuple[float, float]:
        s, v, elapsed = self.s0, self.v0, 0.0
        for duration, accel in self.phases:
            step = min(duration, t - elapsed)
            if step <= 0:
                break
            s, v = _advance(s, v, accel, step)
            elapsed += step
        if t > elapsed:
            s, v = s + v * (t - elapsed), v
        return s, v

    def when(self, s_target: float, until: float = 600.0) -> float:
        """The first time the vehicle reaches s_target (bisection on the monotone s(t))."""
        lo, hi = 0.0, until
        if self.at(hi)[0] < s_target:
            raise ValueError("never reaches it")
        for _ in range(80):
            mid = (lo + hi) / 2
            lo, hi = (mid, hi) if self.at(mid)[0] < s_target else (lo, mid)
        return hi

    @classmethod
    def stopping_at(cls, s0: float, v0: float, s_stop: float, wait: float = 0.0, then: float = 0.0,
                    accel: float = 2.0) -> Motion:
        """Drive at v0, brake evenly to stand at s_stop, wait, then pull away at `accel` for
        `then` seconds."""
        distance = s_stop - s0
        decel = v0 * v0 / (2 * (distance - 0.0)) if distance > 0 else 0.0
        braking = v0 / decel if decel else 0.0
        return cls(s0, v0, [(braking, -decel), (wait, 0.0), (then, accel)])


def _advance(s: float, v: float, a: float, dt: float) -> tuple[float, float]:
    if a < 0 and v + a * dt < 0:
        stop = -v / a
        return s + v * stop + 0.5 * a * stop * stop, 0.0
    return s + v * dt + 0.5 * a * dt * dt, v + a * dt


def rate(hz: float, start: float, end: float) -> list[float]:
    n = int(round((end - start) * hz))
    return [start + i / hz for i in range(n + 1)]


def irregular(start: float, end: float, seed: int = 1, low: float = 0.1, high: float = 0.5) -> list[float]:
    """Sample times with random spacing between low and high seconds (2-10 Hz)."""
    rng = random.Random(seed)
    out, t = [], start
    while t <= end:
        out.append(round(t, 4))
        t += rng.uniform(low, high)
    return out


OPPOSITE = {"west": "east", "east": "west", "north": "south", "south": "north"}


def place(centre: tuple[float, float], approach: str, s: float) -> tuple[float, float, float]:
    """x, y and heading of a vehicle s metres along the route through a junction from an approach.
    "west>south": from the west arm, turning where its lane meets the south arm's outbound lane
    and leaving by it (a right turn on the left of the road); s still counts along the route."""
    approach, _, leaving = approach.partition(">")
    (dx, dy), (lx, ly) = DIRECTION[approach], LEFT[approach]
    if leaving:
        (ox, oy), (mx, my) = DIRECTION[OPPOSITE[leaving]], LEFT[OPPOSITE[leaving]]
        corner = (mx * dx + my * dy) * LANE            # where the outbound lane crosses the inbound one
        if s > corner:
            cx, cy = centre[0] + dx * corner + lx * LANE, centre[1] + dy * corner + ly * LANE
            return cx + ox * (s - corner), cy + oy * (s - corner), math.degrees(math.atan2(oy, ox)) % 360.0
    x, y = centre[0] + dx * s + lx * LANE, centre[1] + dy * s + ly * LANE
    return x, y, math.degrees(math.atan2(dy, dx)) % 360.0


@dataclass
class Foreign:
    """Events of one run, each source numbered from 0, in the order written."""

    run: str = "foreign-1"
    junctions: list[dict] = field(default_factory=lambda: [crossroads("J1", 0.0, 0.0, "lights")])
    roads: list[dict] = field(default_factory=lambda: roads_through(0.0, 0.0))
    monitors: list[dict] = field(default_factory=lambda: [
        {"id": "m1", "junction": "J1", "x": 8.0, "y": 8.0, "heading_deg": 225.0, "range_m": 80.0, "fov_deg": 360.0}])
    events: list[dict] = field(default_factory=list)
    seqs: dict[str, int] = field(default_factory=dict)
    started: bool = False

    def emit(self, src: str, t: int, kind: str, body: dict) -> dict:
        if not self.started:
            self.started = True
            self.emit("sim/camera-vendor", T0, "run.start", {"map": {
                "roads": self.roads, "junctions": self.junctions, "monitors": self.monitors}})
        seq = self.seqs.get(src, 0)
        self.seqs[src] = seq + 1
        event = {"v": 1, "run": self.run, "src": src, "seq": seq, "t": t, "kind": kind, "body": body}
        self.events.append(event)
        return event

    def centre(self, junction: str) -> tuple[float, float]:
        j = next(j for j in self.junctions if j["id"] == junction)
        return j["x"], j["y"]

    def spawn(self, vehicle: str, type: str = "car", *, emergency: bool | None = None, at: float = 0.0,
              role: str = "vehicle", **fields: Any) -> dict:
        """`fields`: more of DESIGN's spawn fields (driver, automation_level, tolerance: the
        sensors' stated tolerance {"position_m", "speed_mps"})."""
        body: dict[str, Any] = {"type": type, **fields}
        if emergency is not None:
            body["emergency"] = emergency
        return self.emit(f"{role}/{vehicle}", ns(at), "entity.spawn", body)

    def lights(self, junction: str, approach: str, changes: Iterable[tuple[float, str]]) -> None:
        for at, colour in changes:
            self.emit(f"signal/{junction}-{approach}", ns(at), "signal.state",
                      {"junction": junction, "approach": approach, "colour": colour})

    def drive(self, vehicle: str, motion: Motion, approach: str, times: Iterable[float], *, junction: str = "J1",
              t_start: float = 0.0, extra: dict | None = None, role: str = "vehicle") -> list[dict]:
        """entity.state of the vehicle at each time (seconds from the run start); the motion's
        clock starts at t_start. `extra`: more body fields (e.g. {"emergency": True}); `role`:
        the source's role ("pedestrian" for a pedestrian's own positions)."""
        out = []
        for at in times:
            x, y, heading, v = self._where(motion, approach, junction, at - t_start)
            body = {"x": round(x, 3), "y": round(y, 3), "heading_deg": heading, "speed_mps": round(v, 3)}
            body.update(extra or {})
            out.append(self.emit(f"{role}/{vehicle}", ns(at), "entity.state", body))
        return out

    def watch(self, vehicle: str, motion: Motion, approach: str, times: Iterable[float], *, monitor: str = "m1",
              junction: str = "J1", t_start: float = 0.0,
              facts: list[str] | Callable[[float, float, float], list[str]] | None = None) -> list[dict]:
        """A camera's monitor.observation of the vehicle, with its measured speed and position.
        `facts`: the sentences of every frame, or a function of (run time, s, speed) giving them
        (what the camera sees at that frame, in DESIGN's core vocabulary)."""
        out = []
        for at in times:
            x, y, _, v = self._where(motion, approach, junction, at - t_start)
            said = facts(at, *motion.at(at - t_start)) if callable(facts) else list(facts or [])
            out.append(self.emit(f"monitor/{monitor}", ns(at), "monitor.observation", {
                "vehicle": vehicle, "facts": said, "speed_mps": round(v, 3),
                "x": round(x, 3), "y": round(y, 3)}))
        return out

    def violation(self, vehicle: str, at: float, action: str, facts: list[str], *, monitor: str = "m1") -> dict:
        """A camera's monitor.potential_violation: what it flagged on line, on its own reading (a
        foreign producer records no rulebook of ours)."""
        return self.emit(f"monitor/{monitor}", ns(at), "monitor.potential_violation",
                         {"vehicle": vehicle, "action": action, "facts": list(facts)})

    def end(self, at: float) -> dict:
        return self.emit("sim/camera-vendor", ns(at), "run.end", {"reason": "end of footage"})

    def _where(self, motion: Motion, approach: str, junction: str, t: float) -> tuple[float, float, float, float]:
        s, v = motion.at(t)
        x, y, heading = place(self.centre(junction), approach, s)
        return x, y, heading, v

    def drop(self, src: str, seqs: Iterable[int]) -> None:
        """Lose events of a source (a sequence gap), as a lossy link would."""
        gone = set(seqs)
        self.events = [e for e in self.events if not (e["src"] == src and e["seq"] in gone)]
