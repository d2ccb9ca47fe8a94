"""Garbage collection between a writer's batches, never inside one.

A batch holds tens of thousands of small containers (the received tuples, the parsed events and
their bodies, the candidates, the rows) for a fraction of a second, and none of them is in a cycle:
reference counting frees them all once the batch is written. CPython's collector counts
allocations, though, and collects in the middle of a batch, walking every container the batch
still holds and promoting them to older generations that it then walks again. With its default
thresholds that was 4.5 us of the writer's 30-40 us an event; with a first generation of 50,000
(this module's earlier answer) it still ran about 14 young collections per 100,000 events of some
6 ms each, the batch alive every time: 0.9 us an event, about 4% of the writer, timed with
gc.callbacks on `gaps serve` taking 940,000 events (2 shared vCPUs, 2026-11-26).

So while any writer runs, automatic collection is off for the process, and each writer collects
between batches, when its last batch is already freed: the young generation then holds only what
was made since (little), every 10th time the middle one too, and everything every FULL_EVERY_S
seconds (not by count: a quiet writer looks 50 times a second, and a process with a large heap,
`gaps sim`'s, would pay a full walk each time).
Garbage in cycles, from any thread, is still collected, at the writer's pace: at least every
take, which returns within IDLE_S on a quiet link. The collector is put back as it was when the
last writer stops.
"""
from __future__ import annotations

import gc
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager

MIDDLE_EVERY = 10
FULL_EVERY_S = 10.0

_lock = threading.Lock()
_writers = 0
_was_enabled = False


@contextmanager
def collections_between_batches() -> Iterator[Callable[[], None]]:
    """Automatic collection off while this (and any other) writer runs; yields the function the
    writer calls between batches, which collects as the module docstring says."""
    global _writers, _was_enabled
    with _lock:
        if _writers == 0:
            _was_enabled = gc.isenabled()
            gc.disable()
        _writers += 1
    try:
        yield _between_batches()
    finally:
        with _lock:
            _writers -= 1
            if _writers == 0 and _was_enabled:
                gc.enable()


def _between_batches(clock: Callable[[], float] = time.monotonic) -> Callable[[], None]:
    """One writer's collector: the young generation each call, the middle one every MIDDLE_EVERY
    calls, all of them once FULL_EVERY_S have passed since the last full collection."""
    calls, full_at = 0, clock()

    def collect() -> None:
        nonlocal calls, full_at
        calls += 1
        now = clock()
        if now - full_at >= FULL_EVERY_S:
            full_at = now
            gc.collect(2)
        else:
            gc.collect(1 if calls % MIDDLE_EVERY == 0 else 0)

    return collect
