"""Plain results of store operations, shaped to be printed by the CLI or sent as JSON."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any

from .verify_report import VerifyReport  # noqa: F401  (its home is store/verify_report.py)


@dataclass
class AppendReport:
    """What one append call did: nothing offered is dropped, so stored + duplicates +
    len(rejected) is the number of events offered. Of the rejected, quarantine_repeats were
    counted on a quarantine row holding the same bytes, and quarantine_full were past the
    quarantine's cap: counted, their bytes not kept (store/quarantine.py)."""

    stored: int = 0
    duplicates: int = 0
    rejected: list[dict[str, str]] = field(default_factory=list)  # {origin, reason}
    quarantine_repeats: int = 0
    quarantine_full: int = 0
    ended: tuple[str, ...] = ()  # runs whose run.end this call stored: what is kept of them is let go

    def as_dict(self) -> dict[str, Any]:
        out = asdict(self)
        del out["ended"]                     # bookkeeping for the caller, not an outcome to print
        return out
