"""Plain results of store operations, shaped to be printed by the CLI or sent as JSON."""

from __future__ import annotations

from dataclasses import asdict, dataclass, field
from typing import Any


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


@dataclass
class VerifyReport:
    """Outcome of recomputing the chains.

    runs: one {run, events, head, ok} per run checked (head is the recomputed chain head, None
    when the run failed); problem: the first event that did not match, as
    {run, src, seq, chain_pos, what}, with src and seq None when the event itself is missing.
    ok is the verdict of the chains and the file's integrity. signatures: the events signed and unsigned, and, when keys
    were given, how many signatures are valid and invalid and the first invalid one
    (store/signature_tally.py); None where not counted (a result kept in the cache).
    integrity: SQLite's integrity check of the file, {ok, messages} (store/integrity.py); a
    failing one makes ok False and, when no event failed first, is the problem.
    """

    ok: bool
    runs: list[dict[str, Any]] = field(default_factory=list)
    problem: dict[str, Any] | None = None
    signatures: dict[str, Any] | None = None
    integrity: dict[str, Any] | None = None

    def as_dict(self) -> dict[str, Any]:
        return asdict(self)
