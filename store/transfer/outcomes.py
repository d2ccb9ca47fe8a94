"""What an import or export did, as typed values the CLI renders by attribute or prints as JSON.

An import accounts for everything the file offered: each event was stored, counted as a
duplicate, or rejected into quarantine; whatever was not an event (a blank line, a visualisation
channel, a message in an encoding we do not read) is counted as skipped with the reason; and a
file that ends early says where. Only the first rejections are listed: a hostile file may hold
millions, and they are all in quarantine anyway. The parts of the report (a rejection, a kind of
skipped input, the cut, a damaged record, a chain checked) are frozen values, each with the
`to_json` that `gaps import --json` prints.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from ..outcomes import AppendReport, Rejection
from .chain_check import ChainResult
from .mcap_records import Cut, Damage
from .rows import Order

MAX_DETAILS = 100

@dataclass(frozen=True)
class Skip:
    """Input of one kind that is not an event (blank lines, a channel): how much, and why."""

    what: str
    count: int
    reason: str

    def to_json(self) -> dict[str, Any]:
        return {"what": self.what, "count": self.count, "reason": self.reason}


@dataclass(frozen=True)
class Truncation:
    """Where the readable part of a file cut short ends and why (its Cut), and what was read
    and stored before it."""

    cut: Cut
    messages_read: int          # event messages read before the cut (offered to the store)
    stored: int

    def to_json(self) -> dict[str, Any]:
        cut = self.cut
        return {"offset": cut.offset, "file_size": cut.file_size, "reason": cut.reason, "record": cut.record,
                "declared": cut.declared, "data_complete": cut.data_complete,
                "unreadable_bytes": cut.unreadable_bytes, "messages_read": self.messages_read, "stored": self.stored}


@dataclass
class ImportReport:
    file: str
    format: str
    stored: int = 0
    duplicates: int = 0
    rejected: int = 0
    quarantine_full: int = 0   # of the rejected, past the quarantine's cap: counted, bytes not kept
    skipped: int = 0
    details: list[Rejection] = field(default_factory=list)  # the first MAX_DETAILS
    skips: dict[str, Skip] = field(default_factory=dict)  # by what was skipped, in the order first met
    truncated: Truncation | None = None  # where the readable part of the file ends, and why
    damaged: list[Damage] = field(default_factory=list)  # unreadable parts read past
    chains: list[ChainResult] = field(default_factory=list)  # exported chain heads, checked

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
        before = self.skips.get(what)
        self.skips[what] = Skip(what, count, reason) if before is None else \
            Skip(what, before.count + count, before.reason)
        self.skipped += count

    @property
    def offered(self) -> int:
        """Events offered to the store: each one is stored, a duplicate, or rejected."""
        return self.stored + self.duplicates + self.rejected

    def to_json(self) -> dict[str, Any]:
        """`gaps import --json`."""
        return {
            "file": self.file,
            "format": self.format,
            "stored": self.stored,
            "duplicates": self.duplicates,
            "rejected": self.rejected,
            "quarantine_full": self.quarantine_full,
            "skipped": self.skipped,
            "details": [rejection.to_json() for rejection in self.details],
            "skips": [skip.to_json() for skip in self.skips.values()],
            "truncated": None if self.truncated is None else self.truncated.to_json(),
            "damaged": [damage.to_json() for damage in self.damaged],
            "chains": [chain.to_json() for chain in self.chains],
        }


@dataclass
class ExportReport:
    file: str
    format: str
    run: str
    order: Order  # the order a re-import appends the events in
    events: int = 0
    derived: int = 0  # visualisation messages written beside the events (MCAP only)
    bytes: int = 0
    chain_order: bool = False  # MCAP: the chain order travels as an attachment (it is not time order)

    def to_json(self) -> dict[str, Any]:
        """`gaps export --json`."""
        return dict(self.__dict__)
