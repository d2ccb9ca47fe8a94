"""History on the wire, the way Zenoh storages answer: a queryable on the ingest's key slice that
replies to `gaps/<run>/<src>/<kind>?_time=[t1..t2]` with the stored events, so that other Zenoh
tools, and `gaps fetch` on another machine, read what was recorded without access to the file.

Each reply is one stored event: its canonical JSON (the very bytes a publisher puts and the chain
hashes), encoding application/json, on the event's own key, with an attachment
`{"chain_pos": N, "hash": "<hex>"}` saying where it sits in this store's chain of its run (what
`gaps fetch` checks a copy against). Runs come in name order, each in chain order.

Nothing here may slow the ingest down. Zenoh's thread only puts the query in a bounded queue (a
full queue gets an immediate "busy" error reply, never a wait); worker threads of our own answer,
each from its own read-only connection, reading a chunk of events per short read transaction
(store/history.py), so the writer is never blocked and an answer of any length holds one chunk.
Replies travel with the query's congestion control (Zenoh 1.10 takes it from the query, and a
query's default is BLOCK; `gaps fetch` says BLOCK): a slow querier makes its worker wait, and
no event is dropped. Errors (a malformed selector, the limit reached, a stopping ingest) are error replies
whose payload is JSON: `{"error": CODE, "message": TEXT, ...}`.
"""
from __future__ import annotations

import json
import logging
import os
import queue
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass

import zenoh

from store import Store
from store.wire import HistoryRow

from .history_request import DEFAULT_LIMIT, HistoryRequest, HistoryRequestError, parse_request

log = logging.getLogger(__name__)

WORKERS = 2     # queries answered at once; the machine's disk is what a third would wait for
BACKLOG = 16    # queries waiting for a worker before more are refused as busy
JOIN_S = 5.0
_MATCH_CACHE = 100_000  # keys remembered as matching or not, per query


class HistoryQueryable:
    """The history queryable on `served_key`, answered from the store at `db_path`. Declared once
    the store exists (the ingest's writer created it); `close` then `join` when stopping."""

    def __init__(self, session: zenoh.Session, db_path: str | os.PathLike, served_key: str, *,
                 workers: int = WORKERS, backlog: int = BACKLOG) -> None:
        self._db = os.fspath(db_path)
        self._served = zenoh.KeyExpr(served_key)
        self._queue: queue.Queue[zenoh.Query | None] = queue.Queue(backlog)
        self._stopping = threading.Event()
        self._threads = [threading.Thread(target=self._work, name=f"gaps-history-{i}", daemon=True)
                         for i in range(workers)]
        for thread in self._threads:
            thread.start()
        # complete=False: an ingest holds what it received, not necessarily everything on its
        # slice; Zenoh then sends a default (BEST_MATCHING) query to every slice that matches.
        self._queryable = session.declare_queryable(served_key, self._enqueue, complete=False)

    def _enqueue(self, query: zenoh.Query) -> None:
        """On Zenoh's thread: hand the query over, or refuse it at once; never wait here."""
        if self._stopping.is_set():
            _finish(query, "stopping", "the ingest is stopping: ask another, or again once it is back")
            return
        try:
            self._queue.put_nowait(query)
        except queue.Full:
            _finish(query, "busy", f"{self._queue.maxsize} history queries are already waiting on this "
                                   "ingest: ask again shortly")

    def _work(self) -> None:
        """A worker: answer queries until told to stop, from a read-only connection of its own."""
        store: Store | None = None
        try:
            while (query := self._queue.get()) is not None:
                try:
                    store = store or Store.open_read_only(self._db)
                    self._answer(query, store)
                except zenoh.ZError as exc:     # the querier or the session went away mid-answer
                    log.debug("history: a reply could not be sent: %s", exc)
                except Exception as exc:  # noqa: BLE001 - a worker must outlive any one query
                    log.error("history: answering %s failed: %s", query.selector, exc)
                    _error(query, "failed", f"the ingest could not read its store: {exc}")
                finally:
                    query.drop()
        finally:
            if store is not None:
                store.close()

    def _answer(self, query: zenoh.Query, store: Store) -> None:
        try:
            # zenoh's stub says Parameters.__iter__ returns a list; it iterates (name, value) pairs
            request = parse_request(str(query.key_expr), query.parameters, time.time_ns())  # type: ignore[arg-type]
        except HistoryRequestError as exc:
            _error(query, "selector", str(exc))
            return
        matches = _Matcher(query.key_expr, self._served)
        sent, last = 0, None
        for row in _rows(store, request, matches):
            if self._stopping.is_set():
                _error(query, "stopping", f"the ingest stopped after {sent:,} replies", sent=sent,
                       next=_cursor(last))
                return
            if sent == request.limit:
                _error(query, "limit", f"{sent:,} replies sent, the limit of this query (_limit; "
                       f"{DEFAULT_LIMIT:,} when not given); more events match: ask again with "
                       f"_after={_cursor(last)}",
                       sent=sent, next=_cursor(last))
                return
            query.reply(row_key(row), row.event.encode(), encoding=zenoh.Encoding.APPLICATION_JSON,
                        attachment=attachment(row))
            sent, last = sent + 1, (row.run, row.chain_pos)
        log.debug("history: %s answered with %d events", query.selector, sent)

    def close(self) -> None:
        """Stop answering: undeclare, refuse what waits, let the workers finish their reply."""
        self._stopping.set()
        try:
            self._queryable.undeclare()
        except zenoh.ZError:
            pass
        while True:
            try:
                waiting = self._queue.get_nowait()
            except queue.Empty:
                break
            if waiting is not None:
                _finish(waiting, "stopping", "the ingest is stopping")
        for _ in self._threads:
            self._queue.put(None)

    def join(self, timeout: float = JOIN_S) -> None:
        """Wait for the workers (one blocked on a reply is freed when the session closes)."""
        for thread in self._threads:
            thread.join(timeout)


def _rows(store: Store, request: HistoryRequest, matches: _Matcher) -> Iterator[HistoryRow]:
    """The stored events the request selects, runs in name order, each in chain order."""
    wanted = request.filter_for()
    for run in store.run_names():
        if request.after is not None and run < request.after[0]:
            continue
        if not matches.run(run):
            continue
        after = request.after[1] if request.after is not None and run == request.after[0] else -1
        for row in store.history(run, wanted, after=after):
            if matches.key(row_key(row)):
                yield row


@dataclass
class _Matcher:
    """Does a key fall in both the query's key expression and the served slice? Zenoh's own rules,
    each distinct key asked once (a run has a few thousand (src, kind) keys, not millions)."""

    asked: zenoh.KeyExpr
    served: zenoh.KeyExpr

    def __post_init__(self) -> None:
        self._known: dict[str, bool] = {}

    def run(self, run: str) -> bool:
        try:
            keys = zenoh.KeyExpr(f"gaps/{run}/**")
        except zenoh.ZError:
            return False
        return self.asked.intersects(keys) and self.served.intersects(keys)

    def key(self, key: str) -> bool:
        found = self._known.get(key)
        if found is None:
            if len(self._known) >= _MATCH_CACHE:
                self._known.clear()
            concrete = zenoh.KeyExpr(key)
            found = self._known[key] = self.asked.intersects(concrete) and self.served.intersects(concrete)
        return found


def row_key(row: HistoryRow) -> str:
    """The key the event was published under (store.key_for, without parsing the event)."""
    return f"gaps/{row.run}/{row.src}/{row.kind}"


def attachment(row: HistoryRow) -> bytes:
    """Where the event sits in this store's chain of its run."""
    return json.dumps({"chain_pos": row.chain_pos, "hash": row.hash}, separators=(",", ":")).encode()


def _cursor(last: tuple[str, int] | None) -> str | None:
    return None if last is None else f"{last[0]}:{last[1]}"


def _error(query: zenoh.Query, code: str, message: str, **extra: object) -> None:
    """An error reply, JSON: {"error": code, "message": message, ...}."""
    payload = json.dumps({"error": code, "message": message, **extra}, ensure_ascii=False).encode()
    try:
        query.reply_err(payload, encoding=zenoh.Encoding.APPLICATION_JSON)
    except zenoh.ZError as exc:
        log.debug("history: an error reply could not be sent: %s", exc)


def _finish(query: zenoh.Query, code: str, message: str) -> None:
    """Refuse a query without answering it (on Zenoh's thread: one error reply, then done)."""
    _error(query, code, message)
    query.drop()
