"""`gaps fetch`: recorded events fetched over Zenoh from the ingests that hold them, into a local
store, with each run's chain checked against the sender's.

An investigator on another machine reaches the ingests through a router or one of them
(`--connect`), asks the history queryable (ingest/history_queryable.py) for a key expression and
a time window, and gets a store of their own that `gaps verify`, `gaps incidents` and the rest read
as if it had been recorded there. Every received event goes through the same screening as a live
sample (ingest/screen.py: the key must agree with the event) and into the store as an import
does; every run's links are checked as they arrive, and where a run came from its first event on,
this store's chain head is compared with the sender's (store.ReceivedChains).

The query goes to every queryable on the key (QueryTarget.ALL: every slice, each ingest that holds
any of it) without consolidation (Zenoh's default would keep one event per key). An answer cut at
its limit says where it stopped; the next page asks with `_after=` the least of those cursors, so
a slice that had finished may repeat some events, which the store counts as duplicates.

The report is typed: its refusals are the store's `Rejection`s, its chains `ReceivedChain`s
(store.wire), an answer's error an `AnswerError`; `to_json` is what `gaps fetch --json` prints.
"""
from __future__ import annotations

import json
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import zenoh

from store import Candidate, GapsError, Rejection, Store
from store.wire import SYNC_KEY, ReceivedChain, ReceivedChains, matched_within, session_config

from .errors import zenoh_message
from .history_request import DEFAULT_LIMIT
from .screen import screen
from .serve import check_key
from .time_range import format_time_range

BATCH = 5000          # events per store transaction
CHANNEL = 10_000      # replies Zenoh may hold for us before it waits (bounded memory)
MATCH_S = 5.0         # how long to wait for an ingest to be known before saying none answers
EXIT_OK, EXIT_INCOMPLETE, EXIT_NOTHING = 0, 1, 3


class NothingAnswers(GapsError):
    """No history queryable matches the key expression where we connected (exit 3: the set-up)."""

    exit_code = EXIT_NOTHING


@dataclass(frozen=True)
class FetchOptions:
    """What to fetch and where from: the endpoints are the wire contract's (store.session_config)."""

    key_expr: str
    connect: tuple[str, ...] = ()
    listen: tuple[str, ...] = ()
    mode: str | None = "client"
    config_file: Path | None = None
    t_from: int | None = None         # inclusive ns; None: open
    t_to: int | None = None
    timeout_s: float = 60.0           # what one page of answers may take
    page: int = DEFAULT_LIMIT         # replies asked per query (_limit)

    def selector_parameters(self, after: str | None) -> str:
        """The query's parameters: `_time` (when a bound is given), `_limit`, `_after`."""
        params = []
        if self.t_from is not None or self.t_to is not None:
            params.append(f"_time={format_time_range(self.t_from, self.t_to)}")
        params.append(f"_limit={self.page}")
        if after is not None:
            params.append(f"_after={after}")
        return ";".join(params)


@dataclass(frozen=True)
class AnswerError:
    """An answer that ended with an error reply other than its limit (a timeout, an ingest's
    refusal): the reply's fields as sent, in their order, for a sender may add its own."""

    fields: tuple[tuple[str, Any], ...]

    @classmethod
    def of(cls, said: dict[str, Any]) -> AnswerError:
        return cls(tuple(said.items()))

    @property
    def code(self) -> Any:
        """The reply's "error" (ours are words; a foreign sender's may be anything JSON holds)."""
        return dict(self.fields).get("error")

    @property
    def message(self) -> str:
        return str(dict(self.fields).get("message"))

    def to_json(self) -> dict[str, Any]:
        return dict(self.fields)


@dataclass
class FetchReport:
    """What a fetch did: events received and their outcome in the store, the answers' errors, the
    pages asked, and each run's chain against the sender's."""

    key_expr: str
    db: str
    received: int = 0
    stored: int = 0
    duplicates: int = 0
    rejected: int = 0
    details: list[Rejection] = field(default_factory=list)   # the first refusals
    errors: list[AnswerError] = field(default_factory=list)  # error replies other than "limit"
    pages: int = 0
    responders: set[str] = field(default_factory=set)
    chains: list[ReceivedChain] = field(default_factory=list)
    elapsed_s: float = 0.0

    @property
    def complete(self) -> bool:
        """Every answer ended of itself (no timeout, no error reply)."""
        return not self.errors

    @property
    def exit_code(self) -> int:
        """0: complete, every link held and every comparable chain matches; 1 otherwise."""
        broken = any(chain.broken for chain in self.chains)
        return EXIT_OK if self.complete and not broken else EXIT_INCOMPLETE

    def to_json(self) -> dict[str, Any]:
        """`gaps fetch --json`."""
        return {"key": self.key_expr, "db": self.db, "received": self.received, "stored": self.stored,
                "duplicates": self.duplicates, "rejected": self.rejected,
                "details": [refused.to_json() for refused in self.details],
                "complete": self.complete, "errors": [error.to_json() for error in self.errors], "pages": self.pages,
                "responders": len(self.responders), "chains": [chain.to_json() for chain in self.chains],
                "elapsed_s": round(self.elapsed_s, 3), "exit_code": self.exit_code}


def fetch(db: str | Path, options: FetchOptions, progress: Callable[[int], None] | None = None) -> FetchReport:
    """Fetch what `options` selects into the store at `db` (created if missing, and only once
    something answers); `progress` is told how many events arrived. NothingAnswers when nothing
    is reachable or no history queryable serves the key; a WireConfigError for a bad key,
    endpoint or config file."""
    check_key(options.key_expr)
    started = time.monotonic()
    session = _open(options)
    try:
        # asked of the ingests' sync key (every gaps serve declares it), not of the history key:
        # through a router, Zenoh 1.10 reports no match for a querier on gaps/** while the ingests'
        # queryables are on slices inside it (gaps/site-a/**), though the query reaches them
        if not matched_within(session.declare_querier(SYNC_KEY), min(MATCH_S, options.timeout_s), 0.02):
            raise NothingAnswers(_nobody(options))
        querier = session.declare_querier(options.key_expr, target=zenoh.QueryTarget.ALL,
                                          consolidation=zenoh.ConsolidationMode.NONE, timeout=options.timeout_s,
                                          congestion_control=zenoh.CongestionControl.BLOCK)
        with Store(db) as store:
            report = FetchReport(options.key_expr, store.path)
            chains = ReceivedChains()
            _pages(querier, options, store, report, chains, progress)
            report.chains = chains.results(store)
    finally:
        session.close()
    report.elapsed_s = time.monotonic() - started
    return report


def _pages(querier: zenoh.Querier, options: FetchOptions, store: Store, report: FetchReport,
           chains: ReceivedChains, progress: Callable[[int], None] | None) -> None:
    """Ask page after page until no answer is cut at its limit."""
    after: str | None = None
    while True:
        report.pages += 1
        replies = querier.get(zenoh.handlers.FifoChannel(CHANNEL), parameters=options.selector_parameters(after))
        cursors = _take(replies, store, report, chains, progress)
        if not cursors:
            return
        following = min(cursors, key=_cursor_order)
        if after is not None and _cursor_order(following) <= _cursor_order(after):
            moved = f"the answers did not move past {after}"
            report.errors.append(AnswerError.of({"error": "paging", "message": moved}))
            return
        after = following


def _open(options: FetchOptions) -> zenoh.Session:
    config = session_config(listen=options.listen, connect=options.connect, mode=options.mode,
                            config_file=options.config_file)
    try:
        return zenoh.open(config)
    except zenoh.ZError as exc:     # in client mode: no router or peer answered at any endpoint
        raise NothingAnswers(f"cannot reach {_where(options)}: {zenoh_message(exc)}") from None


def _where(options: FetchOptions) -> str:
    return ", ".join(options.connect) or "the configured endpoints"


def _nobody(options: FetchOptions) -> str:
    where = _where(options)
    return (f"nothing answers history queries on {options.key_expr} at {where}: no gaps serve is reachable "
            "there (is one running, and is that its endpoint or a router it is connected to?)")


def _take(replies: zenoh.handlers.Handler, store: Store, report: FetchReport, chains: ReceivedChains,
          progress: Callable[[int], None] | None) -> list[str]:
    """Store every event of one page of answers; return the cursors of answers cut at their limit."""
    cursors: list[str] = []
    batch: list[Candidate] = []
    for reply in replies:
        if reply.ok is None:
            problem = _error_of(reply.err)
            if problem.get("error") == "limit" and problem.get("next"):
                cursors.append(problem["next"])
            else:
                report.errors.append(AnswerError.of(problem))
            continue
        report.responders.add(str(reply.replier_id.zid))
        batch.append(_candidate(reply.ok, chains))
        if len(batch) >= BATCH:
            _append(store, batch, report, progress)
    _append(store, batch, report, progress)
    return cursors


def _candidate(sample: zenoh.Sample, chains: ReceivedChains) -> Candidate:
    """The sample screened as the ingest screens a live one; an accepted event is followed on the
    sender's chain as its attachment states it."""
    key, payload = str(sample.key_expr), sample.payload.to_bytes()
    screened = screen(key, payload, encoding=str(sample.encoding))
    candidate = screened.candidate
    link = _link_of(sample.attachment)
    event, canonical = candidate.event, candidate.canonical    # both read for an accepted event
    if candidate.reason is None and event is not None and canonical is not None and link is not None:
        chains.observe(event["run"], link[0], link[1], canonical)
    return candidate


def _link_of(attachment: zenoh.ZBytes | None) -> tuple[int, str] | None:
    """(chain position, hash) from a reply's attachment; None if it has none we can read."""
    if attachment is None:
        return None
    try:
        data = json.loads(attachment.to_bytes())
        pos, digest = data["chain_pos"], data["hash"]
    except (ValueError, TypeError, KeyError):
        return None
    if type(pos) is not int or pos < 0 or not isinstance(digest, str) or len(digest) != 64:
        return None
    try:
        bytes.fromhex(digest)
    except ValueError:
        return None
    return pos, digest


def _error_of(err: zenoh.ReplyError) -> dict[str, Any]:
    """An error reply as {"error", "message", ...}: ours are JSON; Zenoh's own (a timeout) text."""
    raw = err.payload.to_bytes()
    try:
        data = json.loads(raw)
        if isinstance(data, dict) and "error" in data:
            return data
    except ValueError:
        pass
    text = raw.decode("utf-8", "replace")
    return {"error": "timeout" if text == "Timeout" else "zenoh", "message": text}


def _append(store: Store, batch: list[Candidate], report: FetchReport, progress: Callable[[int], None] | None) -> None:
    if not batch:
        return
    done = store.append_candidates(batch)
    report.received += len(batch)
    report.stored += done.stored
    report.duplicates += done.duplicates
    report.rejected += len(done.rejected)
    report.details.extend(done.rejected[:max(0, 100 - len(report.details))])
    batch.clear()
    if progress is not None:
        progress(report.received)


def _cursor_order(cursor: str) -> tuple[str, int]:
    run, _, pos = cursor.rpartition(":")
    return run, int(pos) if pos.lstrip("-").isdigit() else -1
