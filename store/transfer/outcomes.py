"""What an import or export did, as plain data for the CLI to print or send as JSON.

An import accounts for everything the file offered: each event was stored, counted as a
duplicate, or rejected into quarantine; whatever was not an event (a blank line, a visualisation
channel, a message in an encoding we do not read) is counted as skipped with the reason; and a
file that ends early says where. Only the first rejections are listed: a hostile file may hold
millions, and they are all in quarantine anyway.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..outcomes import AppendReport

MAX_DETAILS = 100


@dataclass
class ImportReport:
    file: str
    format: str
    stored: int = 0
    duplicates: int = 0
    rejected: int = 0
    quarantine_full: int = 0   # of the rejected, past the quarantine's cap: counted, bytes not kept
    skipped: int = 0
    details: list[dict[str, str]] = field(default_factory=list)  # first MAX_DETAILS {origin, reason}
    skips: dict[str, dict[str, Any]] = field(default_factory=dict)  # what -> {count, reason}
    truncated: dict[str, Any] | None = None  # where the readable part of the file ends, and why
    damaged: list[dict[str, Any]] = field(default_factory=list)  # unreadable parts read past
    chains: list[dict[str, Any]] = field(default_factory=list)  # exported chain heads, checked

    def add(self, appended: AppendReport) -> None:
        """Fold in one batch's result from the store."""
        self.stored += appended.stored
        self.duplicates += appended.duplicates
        self.rejected += len(appended.rejected)
        self.quarantine_full += appended.quarantine_full
        room = MAX_DETAILS - len(self.details)
        if room > 0:
            self.details.extend(appended.rejected[:room])

    def skip(self, what: str, reason: str, count: int = 1) -> None:
        """Count input that is not an event, grouped by what it was (a channel, blank lines)."""
        entry = self.skips.setdefault(what, {"count": 0, "reason": reason})
        entry["count"] += count
        self.skipped += count

    @property
    def offered(self) -> int:
        """Events offered to the store: each one is stored, a duplicate, or rejected."""
        return self.stored + self.duplicates + self.rejected

    def as_dict(self) -> dict[str, Any]:
        return {
            "file": self.file,
            "format": self.format,
            "stored": self.stored,
            "duplicates": self.duplicates,
            "rejected": self.rejected,
            "quarantine_full": self.quarantine_full,
            "skipped": self.skipped,
            "details": list(self.details),
            "skips": [{"what": what, **entry} for what, entry in self.skips.items()],
            "truncated": self.truncated,
            "damaged": list(self.damaged),
            "chains": list(self.chains),
        }


@dataclass
class ExportReport:
    file: str
    format: str
    run: str
    order: str  # "time" or "chain": the order a re-import appends the events in
    events: int = 0
    derived: int = 0  # visualisation messages written beside the events (MCAP only)
    bytes: int = 0
    chain_order: bool = False  # MCAP: the chain order travels as an attachment (it is not time order)

    def as_dict(self) -> dict[str, Any]:
        return dict(self.__dict__)
