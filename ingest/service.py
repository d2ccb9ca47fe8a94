"""The ingest service: Zenoh ``gaps/**`` in, the store out.

Zenoh fills a bounded FIFO channel (``inbox.Inbox``) without running any Python; a single writer thread
(``writer.BatchWriter``) owns the store and takes from the channel in batches, and between batches
records the sources' liveliness changes and the samples lost beyond their publishers' caches
(``wire_watch.WireWatch``, channels too). ``stop`` closes the session,
which closes the channel; the writer then takes what is left, commits it, closes the store and ends.
"""
from __future__ import annotations

import logging
import os
from collections.abc import Callable, Sequence
from types import TracebackType

import zenoh

from store import QuarantineCap
from store.keys import CheckpointKey, TrustedKeys
from store.wire import SYNC_KEY, session_config, zenoh_message

from . import exposure
from .gap_tracker import GapTracker
from .head_sinks import ZenohHeads, witness_sink
from .history_queryable import HistoryQueryable
from .inbox import Inbox
from .stats import IngestStats
from .wire_watch import WireWatch
from .writer import RUN_QUIET_S, BatchWriter

log = logging.getLogger(__name__)

SUBSCRIPTION = "gaps/**"
BATCH_SIZE = 10_000
"""The most events one commit takes. A busy ingest commits full batches, and each commit rewrites
every page its inserts touched: with a thousand sources the (run, src, seq) index is touched all
over, so a batch of 1,000 cost as much disk as one of 10,000 (measured on 588,655 events of a
1,000-vehicle simulation: 62.7 s against 36.0 s). A quiet ingest commits after flush_interval_s
whatever it has, so this bounds work per commit, not latency."""
MAX_PENDING = 100_000
"""Samples Zenoh may hold for the writer before it pushes back on publishers. Zenoh's channel is a
queue that grows to hold what waits and never shrinks: a fleet's burst left up to 32-64 MB resident
in the serve (bench/ingest_fleet.py, 10,000 runs: RSS after 137 MB against 80 MB idle; 114 MB with
16,384), until a quiet inbox came to renew its subscription, channel and all (ingest/inbox.py
`renew`), which frees it. It stays this large: what it holds is
what a burst may put before its producer is held back, and a producer that closes its session soon
after its last put (as foreign ones do) loses what is still on its side of the link: a 60,000-event
burst into a writer taking 2,000 a second, the producer closing 1 s after its last put, arrived
whole with 100,000 and lost 4,939 events with 16,384 (measured 2026-12-07)."""
OPEN_TIMEOUT_S = 30.0


class IngestService:
    """Subscribes to ``key_expr`` (``gaps/**``: every run) and appends everything received to the store
    at ``db_path``.

    With ``trusted_keys`` (the public keys file, loaded), an event not signed by a key trusted for its
    source is quarantined with the reason, and the liveliness tokens of sources no key is trusted for
    are not recorded; ``quarantine_cap`` bounds what the quarantine keeps
    (store/quarantine.py). With ``checkpoint_key`` every checkpoint is signed, and each
    signed tree head is appended to the ``witness`` file and, with ``publish_heads``, put on
    ``gaps/@heads/<run>`` (ingest/head_sinks.py). Reachable beyond loopback, it needs
    ``trusted_keys`` and Zenoh's authentication in its config, or ``insecure`` (an
    IngestConfigError otherwise, before anything is opened; ingest/exposure.py).
    Use as a context manager, or call ``stop()``: it stops
    receiving, flushes every sample already
    received into the store and closes the store and the session.
    """

    def __init__(
        self,
        db_path: str | os.PathLike,
        *,
        listen: Sequence[str] = (),
        connect: Sequence[str] = (),
        mode: str | None = None,
        config_file: str | os.PathLike | None = None,
        key_expr: str = SUBSCRIPTION,
        batch_size: int = BATCH_SIZE,
        flush_interval_s: float = 0.05,
        durable: bool = True,
        max_pending: int = MAX_PENDING,
        trusted_keys: TrustedKeys | None = None,
        quarantine_cap: QuarantineCap = QuarantineCap(),
        checkpoint_key: CheckpointKey | None = None,
        witness: str | os.PathLike | None = None,
        publish_heads: bool = False,
        insecure: bool = False,
        run_quiet_s: float = RUN_QUIET_S,
    ) -> None:
        if (witness is not None or publish_heads) and checkpoint_key is None:
            raise ValueError("a witness file or published heads need a checkpoint key to sign them")
        if batch_size < 1 or flush_interval_s < 0 or max_pending < 1:
            raise ValueError("batch_size and max_pending must be >= 1, flush_interval_s >= 0")
        self._stats = IngestStats()
        self._tracker = GapTracker()
        self._stopped = False
        config = session_config(listen=listen, connect=connect, mode=mode, config_file=config_file)
        self.exposure = exposure.exposure(config)
        self.insecure_because = exposure.check(self.exposure, signatures_required=trusted_keys is not None,
                                               insecure=insecure)
        self._session = zenoh.open(config)
        self._witness = None
        try:
            self._witness = witness_sink(witness)
            sinks = tuple(s for s in (self._witness.append if self._witness else None,
                                      ZenohHeads(self._session) if publish_heads else None) if s is not None)
            inbox = Inbox(self._session, key_expr, max_pending)
            watch = WireWatch(self._session, inbox, key_expr, trusted_keys.covers if trusted_keys else None)
            self._writer = BatchWriter(
                db_path, inbox, self._stats, self._tracker, batch_size=batch_size,
                flush_interval_s=flush_interval_s, durable=durable, trusted_keys=trusted_keys, watch=watch,
                quarantine_cap=quarantine_cap,
                checkpoint_key=checkpoint_key, head_sinks=sinks, witness=witness, run_quiet_s=run_quiet_s,
            )
            self._writer.start()
            self._writer.started(OPEN_TIMEOUT_S)
            self._sync = self._session.declare_queryable(SYNC_KEY, watch.syncs)   # ingest/sync_answer.py
            self._history = HistoryQueryable(self._session, db_path, key_expr)  # docs/serve.md "History"
        except BaseException:
            self._session.close()
            if self._witness is not None:
                self._witness.close()
            raise

    def stats(self) -> dict:
        """Running totals: received, stored, duplicates, rejected, batches; and errors (with
        last_errors), failed (samples in batches given up after retries), late (arrived after a higher
        seq of their source). A sample counts as received once the writer has taken it."""
        return self._stats.snapshot()

    def gaps(self) -> list[dict]:
        """Sequence gaps seen on the wire: ``[{run, src, missing: [[first, last], ...], highest}]``."""
        return self._tracker.gaps()

    def missing(self) -> tuple[int, int]:
        """(sequence numbers missing on the wire in all, sources missing any): ``gaps`` in a line."""
        return self._tracker.missing()

    def sources(self, active_within_s: float) -> tuple[int, int]:
        """(sources seen, sources that sent something within the last ``active_within_s`` seconds)."""
        return self._tracker.sources(active_within_s)

    @property
    def writing(self) -> bool:
        """Whether the writer thread still runs: False after ``stop``, or if it died, which a
        supervisor must hear about rather than watch a service that accepts and stores nothing."""
        return self._writer.is_alive()

    def wait_for(self, predicate: Callable[[dict], bool], timeout: float) -> bool:
        """Wait until ``predicate(stats)`` holds; False on timeout."""
        return self._stats.wait_for(predicate, timeout)

    def wait_until_stored(self, n: int, timeout: float) -> bool:
        """Wait until at least ``n`` events were stored (committed) since start."""
        return self.wait_for(lambda s: s["stored"] >= n, timeout)

    def wait_until_settled(self, n: int, timeout: float) -> bool:
        """Wait until at least ``n`` samples were received and each has an outcome (stored, duplicate,
        rejected or failed): for inputs that are meant to be refused, where ``stored`` never moves."""
        return self.wait_for(lambda s: s["received"] >= n and _settled(s), timeout)

    def stop(self) -> None:
        """Stop receiving, flush what was received, close store and session. Safe to call twice."""
        if self._stopped:
            return
        self._stopped = True
        self._history.close()
        try:
            self._session.close()
        except zenoh.ZError as exc:   # Zenoh gives up after 10 s, e.g. on a history reply a querier never takes
            log.warning("ingest: closing the Zenoh session: %s; storing what was received all the same",
                        zenoh_message(exc))
        finally:
            self._writer.join()
            self._history.join()
            if self._witness is not None:
                self._witness.close()

    def __enter__(self) -> IngestService:
        return self

    def __exit__(
        self,
        exc_type: type[BaseException] | None,
        exc: BaseException | None,
        tb: TracebackType | None,
    ) -> None:
        self.stop()



def _settled(s: dict) -> bool:
    """Every received sample has an outcome."""
    return s["stored"] + s["duplicates"] + s["rejected"] + s["failed"] >= s["received"]
