"""What a running ingest can honestly say about itself, once a tick: the status line and its JSON.

Every figure comes from the ingest's own counters (IngestStats, GapTracker). Two are narrower than
their names might suggest, and the docs say so: ``lag_s`` is the last batch's time from its first
sample leaving Zenoh's channel to its commit (what waited inside Zenoh is not visible to Python), and
``active`` sources are those that sent something in the last ACTIVE_WITHIN_S seconds (a quiet source is
not known to be gone; liveliness tokens would tell).
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass

from .service import IngestService

ACTIVE_WITHIN_S = 10.0


@dataclass(frozen=True)
class Status:
    """One reading of the ingest; ``events_per_s`` is over the time since the previous reading."""

    uptime_s: float
    events_per_s: float
    received: int
    stored: int
    duplicates: int
    quarantined: int
    failed: int
    errors: int
    late: int
    in_flight: int      # taken from Zenoh, not yet stored, counted or quarantined
    lag_s: float
    lag_max_s: float
    missing: int        # sequence numbers never received, over all sources
    gappy_sources: int  # sources missing at least one
    sources: int
    active_sources: int
    write_failures: int = 0     # commits the store refused (each try counts)
    stalled_s: float = 0.0      # time the store could not write, in all
    stall: str | None = None    # why the store cannot write now (None: it can)
    stalled_for_s: float = 0.0  # how long it has not been able to

    @property
    def settled(self) -> int:
        """Samples with an outcome: stored, duplicate, quarantined or failed."""
        return self.stored + self.duplicates + self.quarantined + self.failed

    def to_json(self) -> dict:
        return asdict(self)

    def line(self) -> str:
        """The status line: what an operator watching a terminal wants at a glance, in one line."""
        gaps = f"gaps {self.missing:,} in {self.gappy_sources:,} sources" if self.missing else "no gaps"
        parts = [f"{self.events_per_s:,.0f} ev/s", f"stored {self.stored:,}", f"dup {self.duplicates:,}",
                 f"quarantined {self.quarantined:,}", gaps,
                 f"sources {self.active_sources:,} active/{self.sources:,}", f"lag {_seconds(self.lag_s)}",
                 f"up {_clock(self.uptime_s)}"]
        if self.failed:
            parts.insert(4, f"FAILED {self.failed:,}")
        if self.stall:
            parts.insert(0, f"STALLED {_seconds(self.stalled_for_s)}: {self.stall}, holding publishers back, retrying")
        if self.in_flight:
            parts.insert(-1, f"in flight {self.in_flight:,}")
        return " · ".join(parts)


class StatusMeter:
    """Reads a service's counters into a Status, keeping the previous reading for the rate."""

    def __init__(self, service: IngestService) -> None:
        self._service = service
        self._started = time.monotonic()
        self._last_at = self._started
        self._last_settled = 0

    def read(self) -> Status:
        now = time.monotonic()
        s = self._service.stats()
        missing, gappy = self._service.missing()
        sources, active = self._service.sources(ACTIVE_WITHIN_S)
        settled = s["stored"] + s["duplicates"] + s["rejected"] + s["failed"]
        rate = (settled - self._last_settled) / max(now - self._last_at, 1e-9)
        self._last_at, self._last_settled = now, settled
        return Status(
            uptime_s=round(now - self._started, 3), events_per_s=round(rate, 1), received=s["received"],
            stored=s["stored"], duplicates=s["duplicates"], quarantined=s["rejected"], failed=s["failed"],
            errors=s["errors"], late=s["late"], in_flight=max(s["received"] - settled, 0),
            lag_s=round(s["lag_s"], 4), lag_max_s=round(s["lag_max_s"], 4), missing=missing,
            gappy_sources=gappy, sources=sources, active_sources=active, write_failures=s["write_failures"],
            stalled_s=round(s["stalled_s"], 3), stall=s["stall"], stalled_for_s=round(s["stalled_for_s"], 3),
        )

    @property
    def uptime_s(self) -> float:
        return time.monotonic() - self._started


def _seconds(value: float) -> str:
    return f"{value * 1000:.0f} ms" if value < 1 else f"{value:.1f} s"


def _clock(seconds: float) -> str:
    whole = int(seconds)
    return f"{whole // 3600}:{whole // 60 % 60:02d}:{whole % 60:02d}"
