"""How the command line writes event times: ISO 8601 in UTC, to the nanosecond the store keeps."""
from __future__ import annotations

from datetime import datetime, timezone

_NS = 1_000_000_000


def iso_utc(t_ns: int) -> str:
    """2024-11-21T10:15:00.35Z: integer arithmetic, so no nanosecond is lost to float rounding."""
    seconds, fraction = divmod(t_ns, _NS)
    try:
        stamp = datetime.fromtimestamp(seconds, tz=timezone.utc).strftime("%Y-%m-%dT%H:%M:%S")
    except (OverflowError, OSError, ValueError):
        return f"{t_ns} ns"  # outside the years datetime can write
    return _trim(f"{stamp}.{fraction:09d}") + "Z"


def duration(ns: int) -> str:
    """12.35 s, or 1:02:03.5 (hours:minutes:seconds) from a minute on; to the millisecond."""
    ms = ns // 1_000_000
    if ms < 60_000:
        return _trim(f"{ms // 1000}.{ms % 1000:03d}") + " s"
    minutes, ms = divmod(ms, 60_000)
    hours, minutes = divmod(minutes, 60)
    return _trim(f"{hours}:{minutes:02d}:{ms // 1000:02d}.{ms % 1000:03d}")


def _trim(number: str) -> str:
    return number.rstrip("0").rstrip(".")
