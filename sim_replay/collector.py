"""Python's cyclic garbage collector, run less often while the simulation ticks.

A tick at a thousand vehicles builds some ten thousand short-lived containers (snapshot tuples,
events and their bodies) and frees almost all of them by reference counting within the tick. With
CPython's default first threshold (700 net allocations) that churn alone starts a young-generation
collection about fifteen times a tick and a full one every few seconds, which walks every object
the run holds: measured at 1,000 vehicles on the bench grid, a tenth of the simulation's CPU time,
for almost no garbage (the loop makes few reference cycles). A threshold above a tick's transient
peak leaves the collector to the rare real growth. Nothing the simulation computes depends on when
the collector runs, so the events are the same.
"""
from __future__ import annotations

import gc
from collections.abc import Iterator
from contextlib import contextmanager

__all__ = ["THRESHOLD", "fewer_collections"]

THRESHOLD = 10_000    # net container allocations before a young collection (CPython's default: 700)


@contextmanager
def fewer_collections(threshold: int = THRESHOLD) -> Iterator[None]:
    """Raise the collector's first threshold to `threshold` for the block and put the old thresholds
    back after. A threshold already higher, or 0 (automatic collection off), is left as it is: this
    never makes collections more frequent."""
    before = gc.get_threshold()
    if 0 < before[0] < threshold:
        gc.set_threshold(threshold, *before[1:])
    try:
        yield
    finally:
        gc.set_threshold(*before)
