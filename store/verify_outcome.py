"""Everything `gaps verify` checks, in one answer with one verdict: the chains and the file
(VerifyReport), the signatures, the cached snapshots and boxes of where road users were, the
cache's seals, and the witness heads and checkpoint key kept outside the file.

`check_store` gathers it and `VerifyOutcome.ok` decides, so a script calling the store and the
command line reading the same store get the same answer: the command only renders it
(cli/verify.py). `to_json()` is `gaps verify --json`'s document.
"""
from __future__ import annotations

from contextlib import AbstractContextManager, nullcontext
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Optional, Sequence

from .keys.anchors import AnchorReport
from .cache.check import CacheTampering, cache_tampering
from .cache.presence import check_presence
from .keys.tree_heads import TreeHead
from .state import check_snapshots
from .verify_report import VerifyReport

if TYPE_CHECKING:
    from .db import Store

Progress = Callable[[int, Optional[int]], None]  # (done, total)
Bars = Callable[[str], AbstractContextManager[Optional[Progress]]]  # a progress callback per labelled phase


def _no_bar(label: str) -> AbstractContextManager[Optional[Progress]]:
    return nullcontext(None)


@dataclass(frozen=True)
class VerifyOutcome:
    """What verify found. `wrong_snapshots` and `misplaced` are per run (None when snapshots were
    not checked): the positions [t, seq, src] of snapshots, the [src, bucket] of boxes, that
    differ from the events; `heads_file` the witness file checked against, if any."""

    report: VerifyReport
    anchored: AnchorReport
    tampering: CacheTampering
    unwritten: str | None
    all_signed: bool = False
    wrong_snapshots: dict[str, list[list]] | None = None
    misplaced: dict[str, list[list]] | None = None
    heads_file: Path | None = None

    @property
    def signatures_ok(self) -> bool:
        """No invalid signature, and with all_signed no unsigned event either."""
        s = self.report.signatures
        return s is None or (not s.invalid and not (self.all_signed and s.unsigned))

    @property
    def ok(self) -> bool:
        """The verdict (exit 0 or 1): the chains, the file, the signatures, the anchors outside the
        file and the cached snapshots and boxes all agree with the events. Cache entries without
        their seal are a warning, not a failure: they are never read."""
        return (self.report.ok and self.signatures_ok and self.anchored.ok
                and not any((self.wrong_snapshots or {}).values()) and not any((self.misplaced or {}).values()))

    def to_json(self) -> dict[str, Any]:
        """`gaps verify --json`: the chains' report with the verdict and the signatures' own ok, then
        what else was checked."""
        checked_snapshots = self.wrong_snapshots is not None
        outcomes, keyed = self.anchored.heads, self.anchored.key
        counted = self.report.signatures
        return {**self.report.to_json(), "ok": self.ok,
                "signatures": {**(counted.to_json() if counted else {}), "ok": self.signatures_ok},
                **({"snapshots": self.wrong_snapshots, "presence": self.misplaced} if checked_snapshots else {}),
                "cache": {**self.tampering.to_json(), "unwritten": self.unwritten},
                **({"heads": {"file": str(self.heads_file), "ok": all(o.ok for o in outcomes),
                              "checked": [o.to_json() for o in outcomes]}} if self.heads_file else {}),
                **({"checkpoint_key": keyed.to_json()} if keyed is not None else {}),
                **({"proven": [p.to_json() for p in self.anchored.runs]} if self.anchored.runs else {})}


def check_store(store: Store, run: str | None = None, *, keys: Any = None, heads: Sequence[TreeHead] = (),
                heads_file: Path | None = None, public: bytes | None = None, recorded: Sequence[TreeHead] = (),
                snapshots: bool = True, all_signed: bool = False, bars: Bars = _no_bar) -> VerifyOutcome:
    """Verify the store (one run, or all), as `gaps verify` does: `keys` (store.TrustedKeys) to
    check the signatures with; the witness `heads` read from `heads_file`; the checkpoint key's
    `public` key and the runs' first signed heads its file `recorded`; `snapshots` to check the
    cached snapshots and boxes too (of the runs whose chain holds: a broken one has already
    failed, and may not be readable); `bars` gives each phase its progress callback."""
    heads = list(heads) if run is None else [h for h in heads if h.run == run]
    with bars("verifying") as progress:
        report = store.verify(run, progress, keys)
    anchored = store.anchor_report(heads, public, run, recorded, witness=heads_file is not None)
    wrong = misplaced = None
    if snapshots:
        sound = [r.run for r in report.runs if r.ok]
        wrong = _per_run(bars, "checking snapshots", sound, lambda name: check_snapshots(store, name))
        misplaced = _per_run(bars, "checking where road users were", sound, lambda name: check_presence(store, name))
    tampering = cache_tampering(store, [r.run for r in report.runs if isinstance(r.run, str)])
    return VerifyOutcome(report, anchored, tampering, store.cache.unwritten, all_signed, wrong, misplaced, heads_file)


def _per_run(bars: Bars, label: str, runs: list[str], check: Callable[[str], Sequence[Any]]) -> dict[str, list[list]]:
    """Each run's wrong entries (as lists, for JSON), with a progress callback per run checked."""
    with bars(label) as progress:
        wrong = {}
        for i, name in enumerate(runs):
            wrong[name] = [list(entry) for entry in check(name)]
            if progress is not None:
                progress(i + 1, len(runs))
    return wrong
