"""Feeding candidates to the store in batches, so a file of any size streams through memory.

Each batch is one store transaction: big enough that commits (FULL durability) do not dominate,
small enough that a crash loses at most one batch of a repeatable import.
"""

from __future__ import annotations

from itertools import islice
from typing import Callable, Iterable

from ..db import Store
from ..intake import Candidate
from .outcomes import ImportReport

BATCH = 5000


def feed(
    store: Store,
    candidates: Iterable[Candidate],
    report: ImportReport,
    *,
    batch: int = BATCH,
    after_batch: Callable[[], None] | None = None,
) -> None:
    """Append every candidate, `batch` at a time, folding each result into `report`."""
    pending = iter(candidates)
    while chunk := list(islice(pending, batch)):
        report.add(store.append_candidates(chunk))
        if after_batch is not None:
            after_batch()
