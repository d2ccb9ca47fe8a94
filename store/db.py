"""The store: one SQLite file holding an append-only, hash-chained log of events per run.

Appends are the hot path (every event of every vehicle passes through here), so chain heads and
the highest stored seq of each source are cached in memory and rows are written with
executemany, one transaction per call. The caches are only ever a shortcut: they are filled
from the file on demand and thrown away whenever another connection may have written to it.
"""

from __future__ import annotations

import hashlib
import json
import os
import sqlite3
import time
from contextlib import contextmanager
from typing import Any, Callable, Collection, Iterable, Iterator

from . import ddl, queries
from .chain import GENESIS, link
from .intake import Candidate, from_dict, from_raw
from .reports import AppendReport, VerifyReport
from .verify import verify_store

_INSERT_EVENT = (
    "INSERT INTO events (run, chain_pos, src, seq, t, kind, event, hash) VALUES (?, ?, ?, ?, ?, ?, ?, ?)"
)
_INSERT_QUARANTINE = "INSERT INTO quarantine (received_at, origin, reason, raw) VALUES (?, ?, ?, ?)"
_INSERT_CHECKPOINT = "INSERT INTO checkpoints (run, count, head, created_at) VALUES (?, ?, ?, ?)"


AppendHook = Callable[[sqlite3.Connection, str, int], None]


class Store:
    """An event store file. Use one Store from one thread at a time (check_same_thread=False
    only lets it move between threads); separate processes may share a file safely.

    durable=False trades the last transactions on power loss (synchronous=NORMAL) for speed,
    for bulk imports that can be repeated.
    """

    def __init__(
        self, path: str | os.PathLike, *, durable: bool = True, check_same_thread: bool = True
    ) -> None:
        self.path = os.fspath(path)
        self._conn = sqlite3.connect(self.path, isolation_level=None, check_same_thread=check_same_thread)
        try:
            self._conn.execute("PRAGMA journal_mode=WAL")
            self._conn.execute(f"PRAGMA synchronous={'FULL' if durable else 'NORMAL'}")
            ddl.migrate(self._conn)
        except BaseException:
            self._conn.close()
            raise
        self._heads: dict[str, tuple[int, bytes]] = {}  # run -> (events in chain, head hash)
        self._max_seq: dict[tuple[str, str], int] = {}  # (run, src) -> highest stored seq, -1 if none
        self._data_version = self._read_data_version()
        self._append_hooks: list[AppendHook] = []

    # --- lifecycle -----------------------------------------------------------------------------

    def close(self) -> None:
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
        return self.append_candidates(from_dict(ev, str(origin)) for ev in events)

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
        report = AppendReport()
        rows: list[tuple] = []
        refused: list[tuple] = []
        received_at = time.time_ns()
        with self._transaction() as conn:
            placed: dict[tuple[str, str, int], bytes] = {}  # events placed in this batch
            for candidate in candidates:
                reason = candidate.reason
                if reason is None:
                    reason = self._place(candidate, placed, rows, report)
                if reason is not None:
                    refused.append((received_at, candidate.origin, reason, candidate.raw))
                    report.rejected.append({"origin": candidate.origin, "reason": reason})
            conn.executemany(_INSERT_EVENT, rows)
            conn.executemany(_INSERT_QUARANTINE, refused)
            conn.executemany(_INSERT_CHECKPOINT, self._checkpoint_rows(rows, received_at))
            self._run_hooks(conn, rows)
        report.stored = len(rows)
        return report


    def add_append_hook(self, hook: AppendHook) -> None:
        """Call `hook(conn, run, min_t)` inside every append transaction that stores events of
        `run`, with the earliest t among them: derived data (state snapshots) can drop what a
        late event makes stale, atomically with the append."""
        self._append_hooks.append(hook)

    def _run_hooks(self, conn: sqlite3.Connection, rows: list[tuple]) -> None:
        if not self._append_hooks or not rows:
            return
        earliest: dict[str, int] = {}
        for row in rows:
            run, t = row[0], row[4]
            earliest[run] = min(t, earliest.get(run, t))
        for hook in self._append_hooks:
            for run, min_t in earliest.items():
                hook(conn, run, min_t)

    def checkpoints(self, run: str) -> list[dict[str, Any]]:
        """The run's checkpoints, oldest first, as stored (count, head and whatever else)."""
        cur = self._conn.execute("SELECT * FROM checkpoints WHERE run = ? ORDER BY id", (run,))
        names = [d[0] for d in cur.description]
        return [dict(zip(names, row)) for row in cur]

    @property
    def connection(self) -> sqlite3.Connection:
        """The underlying connection, for the store's own modules (state folding, transfer)."""
        return self._conn

    def _place(
        self,
        candidate: Candidate,
        placed: dict[tuple[str, str, int], bytes],
        rows: list[tuple],
        report: AppendReport,
    ) -> str | None:
        """Chain a valid candidate onto its run, or count it as a duplicate; return a reason
        to refuse it if it conflicts with an event already stored under its (run, src, seq)."""
        ev, canonical = candidate.event, candidate.canonical
        run, src, seq = ev["run"], ev["src"], ev["seq"]
        key = (run, src, seq)
        earlier = placed.get(key)
        if earlier is None:
            earlier = self._stored_event(run, src, seq)
        if earlier is not None:
            if earlier != canonical:
                return f"conflicting duplicate of {run}/{src}/{seq}"
            report.duplicates += 1
            return None
        count, prev = self._head(run)
        digest = link(prev, canonical)
        rows.append((run, count, src, seq, ev["t"], ev["kind"], canonical.decode("utf-8"), digest.hex()))
        self._heads[run] = (count + 1, digest)
        self._max_seq[(run, src)] = max(self._max_seq[(run, src)], seq)
        placed[key] = canonical
        return None

    def _checkpoint_rows(self, rows: list[tuple], created_at: int) -> list[tuple]:
        """One checkpoint per run this call extended, at its new head."""
        runs = dict.fromkeys(row[0] for row in rows)
        return [(run, self._heads[run][0], self._heads[run][1].hex(), created_at) for run in runs]

    def _head(self, run: str) -> tuple[int, bytes]:
        cached = self._heads.get(run)
        if cached is not None:
            return cached
        row = self._conn.execute(
            "SELECT chain_pos, hash FROM events WHERE run = ? ORDER BY chain_pos DESC LIMIT 1", (run,)
        ).fetchone()
        head = (0, GENESIS) if row is None else (row[0] + 1, _digest(run, row[1]))
        self._heads[run] = head
        return head

    def _stored_event(self, run: str, src: str, seq: int) -> bytes | None:
        """Canonical bytes of the stored event with this identity, if any. Sources send seq in
        rising order, so knowing each source's highest seq answers "new" without a query."""
        highest = self._max_seq.get((run, src))
        if highest is None:
            (found,) = self._conn.execute(
                "SELECT max(seq) FROM events WHERE run = ? AND src = ?", (run, src)
            ).fetchone()
            highest = self._max_seq[(run, src)] = -1 if found is None else found
        if seq > highest:
            return None
        row = self._conn.execute(
            "SELECT event FROM events WHERE run = ? AND src = ? AND seq = ?", (run, src, seq)
        ).fetchone()
        return None if row is None else row[0].encode("utf-8")

    @contextmanager
    def _transaction(self) -> Iterator[sqlite3.Connection]:
        """BEGIN IMMEDIATE (take the write lock first, so the caches cannot go stale while we
        write); on any failure roll back and forget the caches, which may hold unwritten state."""
        self._conn.execute("BEGIN IMMEDIATE")
        try:
            self._refresh_caches()
            yield self._conn
            self._conn.execute("COMMIT")
        except BaseException:
            if self._conn.in_transaction:
                self._conn.execute("ROLLBACK")
            self._forget()
            raise

    def _refresh_caches(self) -> None:
        """Drop the caches if another connection has committed since we last looked."""
        version = self._read_data_version()
        if version != self._data_version:
            self._forget()
            self._data_version = version

    def _forget(self) -> None:
        self._heads.clear()
        self._max_seq.clear()

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
        """A run's events in (t, seq, src) order, streamed from the file; t_to is inclusive."""
        sql, params = queries.select_events(run, kinds, srcs, t_from, t_to)
        cursor = self._conn.execute(sql, params)
        return (json.loads(text) for (text,) in cursor)

    def runs(self) -> list[dict[str, Any]]:
        """{run, events, first_t, last_t, sources} for every run with events, by run name."""
        return [queries.run_summary(self._conn, run) for run in queries.run_names(self._conn)]

    def count(self, run: str | None = None) -> int:
        if run is None:
            return self._conn.execute("SELECT count(*) FROM events").fetchone()[0]
        return self._conn.execute("SELECT count(*) FROM events WHERE run = ?", (run,)).fetchone()[0]

    def quarantined(self) -> list[dict[str, Any]]:
        """Everything refused, oldest first, with the exact bytes received."""
        rows = self._conn.execute("SELECT id, received_at, origin, reason, raw FROM quarantine ORDER BY id")
        return [
            {"id": id_, "received_at": received_at, "origin": origin, "reason": reason, "raw": bytes(raw)}
            for id_, received_at, origin, reason, raw in rows
        ]

    def verify(self, run: str | None = None) -> VerifyReport:
        """Recompute the chains (and, for the whole store, the rulebook addresses)."""
        return verify_store(self._conn, run)

    # --- rulebooks -----------------------------------------------------------------------------

    def put_rulebook(self, name: str, version: str, text: str) -> str:
        """Store a rulebook under the sha256 of its text and return that address. Storing the
        same text again changes nothing: the first name and version given stay."""
        address = hashlib.sha256(text.encode("utf-8")).hexdigest()
        with self._transaction() as conn:
            conn.execute(
                "INSERT OR IGNORE INTO rulebooks (sha256, name, version, text) VALUES (?, ?, ?, ?)",
                (address, name, version, text),
            )
        return address

    def get_rulebook(self, sha256: str) -> dict[str, str] | None:
        """The rulebook stored at this address, or None. Refuses (ValueError) to return text
        that no longer hashes to its address: a run must be judged by the rules it names."""
        row = self._conn.execute(
            "SELECT sha256, name, version, text FROM rulebooks WHERE sha256 = ?", (sha256,)
        ).fetchone()
        if row is None:
            return None
        if hashlib.sha256(row[3].encode("utf-8")).hexdigest() != row[0]:
            raise ValueError(f"rulebook {sha256} does not match its text: the store was altered; run verify")
        return {"sha256": row[0], "name": row[1], "version": row[2], "text": row[3]}


def _digest(run: str, stored: str) -> bytes:
    """The stored head hash as bytes; a non-hex value means the file was altered."""
    try:
        return bytes.fromhex(stored)
    except (TypeError, ValueError):
        raise ValueError(
            f"the chain head of run {run} is not a sha256 hex digest: the store was altered; run verify"
        ) from None
