"""The tolerance a producer states for its sensors, and the one it is held to where it states none
(DESIGN "Kinds": `tolerance` on an `entity.spawn`, for the road user's own `entity.state`, and on a
monitor's entry in the run.start map, for its measurements in `monitor.observation`).

    stated(value) -> Sensor | None      a `tolerance` object read, None where absent or unreadable
    DEFAULT                             the documented defaults: 0.1 m, 0.1 m/s

A tolerance is how far a measured position or speed may be from the truth, as its producer
vouches for it (a bound, as every uncertainty here: reasoner/tolerance.py). The store's schemas
refuse a negative, zero or non-number value, so an event that states one is quarantined, never
read; `stated` still reads defensively (a list of events from a file is not checked) and falls
back to the defaults where a value is unusable. Zero is refused: no sensor measures exactly, and
a producer that claims one would make every margin "beyond its uncertainty".
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from store import EventRef

POSITION_TOLERANCE_M = 0.1       # a lane-level position: under a tenth of a lane
SPEED_TOLERANCE_MPS = 0.1        # a speed to a tenth of a metre per second (0.22 mph)
MAX_POSITION_M = 1000.0          # the schemas' bounds: beyond these a figure says nothing
MAX_SPEED_MPS = 150.0


@dataclass(frozen=True)
class Sensor:
    """A source's position and speed tolerance; `stated_by` the event that states them (None:
    the defaults, which the explanation then says)."""

    position_m: float = POSITION_TOLERANCE_M
    speed_mps: float = SPEED_TOLERANCE_MPS
    stated_by: EventRef | None = None

    @property
    def said(self) -> str:
        """How a method names the tolerance: stated by whom, or the defaults."""
        figures = f"{self.position_m:g} m, {self.speed_mps:g} m/s"
        if self.stated_by is None:
            return f"{figures}: the defaults, its producer states none"
        return f"{figures}: stated by {self.stated_by.src} #{self.stated_by.seq} ({self.stated_by.kind})"

    def to_json(self) -> dict[str, Any]:
        return {"position_m": self.position_m, "speed_mps": self.speed_mps,
                "stated_by": self.stated_by.to_json() if self.stated_by else None}


DEFAULT = Sensor()


def stated(value: Any, by: EventRef | None) -> Sensor | None:
    """The tolerance a `tolerance` object states ({"position_m": .., "speed_mps": ..}, either may
    be left out: the default stands for it); None where there is none or it states nothing usable."""
    if not isinstance(value, dict):
        return None
    position, speed = _figure(value.get("position_m"), MAX_POSITION_M), _figure(value.get("speed_mps"), MAX_SPEED_MPS)
    if position is None and speed is None:
        return None
    return Sensor(position if position is not None else POSITION_TOLERANCE_M,
                  speed if speed is not None else SPEED_TOLERANCE_MPS, by)


def _figure(value: Any, most: float) -> float | None:
    if type(value) not in (int, float) or value != value or not 0 < value <= most:
        return None
    return float(value)
