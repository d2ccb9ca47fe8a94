"""Speeds as the report's reader reads them: UK roads and the Highway Code speak miles per hour,
the producers record metres per second (DESIGN's entity.state `speed_mps`)."""
from __future__ import annotations

MPS_PER_MPH = 1609.344 / 3600          # an international mile is 1,609.344 m, exactly


def mph(mps: float) -> float:
    """A speed in metres per second, in miles per hour."""
    return mps / MPS_PER_MPH


def mph_text(mps: float | None) -> str:
    """"20.1 mph" to one decimal, "?" for a speed not recorded."""
    return "?" if mps is None else f"{mph(mps):.1f} mph"
