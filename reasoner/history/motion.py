"""Measured motion: positions and speeds read from events, and what can be computed between them.

A sample is one measurement of a road user: from its own `entity.state` (x, y, speed_mps,
heading_deg, junction, road, emergency) or from a monitor's `monitor.observation` of it (speed_mps,
x, y, all optional). Values are taken only when they can be measurements: a bool, a string, NaN,
a speed above 150 m/s or a position beyond 10,000 km is left out, and the event is named among
the skipped ones, never a crash.

Between two samples the motion is taken as steady (linear interpolation of position and speed):
at 2-10 Hz a road vehicle's speed changes by at most a few m/s between samples, and every
interpolated figure names the two samples it lies between, so an investigator can check it.
"""
from __future__ import annotations

import bisect
import math
from dataclasses import dataclass
from typing import Any, Iterable, NamedTuple, Sequence, cast, overload

from store import EventRef

from .junctions import MAX_COORD_M, finite

MAX_SPEED_MPS = 150.0        # 540 km/h: no road vehicle measures more
MPH_PER_MPS = 3600 / 1609.344    # an international mile is 1,609.344 m, exactly
STOPPED_MPS = 0.5 / MPH_PER_MPS  # "V is stopped" exactly when its speed rounds to 0 mph (< 0.5 mph)
MIN_DECEL_SPAN_S = 1.0       # decelerations are averaged over at least a second (speed noise)
MAX_DECEL_MPS2 = 4.0         # the hardest braking (or pulling away) assumed between two samples when
                             # asking whether a stop could hide between them
SECOND = 1_000_000_000


class Sample(NamedTuple):
    """One measurement of a road user at t (ns); position and speed each may be missing.
    Immutable like the frozen dataclasses around it, but a NamedTuple: a passage is built from
    hundreds of these, and one costs a fifth of a frozen dataclass to make."""

    t: int
    x: float | None
    y: float | None
    speed_mps: float | None
    heading_deg: float | None
    ref: EventRef
    road: str | None = None
    junction: str | None = None
    emergency: bool | None = None

    @property
    def placed(self) -> bool:
        return self.x is not None and self.y is not None

    @property
    def label(self) -> str:
        """How a method names the sample: "entity.state #41", "monitor/m1 observation #7"."""
        if self.ref.kind == "monitor.observation":
            return f"{self.ref.src} observation #{self.ref.seq}"
        return f"{self.ref.kind} #{self.ref.seq}"

    def to_json(self) -> dict[str, Any]:
        return {"t": self.t, "x": self.x, "y": self.y, "speed_mps": self.speed_mps,
                "heading_deg": self.heading_deg, "evidence": self.ref.to_json()}


def sample_of(event: dict) -> tuple[Sample | None, str | None]:
    """The sample an entity.state or monitor.observation holds, or why it holds none."""
    body = event.get("body")
    if type(body) is not dict:
        return None, "no body"
    x, y, speed, t, seq, src = (body.get("x"), body.get("y"), body.get("speed_mps"), event.get("t"),
                                event.get("seq"), event.get("src"))
    if type(x) is float and type(y) is float and type(speed) is float and type(t) is int and type(seq) is int \
            and type(src) is str and -MAX_COORD_M <= x <= MAX_COORD_M and -MAX_COORD_M <= y <= MAX_COORD_M \
            and 0.0 <= speed <= MAX_SPEED_MPS:
        return _sample(event, body, x, y, speed, t, seq, src), None    # every value a measurement: the usual case
    x, y = finite(x), finite(y)
    speed = finite(speed, MAX_SPEED_MPS)
    if speed is not None and speed < 0:
        speed = None
    bad = None
    if x is None or y is None or speed is None:
        bad = [k for k, v in (("x", x), ("y", y), ("speed_mps", speed)) if k in body and v is None]
        if x is None or y is None:
            x = y = None
        if x is None and speed is None:
            return None, "neither a position nor a speed that can be a measurement"
    if type(t) is not int or type(seq) is not int or type(src) is not str:
        return None, "not an event (t, seq, src)"
    return _sample(event, body, x, y, speed, t, seq, src), (f"{', '.join(bad)} left out: not a measurement"
                                                           if bad else None)


def _sample(event: dict, body: dict, x: float | None, y: float | None, speed: float | None, t: int, seq: int,
            src: str) -> Sample:
    """The sample of an event whose measurements have been checked."""
    ref = EventRef(event.get("run"), src, seq, t, event.get("kind"))
    road, junction, emergency = body.get("road"), body.get("junction"), body.get("emergency")
    return Sample(t, x, y, speed, finite(body.get("heading_deg"), 1e6), ref,
                  road if type(road) is str else None, junction if type(junction) is str else None,
                  emergency if type(emergency) is bool else None)


def samples(events: Iterable[dict]) -> tuple[tuple[Sample, ...], tuple[str, ...]]:
    """The samples of some events in (t, seq) order, and a note per event that gave none or
    gave less than it carried."""
    found, notes = [], []
    for event in events:
        sample, why = sample_of(event)
        if why is not None:
            notes.append(f"{event.get('src')} #{event.get('seq')}: {why}")
        if sample is not None:
            found.append(sample)
    found.sort(key=lambda s: (s.t, s.ref.src, s.ref.seq))
    return tuple(found), tuple(notes)


def mph(speed_mps: float) -> int:
    """Speed in whole mph, half up: the figure a sentence states (30.5 mph -> 31)."""
    return int(math.floor(speed_mps * MPH_PER_MPS + 0.5))


def around(series: Sequence[Sample], t: int) -> tuple[Sample | None, Sample | None]:
    """The samples just at-or-before and just after t (either None beyond the series)."""
    times = [s.t for s in series]
    i = bisect.bisect_right(times, t)
    return (series[i - 1] if i > 0 else None), (series[i] if i < len(series) else None)


def fraction(a: Sample, b: Sample, t: int) -> float:
    return 0.0 if b.t == a.t else (t - a.t) / (b.t - a.t)


@overload
def lerp(a: float, b: float, f: float) -> float: ...
@overload
def lerp(a: float | None, b: float | None, f: float) -> float | None: ...
def lerp(a: float | None, b: float | None, f: float) -> float | None:
    if a is None or b is None:
        return a if f <= 0.5 else b
    return a + (b - a) * f


HOLD_S = 0.25                # a moment this close beyond the first or last sample takes that sample's value


def bracket(series: Sequence[Sample], t: int) -> tuple[Sample, Sample, float] | None:
    """The two samples t lies between and how far between (0..1); the one sample at t, or the
    nearest within HOLD_S beyond either end of the series, twice; None outside it."""
    a, b = around(series, t)
    if a is not None and a.t == t:
        return a, a, 0.0
    if a is not None and b is not None:
        return a, b, fraction(a, b, t)
    nearest = a if a is not None else b
    if nearest is not None and abs(nearest.t - t) <= HOLD_S * SECOND:
        return nearest, nearest, 0.0
    return None


def speed_at(series: Sequence[Sample], t: int) -> tuple[float | None, tuple[Sample, ...]]:
    """A road user's speed at t, interpolated between the samples around it, and those samples."""
    found = bracket([s for s in series if s.speed_mps is not None], t)
    if found is None:
        return None, ()
    a, b, f = found
    return lerp(a.speed_mps, b.speed_mps, f), _used(a, b)


def position_at(series: Sequence[Sample], t: int) -> tuple[tuple[float, float] | None, tuple[Sample, ...]]:
    """A road user's position at t, interpolated between the placed samples around it."""
    found = bracket([s for s in series if s.placed], t)
    if found is None:
        return None, ()
    a, b, f = found
    (ax, ay), (bx, by) = xy(a), xy(b)
    return (lerp(ax, bx, f), lerp(ay, by, f)), _used(a, b)


def xy(s: Sample) -> tuple[float, float]:
    """The position of a placed sample (`Sample.placed`): its x and y, both measurements, for the
    type checker, which cannot see through `placed`."""
    x, y = s.x, s.y
    if x is None or y is None:
        raise ValueError(f"{s.label} holds no position")
    return x, y


def _used(a: Sample, b: Sample) -> tuple[Sample, ...]:
    return (a,) if a is b else (a, b)


def between(used: tuple[Sample, ...], t: int) -> str:
    """How a value at t was read off its samples, in words."""
    if len(used) == 1:
        s = used[0]
        lag = (t - s.t) / SECOND
        return f"{s.label}" + (f" ({abs(lag):.2f} s {'before' if lag > 0 else 'after'})" if s.t != t else "")
    a, b = used
    return f"linear interpolation between {a.label} and {b.label}"


@dataclass(frozen=True)
class Braking:
    """The hardest deceleration of a road user, averaged between two of its samples."""

    decel_mps2: float
    first: Sample
    last: Sample

    def to_json(self) -> dict[str, Any]:
        return {"decel_mps2": round(self.decel_mps2, 3), "from": self.first.ref.to_json(),
                "to": self.last.ref.to_json()}


def peak_deceleration(series: Sequence[Sample], t_from: int, t_to: int) -> Braking | None:
    """The largest drop in speed per second between two samples at least MIN_DECEL_SPAN_S apart
    (or the two furthest apart, if the window is shorter), both within [t_from, t_to]."""
    speeds = [s for s in series if s.speed_mps is not None and t_from <= s.t <= t_to]
    best: Braking | None = None
    span = int(MIN_DECEL_SPAN_S * SECOND)
    j = 0
    for i, first in enumerate(speeds):
        j = max(j, i + 1)
        while j < len(speeds) and speeds[j].t - first.t < span:
            j += 1
        last = speeds[j] if j < len(speeds) else (speeds[-1] if i == 0 and len(speeds) > 1 else None)
        if last is None or last.t <= first.t:
            continue
        drop = cast(float, first.speed_mps) - cast(float, last.speed_mps)     # `speeds` holds measured ones only
        decel = drop / ((last.t - first.t) / SECOND)
        if best is None or decel > best.decel_mps2:
            best = Braking(decel, first, last)
    return best


def stop_could_hide(a: Sample, b: Sample) -> bool:
    """Whether a vehicle seen at these two speeds could have stood still between them, braking
    and pulling away at MAX_DECEL_MPS2: the samples then cannot tell whether it stopped."""
    if a.speed_mps is None or b.speed_mps is None:
        return True
    return a.speed_mps + b.speed_mps <= MAX_DECEL_MPS2 * (b.t - a.t) / SECOND
