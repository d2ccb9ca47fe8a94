"""Running totals of the ingest, written by the writer thread and read by anyone.

A condition variable rather than polling lets ``wait_for`` return the moment the writer reports progress,
which keeps tests fast and exact.
"""
from __future__ import annotations

import threading
import time
from collections.abc import Callable

COUNTERS = ("received", "stored", "duplicates", "rejected", "batches", "errors", "failed", "late")
KEEP_ERRORS = 20


class IngestStats:
    """Thread-safe counters plus the last few writer errors (kept so a failure is never only in a log)."""

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self._counts = dict.fromkeys(COUNTERS, 0)
        self._errors: list[str] = []

    def add(self, **deltas: int) -> None:
        """Add to counters and wake waiters."""
        with self._cond:
            for name, delta in deltas.items():
                self._counts[name] += delta
            self._cond.notify_all()

    def record_error(self, message: str) -> None:
        """Count an error and keep its message among the most recent ones."""
        with self._cond:
            self._counts["errors"] += 1
            self._errors = (self._errors + [message])[-KEEP_ERRORS:]
            self._cond.notify_all()

    def snapshot(self) -> dict:
        """A consistent copy of the counters, with ``last_errors``."""
        with self._cond:
            return {**self._counts, "last_errors": list(self._errors)}

    def wait_for(self, predicate: Callable[[dict], bool], timeout: float) -> bool:
        """Block until ``predicate(snapshot)`` holds or ``timeout`` seconds pass; returns whether it held."""
        deadline = time.monotonic() + timeout
        with self._cond:
            while not predicate({**self._counts, "last_errors": list(self._errors)}):
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return False
                self._cond.wait(remaining)
            return True
