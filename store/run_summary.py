"""What `Store.runs()` says of each run: the one line a listing, a --run check or an export needs."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True, slots=True)
class RunSummary:
    """One run with events, as the store holds it now (read from the indexes, not verified)."""

    run: str
    """The run's id."""
    events: int
    """How many events the store holds for it."""
    first_t: int
    """The earliest event time (ns since the epoch), whatever its kind."""
    last_t: int
    """The latest event time (ns since the epoch)."""
    sources: tuple[str, ...]
    """The srcs that sent its events, by name."""

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "events": self.events, "first_t": self.first_t, "last_t": self.last_t,
                "sources": list(self.sources)}
