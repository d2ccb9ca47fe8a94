"""Speeds as the report's reader reads them: UK roads and the Highway Code speak miles per hour,
the producers record metres per second (DESIGN's entity.state `speed_mps`)."""
from __future__ import annotations

from reasoner.history import MPH_PER_MPS   # the one mile conversion: the histories measure with it too


def mph(mps: float) -> float:
    """A speed in metres per second, in miles per hour (unrounded, for pictures and text)."""
    return mps * MPH_PER_MPS


def mph_text(mps: float | None) -> str:
    """"20.1 mph" to one decimal, "?" for a speed not recorded."""
    return "?" if mps is None else f"{mph(mps):.1f} mph"


def speed_text(mps: object) -> str:
    """"20.1 mph (9 m/s)": the reader's unit first, then the figure the producer recorded, so a
    reader can check the conversion against the evidence. A value that is not a number is shown
    as it was recorded, never converted."""
    if mps is None:
        return "?"
    if isinstance(mps, bool) or not isinstance(mps, (int, float)):
        return f"{mps} (recorded, not a number of m/s)"
    return f"{mph_text(mps)} ({mps:g} m/s)"
