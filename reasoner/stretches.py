"""A speeding act as the record delimits it: one continuous stretch over a road's speed limit.

The law counts one offence per act (the shared notes: "a single continuous stretch over a limit is
one offence, however many cameras recorded it"). A stretch is the run of a road user's speed
measurements over the limit of the road each was taken on, from the first such measurement to the
last, where no two consecutive ones over the limit are more than STRETCH_GAP_S apart: a dip under
the limit shorter than that (a sensor's jitter, a car easing off for a second) does not end the
act, a longer one does, and the next measurement over the limit starts another.

"Over the limit" here is a measurement above the road's limit (RTRA 1984 s.81 and s.89: driving
"at a speed exceeding" it): a car that never drops to the limit has not ended its act, even where
`V has speed of N` (whole mph, half up) would round a moment of it down to the limit; whether the
stretch is an offence (its peak's N > L, and the s.87 exemption) is the rulebooks' question, never
this module's. Which measurements: the road user's
own entity.state where it recorded any in the window read; else the monitors' measured speeds of it
(mixing the two would let one sensor's error cut or join another's stretch).

This module measures and delimits; it decides nothing.
"""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any, Iterable, cast

from store import EventRef, Store

from .history import Map
from .model import FASTEST_MEASURED, Act, DerivedFact, Margin
from .history import MPH_PER_MPS, mph
from .history import DEFAULT, Sensor, stated
from .vocabulary import HAS_SPEED_OF, SPEED_LIMIT_IS

SECOND = 1_000_000_000
STRETCH_GAP_S = 3.0          # measurements over the limit this close together are one stretch
WINDOW_S = 120.0             # read this far either side of a moment for the stretch around it
MAX_SAMPLES = 20_000         # bounded work for any input
SPEEDING_STRETCH = "speeding stretch"


@dataclass(frozen=True)
class Measured:
    """One speed measurement with the limit of the road it was taken on."""

    t: int
    speed_mps: float
    limit_mph: float | None
    road: str | None
    ref: EventRef

    @property
    def over(self) -> bool:
        """Above the road's limit (module docstring: the act goes on while the speed exceeds it)."""
        return self.limit_mph is not None and self.speed_mps * MPH_PER_MPS > self.limit_mph


@dataclass(frozen=True)
class Stretch:
    vehicle: str
    samples: tuple[Measured, ...]       # the measurements over the limit, in time order
    series: str                         # which measurements: "own entity.state" or "monitors' measurements"
    open_start: bool
    open_end: bool
    sensors: tuple[tuple[str, Sensor], ...] = ()    # (src, its stated tolerance): reasoner/sensors.py

    @property
    def start(self) -> int:
        return self.samples[0].t

    @property
    def end(self) -> int:
        return self.samples[-1].t

    @property
    def peak(self) -> Measured:
        return max(self.samples, key=lambda s: (s.speed_mps, -s.t))

    @property
    def road(self) -> str | None:
        return self.peak.road

    def act(self) -> Act:
        return Act(SPEEDING_STRETCH, self.road, self.start, self.end,
                   f"{len(self.samples)} measurements over the limit ({self.series}), none more than "
                   f"{STRETCH_GAP_S:g} s from the next", self.open_start, self.open_end)

    def facts(self) -> tuple[DerivedFact, ...]:
        """`V has speed of N` and `the speed limit is L` at the stretch's highest measurement."""
        p = self.peak
        how = (f"the highest of {len(self.samples)} measurements over the limit from "
               f"{p.ref.src} #{p.ref.seq}: {p.speed_mps:.2f} m/s ({p.speed_mps * MPH_PER_MPS:.1f} mph)")
        out = [DerivedFact(HAS_SPEED_OF.text(self.vehicle, mph(p.speed_mps)), how, (p.ref,))]
        if p.limit_mph is not None:
            limit = int(p.limit_mph) if float(p.limit_mph).is_integer() else p.limit_mph
            out.append(DerivedFact(SPEED_LIMIT_IS.text(limit), f"speed_limit_mph of road {p.road} in the run's map",
                                   (p.ref,)))
        return tuple(out)


    def margin(self) -> Margin | None:
        """mph over the limit at the stretch's highest measurement."""
        p = self.peak
        if p.limit_mph is None:
            return None
        sensor = next((sensor for src, sensor in self.sensors if src == p.ref.src), DEFAULT)
        return speeding_margin(p.speed_mps, p.limit_mph, (p.ref,), sensor, self.open_start or self.open_end,
                               f"fastest {p.speed_mps:.2f} m/s ({p.ref.src} #{p.ref.seq}) of the stretch over the "
                               f"limit against road {p.road}'s {p.limit_mph:g} mph")


def speeding_margin(speed_mps: float, limit_mph: float, refs: tuple[EventRef, ...], sensor: Sensor,
                    open_ended: bool, method: str) -> Margin:
    """mph over the limit at the act's fastest measurement, ± the speed tolerance of the sensor that
    measured it; not proven within that; "at least" where the stretch runs past what was read. The
    fastest speed itself is a figure, for the explanation's headline to cite what decided."""
    over = round(speed_mps * MPH_PER_MPS - limit_mph, 1) or 0.0       # never "-0"
    u = round(sensor.speed_mps * MPH_PER_MPS, 2)
    unproven = None if over > u else (
        f"the fastest measured speed of the act is {over:+.1f} mph against the limit, within its uncertainty "
        f"of ± {u:g} mph" if over > -u else
        f"the fastest measured speed of the act is not over the limit ({over:+.1f} mph)")
    cut = over > 0 and open_ended
    return Margin("mph over the speed limit", over, "mph", refs,
                  f"{method}; ± the speed tolerance ({sensor.said}; reasoner/tolerance.py)"
                  + ("; the stretch reaches the first or last measurement read, so it may have been faster "
                     "beyond: at least" if cut else ""),
                  ((FASTEST_MEASURED, round(speed_mps * MPH_PER_MPS, 1), "mph"),),
                  uncertainty=u, bound="at least" if cut else None, unproven=unproven)


def measured(events: Iterable[dict], map_: Map, vehicle: str) -> list[Measured]:
    """The speed measurements of the vehicle in these events (its entity.state, or monitor
    observations of it), each with its road's limit."""
    out = []
    for e in events:
        body = e.get("body")
        if type(body) is not dict:
            continue
        if e.get("kind") == "monitor.observation" and str(body.get("vehicle")) != vehicle:
            continue
        v, x, y = body.get("speed_mps"), body.get("x"), body.get("y")
        if type(v) not in (int, float) or v != v:
            continue
        road = map_.road(body.get("road"), x if type(x) in (int, float) else None,
                         y if type(y) in (int, float) else None)
        speed = cast(float, v)      # an int or a float: checked above
        out.append(Measured(e["t"], float(speed), road.limit_mph if road else None, road.id if road else None,
                            EventRef.of(e)))
        if len(out) >= MAX_SAMPLES:
            break
    return out


def stretch_around(samples: list[Measured], t: int, vehicle: str, series: str,
                   window: tuple[int | None, int | None] = (None, None)) -> Stretch | None:
    """The stretch over the limit under way at t, else the one nearest to it within
    STRETCH_GAP_S; None where none is."""
    gap = int(STRETCH_GAP_S * SECOND)
    found: list[list[Measured]] = []
    for s in sorted(samples, key=lambda s: s.t):
        if not s.over:
            continue
        if found and s.t - found[-1][-1].t <= gap:
            found[-1].append(s)
        else:
            found.append([s])
    best = None
    for run in found:
        distance = 0 if run[0].t <= t <= run[-1].t else min(abs(t - run[0].t), abs(t - run[-1].t))
        if distance <= gap and (best is None or distance < best[0]):
            best = (distance, run)
    if best is None:
        return None
    run = best[1]
    lo, hi = window
    return Stretch(vehicle, tuple(run), series, lo is not None and run[0].t - lo <= gap,
                   hi is not None and hi - run[-1].t <= gap)


def stretch_at(store: Store, run: str, vehicle: str, t: int, map_: Map) -> Stretch | None:
    """The vehicle's speeding stretch around t, from the store (module docstring)."""
    lo, hi = t - int(WINDOW_S * SECOND), t + int(WINDOW_S * SECOND)
    own = measured(store.source_events(run, f"vehicle/{vehicle}", kinds=["entity.state"], t_from=lo, t_to=hi),
                   map_, vehicle)
    if own:
        found = stretch_around(own, t, vehicle, "own entity.state", (lo, hi))
        spawns = list(store.source_events(run, f"vehicle/{vehicle}", kinds=["entity.spawn"], t_to=t))
        return with_sensors(found, map_, spawns[-1] if spawns else None)
    seen = measured(store.observations_of(run, vehicle, t_from=lo, t_to=hi), map_, vehicle)
    return with_sensors(stretch_around(seen, t, vehicle, "monitors' measurements", (lo, hi)), map_, None) \
        if seen else None


def with_sensors(stretch: Stretch | None, map_: Map, spawn: dict | None) -> Stretch | None:
    """The stretch with the tolerance its sources state: the monitors' in the map, the road
    user's own in its entity.spawn (DESIGN "Kinds": `tolerance`)."""
    if stretch is None:
        return None
    found = dict(map_.sensors)
    body = spawn.get("body") if isinstance(spawn, dict) else None
    sensor = stated(body.get("tolerance"), EventRef.of(spawn)) if isinstance(body, dict) and spawn is not None else None
    if sensor is not None and spawn is not None and isinstance(spawn.get("src"), str):   # (a body is a spawn's)
        found[spawn["src"]] = sensor
    return replace(stretch, sensors=tuple(sorted(found.items()))) if found else stretch


def _number(value: Any) -> bool:
    return type(value) in (int, float) and value == value
