"""Plain results of store operations, shaped to be printed by the CLI or sent as JSON."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

from .verify_report import VerifyReport  # noqa: F401  (its home is store/verify_report.py)


@dataclass(frozen=True)
class Rejection:
    """One event the store refused into quarantine: where it came from (a file's line, a key
    expression), and why. The append report lists them; an import or a fetch report carries the
    first of them; `to_json` is the {origin, reason} every report prints."""

    origin: str
    reason: str

    def to_json(self) -> dict[str, str]:
        return {"origin": self.origin, "reason": self.reason}


@dataclass
class AppendReport:
    """What one append call did: nothing offered is dropped, so stored + duplicates +
    len(rejected) is the number of events offered. Of the rejected, quarantine_repeats were
    counted on a quarantine row holding the same bytes, and quarantine_full were past the
    quarantine's cap: counted, their bytes not kept (store/quarantine.py)."""

    stored: int = 0
    duplicates: int = 0
    rejected: list[Rejection] = field(default_factory=list)
    quarantine_repeats: int = 0
    quarantine_full: int = 0
    ended: tuple[str, ...] = ()  # runs whose run.end this call stored: what is kept of them is let go

    def as_dict(self) -> dict[str, Any]:
        out = asdict(self)
        del out["ended"]                     # bookkeeping for the caller, not an outcome to print
        return out
