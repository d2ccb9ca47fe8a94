"""The store: one SQLite file holding an append-only, hash-chained log of events per run.

Appends are the hot path (every event of every vehicle passes through here): chain heads and
the highest stored seq of each source are cached (store/heads.py), rows are built in memory
(store/batch.py) and written with executemany, one transaction per call.
"""

from __future__ import annotations

import heapq
import os
import sqlite3
import time
from contextlib import contextmanager
from pathlib import Path
from itertools import islice
from operator import itemgetter
from typing import Any, Callable, Collection, Iterable, Iterator, Sequence

from .keys import anchors
from . import envelope, index_guard, opening, queries, quarantine, rulebook_chain, rulebooks
from .wire import history, ends as wire_ends, liveliness
from .cache import verified as verify_cache
from .cache.file import Cache
from .output_files import note_evidence
from .ddl import DENSE_KINDS
from .batch import Batch
from .chain import RunChain
from .heads import Heads
from .integrity import integrity_problems
from .intake import Candidate, from_raw
from .kinds import SRC_ROLES
from .errors import EvidenceError, StoreError
from .sqlite_errors import translate_methods
from .event_rows import events_of
from .outcomes import AppendReport
from .verify_report import SignatureCount, VerifyReport
from .reading import one_snapshot
from .run_summary import RunSummary
from .keys.tally import SignatureTally
from .keys.anchors import HeadOutcome, KeyCheck
from .keys.tree_heads import CheckpointKey, TreeHead
from .keys.trust_root import SignedRuns
from .verify import Progress, tolerant_text, verify_store

_INSERT_EVENT = (
    "INSERT INTO events (run, chain_pos, src, seq, t, kind, event, hash) VALUES (?, ?, ?, ?, ?, ?, ?, ?)"
)
_INSERT_CHECKPOINT = (
    "INSERT INTO checkpoints (run, count, head, created_at, merkle_root, frontier, prev_count, signature, key_id, "
    "wire) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)"
)
CHECKPOINT_EVERY = 1000


AppendHook = Callable[["Store", dict[str, int]], None]
CheckpointHook = Callable[[list[TreeHead]], None]

PAGE_SIZE = opening.PAGE_SIZE


@translate_methods
class Store:
    """An event store file. Use one Store from one thread at a time (check_same_thread=False
    only lets it move between threads); separate processes may share a file safely.

    durable=True (the default) commits with synchronous=FULL: when append returns, its events
    are on disk and survive a power cut. durable=False (synchronous=NORMAL) may lose the last
    transactions on power loss, never corrupting the file; for bulk imports that can be
    repeated. Each run gets a checkpoint every `checkpoint_every` events (docs/store.md).

    checkpoint_key (store/tree_heads.py) signs every checkpoint written; the signed tree heads
    are handed to the checkpoint hooks once committed (a witness file, a Zenoh key). Before a
    run read from the file is extended, its tail is checked against its last checkpoint signed
    by that key and against the run's last signed head known outside the file: the last head of
    the run in `witness` (the witness file the ingest appends its heads to), else the first signed
    head the key's public file records (store/trust_root.py, store/tail_check.py); a run's first
    signed head is appended to that file.

    read_only=True (or Store.open_read_only) reads the file without changing it; derived data
    (state snapshots, verification results) goes to `self.cache`, a separate file (store/cache.py).

    quarantine_cap bounds what the quarantine keeps (store/quarantine.py): past it, refusals are
    counted (AppendReport.quarantine_full), not kept.
    """

    def __init__(
        self,
        path: str | os.PathLike,
        *,
        durable: bool = True,
        check_same_thread: bool = True,
        checkpoint_every: int = CHECKPOINT_EVERY,
        read_only: bool = False,
        quarantine_cap: quarantine.QuarantineCap = quarantine.QuarantineCap(),
        checkpoint_key: CheckpointKey | None = None,
        witness: str | os.PathLike | None = None,
        cache_at: str | None = None,
    ) -> None:
        if type(checkpoint_every) is not int or checkpoint_every < 1:
            raise ValueError(f"checkpoint_every must be a positive integer, got {checkpoint_every!r}")
        self.path = os.fspath(path)
        note_evidence(self.path)            # no output of this process may be it (store/output_files.py)
        self.checkpoint_every = checkpoint_every
        self.read_only = read_only
        if read_only:
            self._conn = opening.connect_read_only(self.path, check_same_thread=check_same_thread)
        else:
            self._conn = opening.connect_writable(self.path, durable=durable, check_same_thread=check_same_thread)
        self.checkpoint_key = checkpoint_key
        self._signed_runs = None if checkpoint_key is None else SignedRuns(
            checkpoint_key.public, checkpoint_key.public_file(), None if witness is None else Path(witness))
        self._heads = Heads(self._conn, checkpoint_key, self._signed_runs)
        self._rulebook_tip = rulebook_chain.RulebookTip()  # the rulebooks' chain end the checkpoints record
        self.quarantine_cap = quarantine_cap
        self._quarantine_tally = quarantine.QuarantineTally(self._conn)
        self._data_version = self._read_data_version()
        self._append_hooks: list[AppendHook] = []
        self._appended: dict[str, RunChain] = {}  # the chains the append whose hooks run committed
        self._checkpoint_hooks: list[CheckpointHook] = []
        self._integrity: tuple[tuple[int, int], list[str]] | None = None  # (file state, problems)
        self.cache = Cache(self.path, at=cache_at)

    @classmethod
    def open_read_only(cls, path: str | os.PathLike, *, check_same_thread: bool = True) -> Store:
        """Open an existing store to read it, changing nothing in the file (docs/store.md):
        StoreError if it is missing, not an event store, or of an older schema (`gaps migrate`)."""
        return cls(path, check_same_thread=check_same_thread, read_only=True)

    # --- lifecycle -----------------------------------------------------------------------------

    def shrink_memory(self) -> None:
        """Give back the connections' page caches (SQLite keeps up to CACHE_KIB each) and the
        run names the envelope check remembers (envelope.forget_admitted), and the weak references
        to dead cursors (opening.drop_dead_cursors): what an ingest that went quiet calls, so that a
        fleet's burst is not resident for ever."""
        self._conn.execute("PRAGMA shrink_memory")
        opening.drop_dead_cursors(self._conn)
        self.cache.shrink_memory()
        envelope.forget_admitted()

    def close(self) -> None:
        self.cache.close()
        if not self.read_only:
            opening.leave_rollback_journal(self._conn)
        self._conn.close()

    def __enter__(self) -> Store:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # --- appending -----------------------------------------------------------------------------

    def append(self, events: Iterable[dict], origin: str = "api") -> AppendReport:
        """Append decoded events; all of them come from `origin`."""
        if isinstance(events, dict):
            raise TypeError("append takes an iterable of events; wrap a single event in a list")
        return self._append(lambda batch: batch.offer_events(events, str(origin)))

    def append_raw(self, items: Iterable[tuple[bytes, str]]) -> AppendReport:
        """Append events as received: (raw bytes, where they came from) pairs."""
        if isinstance(items, (bytes, bytearray, memoryview)):
            raise TypeError("append_raw takes an iterable of (raw bytes, origin) pairs")
        return self.append_candidates(from_raw(raw, str(origin)) for raw, origin in items)

    def append_candidates(self, candidates: Iterable[Candidate]) -> AppendReport:
        """Store, count or quarantine each candidate, in order, all in one transaction.

        For callers that judge input themselves before the store does (the ingest refuses a
        sample whose Zenoh key disagrees with its event, and reads identities for gap tracking
        without parsing twice). A refused candidate is quarantined with its raw bytes and reason.
        An accepted one is trusted as built: make it with intake.from_raw/from_dict or from
        envelope.decode_event/encode_event, never with hand-made canonical bytes.
        """
        return self._append(lambda batch: batch.offer_candidates(candidates))

    def _append(self, feed: Callable[[Batch], None]) -> AppendReport:
        """Feed a batch, then write its rows and run the hooks, all in one transaction that is
        committed (durably, by default) before the report is returned; then run the hooks."""
        with self._transaction() as conn:
            batch = Batch(self._heads, self.checkpoint_every, time.time_ns(), self.checkpoint_key,
                          wire_ends.ends_now(conn, self._rulebook_tip))
            feed(batch)
            batch.finish()
            conn.executemany(_INSERT_EVENT, batch.events)
            kept = quarantine.keep(conn, batch.refused, self.quarantine_cap, self._quarantine_tally)
            conn.executemany(_INSERT_CHECKPOINT, batch.checkpoints)
        for run in batch.ended:                  # committed: an ended run costs nothing kept for ever
            self._heads.release(run)
        self._appended = batch.grown
        try:
            self._run_hooks(batch.events)
        finally:
            self._appended = {}
        batch.report.quarantine_repeats, batch.report.quarantine_full = kept.repeats, kept.over_cap
        if batch.signed:
            assert self._signed_runs is not None  # only a store with a checkpoint key signs
            self._signed_runs.signed(batch.signed)
            for hook in self._checkpoint_hooks:
                hook(batch.signed)
        return batch.report

    def release_runs(self, runs: Iterable[str]) -> None:
        """Let go of what the append path keeps of these runs (their chains' ends, their sources'
        highest seqs): for runs that went quiet without a run.end (an ended run is let go as its
        run.end commits). Nothing is lost: a later event of one reloads its chain from its last
        checkpoint, its tail checked as on a reopened store (store/tail_check.py), and goes on."""
        for run in runs:
            self._heads.release(run)

    @property
    def trust_problem(self) -> str | None:
        """Why the key's public file could not record a run's first signed head at the last append
        that signed one (store/trust_root.py), or None; the append itself was committed."""
        return None if self._signed_runs is None else self._signed_runs.problem

    def add_checkpoint_hook(self, hook: CheckpointHook) -> None:
        """Call `hook(heads)` with the signed tree heads of each append's checkpoints, once they are
        committed (with a checkpoint key only): to publish them outside the store (store/witness.py)."""
        self._checkpoint_hooks.append(hook)

    def add_append_hook(self, hook: AppendHook) -> None:
        """Call `hook(store, {run: min_t, ...})` after every append that stored events, once, with
        each run it stored events of and the earliest t among them: derived data (state snapshots,
        in the cache file) can drop what a late event makes stale before anyone reads it. Once per
        append, not per run: a fleet's batch holds hundreds of runs, and a cache transaction each
        cost the ingest 20 ms a run (bench/ingest_fleet.py)."""
        self._append_hooks.append(hook)

    def appended_end(self, run: str) -> tuple[int, str] | None:
        """(chain length, head hash) of the run as the append whose hooks are running committed it,
        or None outside the hooks or for a run it did not extend: what an append hook would
        otherwise read back from the file (two queries a run, for each of a fleet's runs)."""
        chain = self._appended.get(run)
        return None if chain is None else (chain.count, chain.head.hex())

    def _run_hooks(self, rows: list[tuple]) -> None:
        if not self._append_hooks or not rows:
            return
        earliest = _earliest_t(rows)
        for hook in self._append_hooks:
            hook(self, earliest)

    def checkpoints(self, run: str) -> list[dict[str, Any]]:
        """The run's checkpoints, oldest first, as stored (count, head, merkle_root, ...)."""
        cur = self._conn.execute("SELECT * FROM checkpoints WHERE run = ? ORDER BY id", (run,))
        names = [d[0] for d in cur.description]
        return [dict(zip(names, row)) for row in cur]

    @property
    def connection(self) -> sqlite3.Connection:
        """The underlying connection, for the store's own modules (state folding, transfer)."""
        return self._conn

    @contextmanager
    def _transaction(self) -> Iterator[sqlite3.Connection]:
        """BEGIN IMMEDIATE (take the write lock first, so the caches cannot go stale while we
        write); on any failure roll back and forget the caches, which may hold unwritten state."""
        if self.read_only:
            raise StoreError(f"the event store {self.path} is open read-only: it cannot be written")
        self._conn.execute("BEGIN IMMEDIATE")
        try:
            self._refresh_caches()
            yield self._conn
            self._conn.execute("COMMIT")
        except BaseException:
            if self._conn.in_transaction:
                self._conn.execute("ROLLBACK")
            self._heads.forget()
            self._quarantine_tally.forget()
            self._rulebook_tip.forget()
            raise

    def _refresh_caches(self) -> None:
        """Drop the caches if another connection has committed since we last looked."""
        version = self._read_data_version()
        if version != self._data_version:
            self._heads.forget()
            self._quarantine_tally.forget()
            self._rulebook_tip.forget()
            self._data_version = version

    def _read_data_version(self) -> int:
        return self._conn.execute("PRAGMA data_version").fetchone()[0]

    # --- reading -------------------------------------------------------------------------------

    def events(
        self,
        run: str,
        *,
        kinds: Collection[str] | None = None,
        srcs: Collection[str] | None = None,
        t_from: int | None = None,
        t_to: int | None = None,
    ) -> Iterator[dict]:
        """A run's events in (t, seq, src) order, streamed from the file; t_to is inclusive.
        Sparse kinds are read through the covering index by kind, each entry checked against its
        chained row: IndexDisagrees (exit 1) at the first that is not (store/index_guard.py)."""
        chosen = queries.collection("kinds", kinds)
        wanted = None if chosen is None else sorted(set(chosen))
        if wanted is not None and len(wanted) > 1 and not set(wanted) & set(DENSE_KINDS):
            # one index range per kind, merged: cheaper than the whole run's time index
            streams = [self._rows(run, [kind], srcs, t_from, t_to) for kind in wanted]
            rows: Iterator[tuple] = heapq.merge(*streams)
        else:
            rows = self._rows(run, wanted, srcs, t_from, t_to)
        return _parsed(index_guard.checked(rows, run), run)

    def _rows(self, run: str, kinds, srcs, t_from, t_to) -> Iterator[tuple]:
        sql, params = queries.select_events(run, kinds, srcs, t_from, t_to)
        return self._conn.execute(sql, params)

    def source_events(
        self,
        run: str,
        src: str,
        *,
        kinds: Collection[str] | None = None,
        t_from: int | None = None,
        t_to: int | None = None,
    ) -> list[dict]:
        """One source's events with t in [t_from, t_to] (inclusive; None: open), in (t, seq)
        order: a vehicle's entity.state series around an act, without reading the other
        sources' events of that time. `events(run, srcs=[src])` walks the run's time index;
        this reads the (run, src, seq) index, finding the window's seq range by a search of a
        few probes, so its cost follows the events returned, not the run's length.

        The search takes a source's t to rise with its seq, as a producer numbering its events
        in the order it publishes them does (DESIGN "Envelope"); an event out of that order by
        up to SEQ_SLACK (64) places is still found, one further out may be missed."""
        with self._reading():
            rows = queries.source_rows(self._conn, run, src, kinds, t_from, t_to)
        return events_of(rows, run)

    def observations_of(
        self,
        run: str,
        vehicle: str,
        *,
        srcs: Collection[str] | None = None,
        t_from: int | None = None,
        t_to: int | None = None,
    ) -> list[dict]:
        """The monitor.observation events about one vehicle (body.vehicle, compared as text),
        from the monitors `srcs` (default: all), with t in [t_from, t_to], in (t, seq, src)
        order: what monitors measured of a vehicle that records nothing itself. Read through
        the covering index by kind, each entry checked against its chained row (IndexDisagrees);
        the vehicle is matched inside SQLite, so observations of other vehicles are never parsed."""
        with self._reading():
            rows = list(index_guard.checked(queries.observation_rows(self._conn, run, str(vehicle), srcs,
                                                                      t_from, t_to), run))
        return events_of(rows, run)

    def history(self, run: str, wanted: history.HistoryFilter = history.HistoryFilter(), *,
                after: int = -1, chunk: int = history.CHUNK) -> Iterator[history.HistoryRow]:
        """The run's events that pass `wanted`, above chain position `after`, in chain order, as
        stored (canonical text and chain hash): what a history query over Zenoh answers. Read
        `chunk` rows at a time, each chunk in its own short read transaction, so a long answer
        holds neither memory nor a snapshot that keeps a live ingest's WAL from being folded back
        (store/history.py)."""
        return history.history_rows(self._conn, run, wanted, after, chunk)

    def chain_head(self, run: str) -> tuple[int, str]:
        """(events in the run's chain, stored hash of its last event); (0, "") for no events."""
        return verify_cache.chain_key(self._conn, run)

    def chain_tip(self, run: str) -> tuple[int, str]:
        """The run's chain as stored now, by its last chain position: (that position + 1, the
        stored hash there), (0, "") for no events. Two index probes, where chain_head counts
        the rows (seconds on a long run); what the derived cache is keyed by
        (store/derived_cache.py). An append changes both; a row taken out of the middle is no
        append and is for `gaps verify` to find, as the chain then no longer holds."""
        with self._reading():
            return queries.chain_tip(self._conn, run)

    def runs(self) -> list[RunSummary]:
        """Every run with events, by run name."""
        return [queries.run_summary(self._conn, run) for run in queries.run_names(self._conn)]

    def count(self, run: str | None = None) -> int:
        if run is None:
            return self._conn.execute("SELECT count(*) FROM events").fetchone()[0]
        return self._conn.execute("SELECT count(*) FROM events WHERE run = ?", (run,)).fetchone()[0]

    def quarantined(self, limit: int | None = None, *, latest: bool = False) -> list[dict[str, Any]]:
        """What the quarantine keeps, oldest first, with the exact bytes received: all of it, the
        first `limit` entries, or with latest=True the last `limit` ones. A row stands for `count`
        identical refusals (same source, reason and bytes), the first from origin at received_at,
        the last from last_origin at last_at (store/quarantine.py)."""
        select = ("SELECT id, received_at, origin, reason, raw, count, coalesce(last_at, received_at), digest, "
                  "coalesce(last_origin, origin) FROM quarantine")
        if latest:
            sql = f"SELECT * FROM ({select} ORDER BY id DESC LIMIT ?) ORDER BY id"
        else:
            sql = f"{select} ORDER BY id LIMIT ?"
        rows = self._conn.execute(sql, (-1 if limit is None else limit,))
        return [
            {"id": id_, "received_at": received_at, "origin": origin, "reason": reason, "raw": bytes(raw),
             "count": count, "last_at": last_at, "digest": digest, "last_origin": last_origin}
            for id_, received_at, origin, reason, raw, count, last_at, digest, last_origin in rows
        ]

    def quarantine_count(self) -> int:
        """Rows the quarantine keeps (each may stand for several identical refusals)."""
        return self._conn.execute("SELECT count(*) FROM quarantine").fetchone()[0]

    def quarantine_summary(self) -> dict[str, Any]:
        """The quarantine in figures, read together: what it holds ({rows, samples, bytes}), the
        refusals counted past its cap per origin (`over_cap`), and every recorded prune."""
        with self._reading():
            return {"held": quarantine.held(self._conn), "over_cap": quarantine.overflow(self._conn),
                    "prunes": [p.to_json() for p in quarantine.prunes(self._conn)]}

    def prune_quarantine(self, before: int) -> quarantine.Pruned | None:
        """Remove the quarantine rows whose last refusal came before `before` (ns), recording what
        they were in the same transaction; None if none did (store/quarantine.py)."""
        with self._transaction() as conn:
            pruned = quarantine.prune(conn, before, time.time_ns())
        self._quarantine_tally.forget()
        return pruned

    def gaps(self, run: str | None = None) -> list[dict[str, Any]]:
        """Sources with seqs missing, from the stored seqs: {run, src, missing, highest}, where
        missing lists [first, last] ranges. A source that stopped early shows no gap: what it
        never sent cannot be told from what was lost after its last stored event."""
        return queries.gaps(self._conn, run)

    def record_wire(self, changes: Iterable[liveliness.LivelinessChange] = (),
                    misses: Iterable[liveliness.WireMiss] = ()) -> None:
        """Record what the ingest noticed on the wire (store/liveliness.py), in one transaction."""
        with self._transaction() as conn:
            liveliness.insert_changes(conn, changes)
            liveliness.insert_misses(conn, misses)

    def liveliness_changes(self, run: str, src: str | None = None) -> list[liveliness.LivelinessChange]:
        """The liveliness changes recorded for a run (or one of its sources), in the order noticed."""
        return liveliness.changes(self._conn, run, src)

    def lives(self, run: str) -> list[liveliness.SourceLife]:
        """Per source of the run whose token was seen: when it appeared and last disappeared."""
        return liveliness.lives(self._conn, run)

    def wire_misses(self, run: str | None = None) -> list[liveliness.WireMiss]:
        """Samples the ingest recorded as lost on the wire, beyond their publisher's cache."""
        return liveliness.misses(self._conn, run)

    def run_names(self) -> list[str]:
        """Every run with events, by name (one index probe per run)."""
        return queries.run_names(self._conn)

    def first_conflict(self, candidates: Iterable[Candidate]) -> tuple[str, str, int] | None:
        """(run, src, seq) of the first accepted candidate that the store already holds under its
        identity with other content (what an append would quarantine as a conflicting duplicate),
        or None: how an import tells another producer's run from its own (store/transfer/feed.py)."""
        for candidate in candidates:
            ev = candidate.event
            if ev is None or candidate.canonical is None:
                continue
            stored = self._heads.stored_event(ev["run"], ev["src"], ev["seq"])
            if stored is not None and stored != candidate.canonical:
                return (ev["run"], ev["src"], ev["seq"])
        return None

    def sources(self, run: str) -> list[str]:
        """The run's sources, by name (one index probe per source)."""
        return queries.sources(self._conn, run)

    def run_start(self, run: str) -> int | None:
        """When the run started (ns): its run.start event, else its first event; None for a run
        with no events. A few index probes (run.start comes only from the roles its schema
        allows), so it costs nothing on long runs: the reasoner asks it of every scene."""
        first = queries.first_t(self._conn, run)
        if first is None:
            return None
        started = queries.earliest_of_kind(self._conn, run, "run.start", SRC_ROLES["run.start"])
        return first if started is None else started

    def has_sequence_gaps(self, run: str) -> bool:
        """Whether any source of the run misses a seq, from one probe per source: each source
        holds at most highest seq + 1 events (seqs are distinct and start at 0), with equality
        exactly when it has no gap, so the run has none exactly when those bounds add up to its
        chain length. Lets the reasoner skip looking for missing evidence on a complete run."""
        bound = 0
        for src in self.sources(run):
            highest = queries.highest_seq(self._conn, run, src)
            if highest is None:  # one index lists the source, another holds none of its events
                raise EvidenceError(f"run {run} src {src}: the store's indexes disagree about this source's "
                                    "events: the file was damaged or altered; `gaps verify` says where")
            bound += highest + 1
        return bound != queries.chain_length(self._conn, run)

    def highest_seq(self, run: str, src: str) -> int | None:
        """The highest seq stored of one source, None if none (the append path's cached answer):
        where a restarted ingest asks the producers' caches to go on from."""
        highest = self._heads.highest_seq(run, src)
        return None if highest < 0 else highest

    def sequence_gaps(self, run: str, src: str) -> list[tuple[int, int]]:
        """The [first, last] seq ranges of one source that the store does not hold, below its
        highest stored seq: evidence that was sent and lost (two probes when there are none)."""
        return queries.missing_seqs(self._conn, run, src)

    def t_of(self, run: str, src: str, seq: int) -> int | None:
        """The t of one stored event, or None if it is not stored (an index probe)."""
        return None if seq < 0 else queries.t_of(self._conn, run, src, seq)

    def next_t(self, run: str, src: str, after: int, until: int) -> int | None:
        """The earliest t of the source's events in (after, until], or None: did it report
        again within a window (a source gone silent)?"""
        return queries.next_t(self._conn, run, src, after, until)

    def chain_positions(self, run: str, keys: Collection[tuple[str, int]]) -> dict[tuple[str, int], int]:
        """The chain position of each stored (src, seq) of the run; keys not stored are left out."""
        return queries.chain_positions(self._conn, run, keys)

    def verify(self, run: str | None = None, progress: Progress | None = None, keys: Any = None) -> VerifyReport:
        """Recompute the chains and checkpoints (and, for the whole store, the rulebook
        addresses); `progress(done, total)` is called now and then with events checked. Always
        recomputes; each run's result is then kept in the cache file for `verified`. Signed
        events are counted, and with `keys` (a TrustedKeys) their signatures checked
        (report.signatures)."""
        with self._reading(), tolerant_text(self._conn):
            report = verify_store(self._conn, run, progress, keys, self._integrity_once)
            if report.integrity and not report.integrity.ok:
                return report  # no run of a damaged file is recorded as verified
            keys = {r.run: verify_cache.chain_key(self._conn, r.run) for r in report.runs}
        for summary in report.runs:
            name = summary.run
            problem = report.problem if report.problem and report.problem.run == name else None
            if keys[name][0] and (summary.ok or problem is not None):
                counted = SignatureCount.from_json(SignatureTally.counted(summary.signed, summary.unsigned))
                verify_cache.record(self.cache, name, keys[name],
                                    VerifyReport(ok=summary.ok, runs=(summary,), problem=problem, signatures=counted,
                                                 integrity=report.integrity))
        return report

    def check_anchors(self, heads: Sequence[TreeHead] = (), public: bytes | None = None,
                      run: str | None = None, recorded: Sequence[TreeHead] = ()
                      ) -> tuple[list[HeadOutcome], KeyCheck | None]:
        """The store against what is kept outside it (store/anchors.py): each tree head of a witness
        (its signature too, with `public`), and with `public` the checkpoint key's signatures over
        every run checked, from where the key file's `recorded` first heads (store/trust_root.py)
        say its signing began; all read in one snapshot."""
        report = self.anchor_report(heads, public, run, recorded)
        return report.heads, report.key

    def anchor_report(self, heads: Sequence[TreeHead] = (), public: bytes | None = None,
                      run: str | None = None, recorded: Sequence[TreeHead] = (),
                      witness: bool | None = None) -> anchors.AnchorReport:
        """check_anchors, and per run what the witness and the key prove of its stored events
        (anchors.RunProof): what an investigator may rely on, and what nothing outside the file covers.
        `witness`: whether a witness was given (default: whether `heads` holds any), so that a run
        the witness has no head of is not proven by it."""
        witness = bool(heads) if witness is None else witness
        with self._reading(), tolerant_text(self._conn):
            outcomes = anchors.check_heads(self._conn, heads, public)
            keyed = None if public is None else anchors.check_checkpoint_key(self._conn, public, run, recorded)
            proofs = anchors.prove_runs(self._conn, run, heads, outcomes, keyed, witness) if witness or public else []
        return anchors.AnchorReport(outcomes, keyed, proofs)

    def _integrity_once(self, conn: sqlite3.Connection) -> list[str]:
        """SQLite's integrity check of the file (store/integrity.py), run once per state of the
        file this connection sees: an investigation that verifies run after run checks a whole
        file once. Another connection's commit changes data_version, this one's total_changes."""
        version = (self._read_data_version(), conn.total_changes)
        if self._integrity is None or self._integrity[0] != version:
            self._integrity = (version, integrity_problems(conn))
        return self._integrity[1]

    def verified(self, run: str, progress: Progress | None = None) -> VerifyReport:
        """The run's chain recomputed, once per chain head: the result kept in the cache file if
        the run's chain length and head hash are still those it was computed at, else `verify`.
        For explanations and reports that cite the verdict; `gaps verify` always recomputes."""
        key = verify_cache.chain_key(self._conn, run)
        if key[0]:
            kept = verify_cache.recorded(self.cache, run, key)
            if kept is not None:
                return kept
        return self.verify(run, progress)

    @contextmanager
    def _reading(self) -> Iterator[None]:
        """One read transaction, so that what is read together agrees (store/reading.py)."""
        with one_snapshot(self._conn):
            yield

    # --- rulebooks -----------------------------------------------------------------------------

    def put_rulebook(self, name: str, version: str, text: str) -> str:
        """Store a rulebook under the sha256 of its text and return that address. Storing the
        same text again changes nothing: the first name and version given stay."""
        with self._transaction() as conn:
            return rulebooks.put(conn, name, version, text)

    def get_rulebook(self, sha256: str) -> dict[str, Any] | None:
        """The rulebook stored at this address, or None. Refuses (ValueError) to return text
        that no longer hashes to its address: a run must be judged by the rules it names."""
        return rulebooks.by_hash(self._conn, sha256)

    def get_rulebook_by_name(self, name: str, version: str | None = None) -> dict[str, Any] | None:
        """The rulebook stored under this name and version, or, without a version, the newest
        version of the name (docs/store.md says how versions compare); None if there is none."""
        return rulebooks.by_name(self._conn, name, version)

    def rulebooks(self) -> list[dict[str, Any]]:
        """Every stored rulebook without its text: {sha256, name, version, stored_at, bytes}."""
        return rulebooks.listing(self._conn)



def _earliest_t(rows: list[tuple]) -> dict[str, int]:
    """The earliest t per run of event rows (run, chain_pos, src, seq, t, ...). A batch is nearly
    always of one run, found so by one pass in C over the run column; then the minimum is one
    more (a loop in Python cost the ingest's writer a quarter of a microsecond an event)."""
    runs = set(map(_RUN_OF, rows))
    if len(runs) == 1:
        return {runs.pop(): min(map(_T_OF, rows))}
    earliest: dict[str, int] = {}
    for row in rows:
        run, t = row[0], row[4]
        earliest[run] = min(t, earliest.get(run, t))
    return earliest


_RUN_OF, _T_OF = itemgetter(0), itemgetter(4)


def _parsed(rows: Iterator[tuple], run: str) -> Iterator[dict]:
    """The events of rows (src, seq, t, event JSON, ...), parsed a chunk at a time: one parse
    of a chunk is several times cheaper than one parse an event. Chunks start small and grow,
    so that a reader taking the first few events of a long stream parses little more than it
    takes."""
    size = 16
    while True:
        chunk = list(islice(rows, size))
        if not chunk:
            return
        yield from events_of(chunk, run)
        size = min(size * 2, 1024)
