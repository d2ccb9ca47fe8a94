"""The single writer: takes received samples in batches and appends them to the store on its own thread.

SQLite wants one writer, and nothing slow may happen on Zenoh's receive path, so everything (parsing,
hashing, fsync) happens here, on a thread that owns its ``Store`` from open to close. Batching amortises
the commit (and its fsync under FULL durability) over up to ``batch_size`` events, while
``flush_interval_s`` bounds how long a lone event waits for company before it is committed.
"""
from __future__ import annotations

import logging
import os
import threading
import time
from collections.abc import Callable
from dataclasses import replace

from store import Candidate, QuarantineCap, Store
from store.cache import enable_snapshots
from store.keys import CheckpointKey, TrustedKeys

from .gap_tracker import GapTracker
from .gc_pacing import collections_between_batches
from .head_sinks import HeadSink, HeadSinks
from .idle_memory import QUIET_S, give_back
from .inbox import Inbox, Received
from .run_claims import RunClaims
from .screen import Screened, refused, require_signature, screen_all
from .stats import IngestStats
from .store_faults import Backoff, store_condition
from .wire_watch import WireWatch

log = logging.getLogger(__name__)

RETRIES = 3
RETRY_PAUSE_S = 0.2  # times the attempt number, between tries of a batch that fails for its own reasons
RUN_QUIET_S = 300.0
"""How long a run may send nothing before the writer lets go of what it keeps of it, as of a run
whose run.end came (its sources' seqs here, its chain's end in the store): a source that goes
quiet for good costs nothing for ever. If it speaks again it goes on from the store: its chain
from its last checkpoint (the tail checked, store/tail_check.py), each source from its highest
seq stored, as after a restart of the serve (tests/ingest/test_quiet_runs.py)."""
STOP_GRACE_S = 10.0
"""How long a stopping writer keeps trying a store that cannot write before it counts what it holds
as failed (the publishers' caches still hold it for the next ingest, which asks for it)."""


class BatchWriter(threading.Thread):
    """Owns the store; runs until the inbox is closed and empty. ``started`` reports a failed open."""

    def __init__(
        self,
        db_path: str | os.PathLike,
        inbox: Inbox,
        stats: IngestStats,
        tracker: GapTracker,
        *,
        batch_size: int,
        flush_interval_s: float,
        durable: bool,
        trusted_keys: TrustedKeys | None = None,
        watch: WireWatch | None = None,
        quarantine_cap: QuarantineCap = QuarantineCap(),
        checkpoint_key: CheckpointKey | None = None,
        head_sinks: tuple[HeadSink, ...] = (),
        witness: str | os.PathLike | None = None,
        run_quiet_s: float = RUN_QUIET_S,
    ) -> None:
        super().__init__(name="ingest-writer", daemon=True)
        self._run_quiet_s = run_quiet_s
        self._swept_at = time.monotonic()   # when quiet runs were last looked for (_let_go_of_quiet)
        self._checkpoint_key = checkpoint_key
        self._witness = witness  # its last head of each run is the head a run's tail must extend
        self._head_sinks = head_sinks
        self._keys = trusted_keys
        self._claims = RunClaims()
        self._watch = watch
        self._noticed: list = []   # wire_watch.Noticed waiting for the inbox to catch up (_record_wire)
        self._db_path = db_path
        self._inbox = inbox
        self._stats = stats
        self._tracker = tracker
        self._batch_size = batch_size
        self._flush_interval_s = flush_interval_s
        self._durable = durable
        self._ready = threading.Event()
        self._open_error: BaseException | None = None
        self._stalled_since: float | None = None  # monotonic time the store last began refusing commits
        self._gave_up = False                     # a stop found the store unable to write (_stalled)
        self._quarantine_full = False             # said once in the log
        self._quarantine_cap = quarantine_cap

    def started(self, timeout: float) -> None:
        """Wait until the store is open; re-raise in the caller's thread if it could not be."""
        if not self._ready.wait(timeout):
            raise TimeoutError(f"store {self._db_path} did not open within {timeout} s")
        if self._open_error is not None:
            raise self._open_error

    def run(self) -> None:
        store = self._open_store()
        if store is None:
            return
        try:
            with collections_between_batches() as between_batches:
                self._drain(store, between_batches)
        finally:
            store.close()

    def _open_store(self) -> Store | None:
        """Open the store in this thread (SQLite connections belong to the thread that made them).

        Snapshots are kept checked inside each append (store.enable_snapshots): runs
        are read while they grow, and the check costs this writer a look at its own batch
        instead of costing every reader a scan of everything appended since its last snapshot."""
        try:
            store = Store(self._db_path, durable=self._durable, quarantine_cap=self._quarantine_cap,
                          checkpoint_key=self._checkpoint_key, witness=self._witness)
            try:
                enable_snapshots(store)
                if self._head_sinks:
                    store.add_checkpoint_hook(HeadSinks(self._head_sinks, self._stats.record_error))
                self._tracker.stored_highest = store.highest_seq
                if self._watch is not None:
                    self._watch.recovery.stored_highest = store.highest_seq
            except BaseException:
                store.close()
                raise
        except BaseException as exc:  # handed to the caller of started(), not swallowed
            self._open_error = exc
            store = None
        self._ready.set()
        return store

    def _drain(self, store: Store, between_batches: Callable[[], None]) -> None:
        """Write batches until the inbox is closed and empty; nothing here may end the thread early.
        The collector runs between batches (ingest/gc_pacing.py), once the last one is let go;
        once the link has been quiet for QUIET_S, memory is given back (ingest/idle_memory.py)."""
        last_batch, kept = time.monotonic(), False
        while True:
            try:
                batch = self._inbox.take(self._batch_size, self._flush_interval_s)
            except Exception as exc:
                log.exception("ingest: taking from the inbox failed")
                self._stats.record_error(f"receive: {exc!r}")
                if self._inbox.closing:
                    return  # stop() was called; retrying a broken channel would hang it
                time.sleep(RETRY_PAUSE_S)
                continue
            if batch:
                self._stats.add(received=len(batch))
                self._write(store, batch)
                self._stats.record_lag(time.monotonic() - self._inbox.first_at)
                last_batch, kept = time.monotonic(), True
            elif kept and time.monotonic() - last_batch >= QUIET_S:
                self._inbox.renew()   # Zenoh's channel never shrinks: a fresh one, the old one freed
                give_back(store)
                kept = False
            self._record_wire(store, caught_up=batch is None or len(batch) < self._batch_size, last=batch is None)
            self._write_recovered(store)
            if batch is None:
                return
            self._let_go_of_quiet(store)
            batch = None
            between_batches()

    def _let_go_of_quiet(self, store: Store) -> None:
        """Release the runs quiet for run_quiet_s (RUN_QUIET_S), looking a few times in that span:
        the look walks the sources held, so it is made every quarter of it (at most every 30 s),
        not per batch."""
        now = time.monotonic()
        if now - self._swept_at < min(self._run_quiet_s / 4, 30.0):
            return
        self._swept_at = now
        quiet = self._tracker.quiet_runs(self._run_quiet_s)
        if quiet:
            store.release_runs(quiet)
            self._release(quiet)

    def _write_recovered(self, store: Store) -> None:
        """Store what the publishers' caches replied (ingest/wire_watch.py), as received samples."""
        if self._watch is None:
            return
        while recovered := self._watch.recovered(self._batch_size):
            self._stats.add(received=len(recovered), recovered=len(recovered))
            self._write(store, recovered, live=False)

    def _record_wire(self, store: Store, caught_up: bool, last: bool = False) -> None:
        """Record the liveliness changes and losses noticed, each saying how far its source had
        got. A change is noticed on its own channel, between two takes of samples, not at its
        place among them, so its place is known only between two bounds: the source's highest
        seq at the previous look (every event written by then arrived before the change did) and
        its highest once every sample received before the change is written (a later take found
        the inbox empty: `caught_up`; at full speed a backlog of thousands may still wait when it
        is noticed). A disappearance is placed at the upper bound, so that it never says a source
        stopped before events it sent; an appearance, and a loss on the wire, at the lower bound,
        so that neither says it came after events sent after it. So what is noticed waits until
        caught up; the last look (the inbox closed and empty) records everything. A failure costs
        those records (logged and counted), never the events; one of the disk's (a full disk)
        keeps them for a later look. (tests/ingest/test_liveliness_order.py drives each ordering.)"""
        if self._watch is None:
            return
        due: list = []
        try:
            due, self._noticed = (self._noticed, []) if caught_up else ([], self._noticed)
            noticed = self._watch.drain(self._tracker.highest_before)
            self._tracker.new_look()
            if noticed:
                (due if last else self._noticed).append(noticed)
            if due:
                highest = self._tracker.highest
                store.record_wire([c if c.alive else replace(c, last_seq=highest(c.run, c.src))
                                   for n in due for c in n.changes],
                                  [m for n in due for m in n.misses])
        except Exception as exc:
            if store_condition(exc) is not None and not last:
                self._noticed = due + self._noticed  # the disk, not the records: tried again later
            log.exception("ingest: recording liveliness changes and losses failed")
            self._stats.record_error(f"wire records: {exc!r}")

    def _write(self, store: Store, batch: list[Received], *, live: bool = True) -> None:
        """Screen and store one batch. A store that cannot write (a full disk, an I/O error: see
        ingest/store_faults.py) is waited for with the batch held, which is back-pressure: nothing
        more is taken, Zenoh's channel fills and publishers block. A batch that keeps failing for
        another reason is stored sample by sample, so that a sample the store cannot digest costs
        only itself (quarantined with the error, see ``_give_up``). Samples are counted failed only
        when the store takes not even their quarantine for a reason of theirs, or when a stop finds
        the store still unable to write after STOP_GRACE_S."""
        candidates = [item.candidate for item in self._one_producer(store, self._screen(batch, live))]
        error = self._append(store, candidates, retries=RETRIES)
        if error is None:
            return
        if store_condition(error) is not None:  # stopping, and the store still cannot write
            self._lost(candidates)
            return
        for i, candidate in enumerate(candidates):
            error = error if len(candidates) == 1 else self._append(store, [candidate], retries=0)
            if error is not None and not self._give_up(store, candidate, error):
                self._lost(candidates[i:])
                return

    def _append(self, store: Store, candidates: list[Candidate], *, retries: int) -> Exception | None:
        """Append and account for the outcome; returns None once stored, else the error that ended
        the trying. An error of the sample's own is tried ``retries`` more times; the store's
        condition (store_faults.store_condition) is waited out for as long as it lasts, with a
        backoff, unless the service is stopping and it lasted STOP_GRACE_S."""
        backoff = Backoff()
        tried = 0
        while True:
            try:
                report = store.append_candidates(candidates)
            except Exception as exc:
                self._stats.add(write_failures=1)
                self._stats.record_error(f"store ({len(candidates)} samples): {exc!r}")
                condition = store_condition(exc)
                if condition is None:
                    log.warning("ingest: storing %d samples failed: %r", len(candidates), exc)
                    if tried >= retries:
                        return exc
                    tried += 1
                    time.sleep(RETRY_PAUSE_S * tried)
                elif self._stalled(condition, len(candidates), exc):
                    time.sleep(backoff.pause())
                else:
                    return exc
                continue
            self._resumed()
            if report.ended:
                self._release(report.ended)
            self._stats.record_rejected([refused.to_json() for refused in report.rejected])
            self._stats.add(
                stored=report.stored, duplicates=report.duplicates, rejected=len(report.rejected), batches=1,
                quarantine_full=report.quarantine_full,
            )
            if store.trust_problem is not None:  # the key file could not record a run's first signed head
                self._stats.record_error(f"key file: {store.trust_problem}")
                log.error("ingest: %s", store.trust_problem)
            if report.quarantine_full and not self._quarantine_full:
                self._quarantine_full = True
                cap = store.quarantine_cap
                log.error("ingest: the quarantine is full (%d rows or %d bytes): later refusals are counted per "
                          "origin, their bytes not kept; `gaps quarantine --prune` makes room", cap.rows, cap.bytes)
            return None

    def _release(self, runs: tuple[str, ...] | list[str]) -> None:
        """What the writer kept of runs that ended or went quiet (each source's seqs) let go: a
        fleet's short runs come and go, and a source gone for good must cost nothing (the store
        let go of its chain already)."""
        self._tracker.release(runs)
        self._inbox.release(runs)
        if self._watch is not None:
            self._watch.recovery.release(runs)

    def _stalled(self, condition: str, held: int, exc: Exception) -> bool:
        """Note that the store cannot write (once in the log, as it begins); returns whether to
        keep waiting: always, unless a stop was asked for and the stall outlasted STOP_GRACE_S (then
        every later batch gives up at its first failure too: the service is going down)."""
        now = time.monotonic()
        if self._stalled_since is None:
            self._stalled_since = now
            log.error("ingest: %s (%r): holding %d samples and taking no more (publishers are held back) "
                      "until a commit succeeds; retrying", condition, exc, held)
        self._stats.stall(condition)
        if self._inbox.closing and (self._gave_up or now - self._stalled_since >= STOP_GRACE_S):
            self._gave_up = True
            return False
        return True

    def _resumed(self) -> None:
        """A commit went through: an ongoing stall is over (logged with its length)."""
        if self._stalled_since is not None:
            log.warning("ingest: the store writes again after %.1f s", time.monotonic() - self._stalled_since)
            self._stalled_since = None
            self._stats.resume()

    def _give_up(self, store: Store, candidate: Candidate, error: Exception) -> bool:
        """Quarantine a sample the store would not take, with its bytes and the error, so it is not
        lost; returns whether that worked."""
        reason = f"the store failed on this sample: {error!r}"
        return self._append(store, [refused(candidate.origin, candidate.raw, reason)], retries=0) is None

    def _lost(self, candidates: list[Candidate]) -> None:
        """Count samples neither stored nor quarantined, and name them in the log."""
        origins = sorted({c.origin for c in candidates})
        log.error("ingest: lost %d samples on %s", len(candidates), ", ".join(origins[:10]))
        self._stats.add(failed=len(candidates))

    def _screen(self, batch: list[Received], live: bool) -> list[Screened]:
        """Screen each sample and track its sequence number (a hole in the live stream is asked of
        the producers' caches); a sample that breaks screening is quarantined."""
        self._tracker.tick()
        screened = screen_all(batch, self._unscreenable)
        if self._keys is not None:
            screened = self._check_signatures(screened, self._keys)
        identities = [item.identity for item in screened if item.identity is not None]
        late = self._tracker.observe_all(identities)
        if self._watch is not None:
            self._follow_seqs(self._watch, identities, live)
        if late:
            self._stats.add(late=late)
        return screened

    def _one_producer(self, store: Store, screened: list[Screened]) -> list[Screened]:
        """Each event of a run held by another producer refused (ingest/run_claims.py); a store
        that cannot be read for it leaves the batch as it is (its append meets the same fault)."""
        try:
            return self._claims.refuse_mixed(store, screened)
        except Exception as exc:
            log.warning("ingest: checking the batch's runs against the store failed: %r", exc)
            self._stats.record_error(f"run claims: {exc!r}")
            return screened

    def _unscreenable(self, key: str, payload: bytes, exc: Exception) -> Screened:
        """A screening bug must cost one sample's verdict, not the writer: quarantined with the error."""
        log.error("ingest: screening a sample on %s failed", key, exc_info=exc)
        self._stats.record_error(f"screening: {exc!r}")
        return Screened(refused(key, payload, f"ingest could not screen this sample: {exc!r}"), None)

    def _follow_seqs(self, watch: WireWatch, identities: list[tuple[str, str, int]], live: bool) -> None:
        """Tell the cache recovery each event's seq (a hole in the live stream is asked of the
        producers' caches); a failure there costs the asking, never the batch."""
        try:
            watch.recovery.saw_all(identities, live)
        except Exception as exc:
            log.exception("ingest: following the sources' seqs failed")
            self._stats.record_error(f"cache recovery: {exc!r}")

    def _check_signatures(self, screened: list[Screened], keys: TrustedKeys) -> list[Screened]:
        """Quarantine, with the reason, each event not signed by a key trusted for its source. Here,
        on the writer's thread, not on Zenoh's: a check costs tens of microseconds."""
        checked = [require_signature(item, keys) for item in screened]
        refused_now = sum(new is not old for new, old in zip(checked, screened))
        if refused_now:
            self._stats.add(signature_refused=refused_now)
        return checked
