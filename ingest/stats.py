"""Running totals of the ingest, written by the writer thread and read by anyone.

A condition variable rather than polling lets ``wait_for`` return the moment the writer reports progress,
which keeps tests fast and exact.
"""
from __future__ import annotations

import threading
import time
from collections.abc import Callable

COUNTERS = ("received", "stored", "duplicates", "rejected", "batches", "errors", "failed", "late", "signature_refused",
            "recovered", "write_failures", "quarantine_full")
"""signature_refused: samples quarantined for their signature (unsigned, unknown key, forged), when
signatures are required; they are counted in rejected too. recovered: samples a producer's cache
sent after a restart (docs/serve.md). write_failures: commits the store refused (each try of a
stalled write counts). quarantine_full: refusals past the quarantine's cap, counted in the
store per origin, their bytes not kept (store/quarantine.py)."""
KEEP_ERRORS = 20
KEEP_REJECTED = 20


class IngestStats:
    """Thread-safe counters plus the last few writer errors and refusals (kept so a failure or a
    quarantined sample is never only in a log), and the writer's lag."""

    def __init__(self) -> None:
        self._cond = threading.Condition()
        self._counts = dict.fromkeys(COUNTERS, 0)
        self._errors: list[str] = []
        self._rejected: list[dict[str, str]] = []
        self._lag_s = 0.0
        self._lag_max_s = 0.0
        self._stalled_at: float | None = None   # monotonic time the current stall began
        self._stall_reason: str | None = None
        self._stalled_before_s = 0.0            # the stalls that ended, in all

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

    def record_rejected(self, refusals: list[dict[str, str]]) -> None:
        """Keep the most recent refusals ({origin, reason}) so an operator sees why, not just how many."""
        if refusals:
            with self._cond:
                self._rejected = (self._rejected + refusals[-KEEP_REJECTED:])[-KEEP_REJECTED:]

    def record_lag(self, seconds: float) -> None:
        """The last batch's lag: from its first sample leaving Zenoh's channel to its commit. Time a
        sample spent queued inside Zenoh before that is not visible to Python, so it is not included."""
        with self._cond:
            self._lag_s = seconds
            self._lag_max_s = max(self._lag_max_s, seconds)

    def stall(self, reason: str) -> None:
        """The store cannot write (``reason``): the writer holds its batch and takes nothing more."""
        with self._cond:
            if self._stalled_at is None:
                self._stalled_at = time.monotonic()
            self._stall_reason = reason
            self._cond.notify_all()

    def resume(self) -> None:
        """The store writes again: the stall's time is added to ``stalled_s``."""
        with self._cond:
            if self._stalled_at is not None:
                self._stalled_before_s += time.monotonic() - self._stalled_at
            self._stalled_at, self._stall_reason = None, None
            self._cond.notify_all()

    def snapshot(self) -> dict:
        """A consistent copy of the counters, with ``last_errors``, ``last_rejected``, ``lag_s``,
        ``lag_max_s``, and the stalls: ``stall`` (why the store cannot write now, None when it can),
        ``stalled_for_s`` (how long this stall has lasted) and ``stalled_s`` (all stalls, this one
        included)."""
        with self._cond:
            return self._snapshot()

    def _snapshot(self) -> dict:
        now = 0.0 if self._stalled_at is None else time.monotonic() - self._stalled_at
        return {**self._counts, "last_errors": list(self._errors), "last_rejected": list(self._rejected),
                "lag_s": self._lag_s, "lag_max_s": self._lag_max_s, "stall": self._stall_reason,
                "stalled_for_s": now, "stalled_s": self._stalled_before_s + now}

    def wait_for(self, predicate: Callable[[dict], bool], timeout: float) -> bool:
        """Block until ``predicate(snapshot)`` holds or ``timeout`` seconds pass; returns whether it held."""
        deadline = time.monotonic() + timeout
        with self._cond:
            while not predicate(self._snapshot()):
                remaining = deadline - time.monotonic()
                if remaining <= 0:
                    return False
                self._cond.wait(remaining)
            return True
