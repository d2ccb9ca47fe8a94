"""`gaps serve` (and `python -m ingest`): the ingest as a long-running service.

``Server`` is the ingest as every command runs it: the store's serve lock taken, then an
``IngestService`` on the options' endpoints and key; `gaps demo` and `gaps sim --db` use it in-process
too. ``serve`` adds what a service needs around it: SIGINT and SIGTERM ask it to stop, and it stops by
flushing everything already received into the store before it closes; a status reading every tick, as
a status line or JSON log lines (serve_output); systemd notifications; the final metrics. Its return
value is the exit code.
"""
from __future__ import annotations

import json
import logging
import os
import signal
import threading
from collections.abc import Callable
from dataclasses import dataclass
from datetime import datetime, timezone
from pathlib import Path
from types import FrameType, TracebackType
from typing import Any, TextIO

import zenoh

from store import QuarantineCap
from store.keys import CheckpointKey, TrustedKeys

from . import exposure
from .errors import IngestConfigError, zenoh_message
from .sd_notify import notify
from .serve_lock import ServeLock
from .serve_output import Reporter, ReporterHandler
from .serve_status import Status, StatusMeter
from .service import SUBSCRIPTION, IngestService

DEFAULT_LISTEN = "tcp/127.0.0.1:7447"
TERMINAL_TICK_S = 1.0
LOG_TICK_S = 10.0
EXIT_OK, EXIT_LOST = 0, 1
STOP_SIGNALS = (signal.SIGINT, signal.SIGTERM)


@dataclass(frozen=True)
class ServeOptions:
    """What `gaps serve` and `python -m ingest` take, the same for both."""

    db: Path
    listen: tuple[str, ...] = ()
    connect: tuple[str, ...] = ()
    mode: str | None = None              # None: the config file's, else peer
    config_file: Path | None = None
    key: str = SUBSCRIPTION
    status_every_s: float | None = None  # None: 1 s on a terminal, 10 s in logs
    durable: bool = True
    require_signatures: Path | None = None  # the public keys file: quarantine what they do not sign
    quarantine_cap: QuarantineCap = QuarantineCap()
    checkpoint_key: Path | None = None      # sign every checkpoint with this key (store/tree_heads.py)
    witness: Path | None = None             # append each signed tree head to this file
    publish_heads: bool = False             # put each signed tree head on gaps/@heads/<run>
    insecure: bool = False                  # --insecure-beyond-loopback: run open beyond loopback (logged)

    def endpoints(self) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """(listen, connect): with nothing said about the network, listen on DEFAULT_LISTEN."""
        if not (self.listen or self.connect or self.config_file):
            return (DEFAULT_LISTEN,), ()
        return self.listen, self.connect


class Server:
    """The serve lock and an IngestService, opened in that order and closed in the other.

    Closing stops receiving, stores everything received, closes the store, then releases the lock.
    Bad options, a busy port or a store in use are GapsErrors with a message saying which."""

    def __init__(self, options: ServeOptions) -> None:
        self.options = options
        self._lock = ServeLock(options.db)
        self._service: IngestService | None = None

    def __enter__(self) -> Server:
        check_key(self.options.key)
        keys = TrustedKeys.load(self.options.require_signatures) if self.options.require_signatures else None
        checkpoint_key = _checkpoint_key(self.options)
        self._lock.acquire()
        try:
            self._service = _open_service(self.options, keys, checkpoint_key)
        except BaseException:
            self._lock.release()
            raise
        return self

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        try:
            if self._service is not None:
                self._service.stop()
        finally:
            self._lock.release()

    @property
    def service(self) -> IngestService:
        """The service, from entering the server on."""
        if self._service is None:
            raise RuntimeError("the server is not open: use it in a `with` block")
        return self._service

    @property
    def lock_path(self) -> Path:
        return self._lock.path


def check_key(key: str) -> None:
    """The key must be a valid key expression that can match events (inside ``gaps/**``)."""
    try:
        expr = zenoh.KeyExpr(key)
    except zenoh.ZError as exc:
        raise IngestConfigError(f"--key {key!r} is not a Zenoh key expression: {zenoh_message(exc)}") from None
    if not expr.intersects(zenoh.KeyExpr(SUBSCRIPTION)):
        raise IngestConfigError(f"--key {key!r} matches no event key: events are published under "
                                "gaps/<run>/<src>/<kind> (e.g. gaps/** or gaps/site-a/**)")


def _checkpoint_key(options: ServeOptions) -> CheckpointKey | None:
    """The checkpoint key, loaded; --witness and --publish-heads need one (heads are signed)."""
    if options.checkpoint_key is None:
        if options.witness is not None or options.publish_heads:
            raise IngestConfigError("--witness and --publish-heads publish signed tree heads: give --checkpoint-key "
                                    "KEY too (gaps keys checkpoint KEY makes one)")
        return None
    return CheckpointKey.load(options.checkpoint_key)


def _open_service(options: ServeOptions, keys: TrustedKeys | None,
                  checkpoint_key: CheckpointKey | None = None) -> IngestService:
    """The IngestService, with Zenoh's refusal to open (a port in use, an address not ours) said plainly."""
    listen, connect = options.endpoints()
    try:
        return IngestService(options.db, listen=listen, connect=connect, mode=options.mode,
                             config_file=options.config_file, key_expr=options.key,
                             durable=options.durable, trusted_keys=keys, quarantine_cap=options.quarantine_cap,
                             checkpoint_key=checkpoint_key, witness=options.witness,
                             publish_heads=options.publish_heads, insecure=options.insecure)
    except zenoh.ZError as exc:
        where = ", ".join([*(f"listen {e}" for e in listen), *(f"connect {e}" for e in connect)]) or "the config file"
        raise IngestConfigError(f"cannot open Zenoh ({where}): {zenoh_message(exc)}") from None


Handler = Callable[[int, FrameType | None], Any] | int | signal.Handlers | None  # what signal.signal takes


class StopRequest:
    """SIGINT/SIGTERM handlers that ask the loop to stop instead of killing it mid-batch; the
    previous handlers come back on ``restore``. A repeated signal only says that the flush goes on."""

    def __init__(self, reporter: Reporter) -> None:
        self._event = threading.Event()
        self._reporter = reporter
        self.signal_name: str | None = None
        self._previous: dict[int, Handler] = {}

    def install(self) -> StopRequest:
        if threading.current_thread() is threading.main_thread():
            for sig in STOP_SIGNALS:
                self._previous[sig] = signal.signal(sig, self._handle)
        return self

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        name = signal.Signals(signum).name
        if self.signal_name is None:
            self.signal_name = name
            self._event.set()
        else:
            self._reporter.event("serve.signal", f"{name} again: still storing what was received; "
                                 "kill -9 would lose what is not yet committed", "warning", signal=name)

    def wait(self, timeout: float) -> bool:
        """Sleep until the next tick or a stop request; True if stopping was asked."""
        return self._event.wait(timeout)

    def restore(self) -> None:
        for sig, handler in self._previous.items():
            signal.signal(sig, handler)
        self._previous.clear()


def serve(options: ServeOptions, *, json_out: bool = False, out: TextIO, err: TextIO) -> int:
    """Run until SIGINT or SIGTERM, then flush, close and report; returns the exit code (0: stopped
    with every received sample stored, counted or quarantined; 1: some were lost, or the writer died).
    A GapsError (bad options, store in use, port busy) propagates before anything is received.
    Signals can only be caught on the main thread: called from another, it runs until the process ends."""
    reporter = Reporter.for_stream(err)
    stop = StopRequest(reporter).install()
    logger = logging.getLogger("ingest")
    handler, propagate, level = ReporterHandler(reporter), logger.propagate, logger.level
    logger.addHandler(handler)
    logger.propagate, logger.level = False, logging.INFO  # once, in the chosen format
    try:
        return _serve(options, reporter, stop, json_out, out)
    finally:
        stop.restore()
        logger.removeHandler(handler)
        logger.propagate, logger.level = propagate, level
        reporter.close()


def _serve(options: ServeOptions, reporter: Reporter, stop: StopRequest, json_out: bool, out: TextIO) -> int:
    started_at = _utc_now()
    with Server(options) as server:
        service = server.service
        meter = StatusMeter(service)
        _announce(options, server, reporter)
        tick = options.status_every_s or (TERMINAL_TICK_S if reporter.is_terminal else LOG_TICK_S)
        news = _News(reporter)
        stopped_by = None
        while not stop.wait(tick):
            status = meter.read()
            reporter.status(status)
            news.report(service.stats())
            notify(f"STATUS={status.line()}")
            if not service.writing:
                stopped_by = "the writer stopped"
                reporter.event("serve.failed", "the store writer stopped; shutting down", "error")
                break
        stopped_by = stopped_by or stop.signal_name
        at_stop = meter.read()
        notify("STOPPING=1")
        reporter.event("serve.stopping", f"{stopped_by}: storing what was received, then closing",
                       signal=stopped_by, in_flight=at_stop.in_flight)
    final = meter.read()
    news.report(service.stats())
    metrics = _metrics(options, server, started_at, stopped_by, at_stop, final, service)
    if not reporter.is_terminal:  # on a terminal the summary on stdout says it once
        reporter.event("serve.stopped", _summary(metrics), **metrics)
    reporter.close()
    out.write(json.dumps(metrics, indent=2) + "\n" if json_out else _summary(metrics) + "\n")
    out.flush()
    return metrics["exit_code"]


def _announce(options: ServeOptions, server: Server, reporter: Reporter) -> None:
    """The ready line (the subscription is declared and the store open: publishers may start), and
    READY=1 for systemd."""
    listen, connect = options.endpoints()
    where = "; ".join([*(f"listening on {e}" for e in listen), *(f"connected to {e}" for e in connect)])
    signed = f"; signatures required ({options.require_signatures})" if options.require_signatures else ""
    if options.checkpoint_key:
        signed += f"; checkpoints signed ({options.checkpoint_key})"
        signed += f", heads to {options.witness}" if options.witness else ""
        signed += ", heads on gaps/@heads/<run>" if options.publish_heads else ""
    reporter.event("serve.ready", f"Serving {options.db} ({where or 'endpoints of ' + str(options.config_file)}; "
                   f"key {options.key}{signed}); Ctrl-C or SIGTERM stops it after storing what was received",
                   db=str(options.db), lock=str(server.lock_path), listen=list(listen), connect=list(connect),
                   mode=options.mode or ("peer" if options.config_file is None else "from config"),
                   config=str(options.config_file) if options.config_file else None, key=options.key,
                   require_signatures=_keys_file(options), pid=os.getpid(),
                   checkpoint_key=str(options.checkpoint_key) if options.checkpoint_key else None,
                   witness=str(options.witness) if options.witness else None, publish_heads=options.publish_heads,
                   **server.service.exposure.to_json())
    lacks, found = server.service.insecure_because, server.service.exposure
    if lacks:
        reporter.event("serve.insecure", f"{exposure.INSECURE_FLAG}: this serve can be reached beyond loopback "
                       f"({'; '.join(found.reachable)}), and {'; and '.join(lacks)}",
                       "warning", beyond_loopback=list(found.reachable), lacks=lacks)
    notify(f"READY=1\nMAINPID={os.getpid()}")


class _News:
    """Refusals and writer errors since the last tick, reported once each tick (a hostile flood
    yields one line a tick with a count, not one per sample)."""

    SHOWN = 3

    def __init__(self, reporter: Reporter) -> None:
        self._reporter = reporter
        self._rejected = 0
        self._errors = 0
        self._stall: str | None = None

    def report(self, stats: dict) -> None:
        new = stats["rejected"] - self._rejected
        if new > 0:
            latest = stats["last_rejected"][-min(new, self.SHOWN):]
            why = "; ".join(f"{r['origin']}: {r['reason']}" for r in latest)
            self._reporter.event("serve.quarantined", f"quarantined {new:,} sample(s) (latest: {why[:300]})",
                                 "warning", count=new, latest=latest)
        errors = stats["errors"] - self._errors
        if errors > 0:
            self._reporter.event("serve.errors", f"{errors:,} writer error(s) (latest: {stats['last_errors'][-1]})",
                                 "error", count=errors, latest=stats["last_errors"][-min(errors, self.SHOWN):])
        self._rejected, self._errors = stats["rejected"], stats["errors"]
        self._report_stall(stats)

    def _report_stall(self, stats: dict) -> None:
        """A stall of the store (a full disk) said once as it begins and once as it ends."""
        if stats["stall"] and stats["stall"] != self._stall:
            self._reporter.event("serve.stalled", f"the store cannot write ({stats['stall']}): holding what was "
                                 "received, taking no more (publishers are held back), retrying", "error",
                                 reason=stats["stall"], stalled_for_s=round(stats["stalled_for_s"], 3),
                                 write_failures=stats["write_failures"])
        elif self._stall and not stats["stall"]:
            self._reporter.event("serve.resumed", f"the store writes again (stalled {stats['stalled_s']:.1f} s "
                                 "in all)", "warning", stalled_s=round(stats["stalled_s"], 3),
                                 write_failures=stats["write_failures"])
        self._stall = stats["stall"]


def _metrics(options: ServeOptions, server: Server, started_at: str, stopped_by: str | None,
             at_stop: Status, final: Status, service: IngestService) -> dict:
    """The final metrics (`--json`, and the serve.stopped log line)."""
    stats = service.stats()
    lost = final.failed > 0 or stopped_by == "the writer stopped" or final.received > final.settled
    listen, connect = options.endpoints()
    return {
        "db": str(options.db), "listen": list(listen), "connect": list(connect), "key": options.key,
        "pid": os.getpid(), "started_at": started_at, "stopped_at": _utc_now(), "stopped_by": stopped_by,
        "uptime_s": final.uptime_s, "received": final.received, "stored": final.stored,
        "duplicates": final.duplicates, "quarantined": final.quarantined, "failed": final.failed,
        "errors": final.errors, "write_failures": final.write_failures, "stalled_s": final.stalled_s,
        "quarantine_full": stats["quarantine_full"],
        "late": final.late, "recovered": stats["recovered"], "batches": stats["batches"],
        "require_signatures": _keys_file(options), "signature_refused": stats["signature_refused"],
        "settled_after_stop": final.settled - at_stop.settled,
        "events_per_s_mean": round(final.settled / final.uptime_s, 1) if final.uptime_s else 0.0,
        "lag_max_s": final.lag_max_s, "sources": final.sources, "missing": final.missing,
        "gaps": service.gaps(), "last_errors": stats["last_errors"], "last_rejected": stats["last_rejected"],
        "exit_code": EXIT_LOST if lost else EXIT_OK,
    }


def _keys_file(options: ServeOptions) -> str | None:
    return str(options.require_signatures) if options.require_signatures else None


def _summary(m: dict) -> str:
    """The final metrics in a sentence."""
    line = (f"Stopped ({m['stopped_by']}) after {m['uptime_s']:.1f} s: stored {m['stored']:,}, duplicates "
            f"{m['duplicates']:,}, quarantined {m['quarantined']:,}, failed {m['failed']:,}; "
            f"{m['missing']:,} seqs missing on the wire → {m['db']}")
    if m["quarantined"]:
        line += f"\n`gaps quarantine --db {m['db']}` shows what was refused and why."
    return line


def _utc_now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="milliseconds").replace("+00:00", "Z")
