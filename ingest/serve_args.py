"""`python -m ingest`: the command line of `gaps serve`, for a host that runs the ingest alone.

The ingest room may not import the `gaps` command (cli/), so its options are declared here a second
time, with argparse, onto the same ServeOptions and the same ``serve``; tests/ingest/test_serve_cli.py
checks that both take the same options. Messages and exit codes are the same as `gaps serve`'s.
"""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from store import GapsError, QuarantineCap

from .serve import DEFAULT_LISTEN, ServeOptions, serve
from .service import SUBSCRIPTION
from store.wire import MODES

USAGE_ERROR = 2


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(
        prog="python -m ingest",
        description="Receive audit events over Zenoh and append them to the store until SIGINT or SIGTERM "
                    "(the same service as `gaps serve`).")
    ap.add_argument("--db", type=Path, default=None, help="SQLite event store (default: $GAPS_DB or ./gaps.db).")
    ap.add_argument("--listen", action="append", default=[], metavar="ENDPOINT",
                    help=f"Zenoh endpoint to listen on (repeatable; default {DEFAULT_LISTEN} when neither "
                         "--connect nor --config is given).")
    ap.add_argument("--connect", action="append", default=[], metavar="ENDPOINT",
                    help="Zenoh endpoint to connect to: a router or a publisher (repeatable).")
    ap.add_argument("--mode", choices=MODES, default=None, help="Zenoh mode (default: peer, or the config file's).")
    ap.add_argument("--config", type=Path, default=None, metavar="FILE",
                    help="A Zenoh config file (JSON5); --listen/--connect/--mode given here override it.")
    ap.add_argument("--key", default=SUBSCRIPTION, help=f"Key expression to receive (default {SUBSCRIPTION}).")
    ap.add_argument("--status-every", type=float, default=None, metavar="SECONDS",
                    help="Seconds between status readings (default: 1 on a terminal, 10 in the logs).")
    ap.add_argument("--require-signatures", type=Path, default=None, metavar="KEYS",
                    help="Quarantine every event not signed by a key the public keys file KEYS trusts for its "
                         "source (unsigned, unknown key, forged).")
    ap.add_argument("--quarantine-rows", type=int, default=QuarantineCap.rows, metavar="N",
                    help="The most rows the quarantine keeps; past it (or --quarantine-bytes) refusals are counted, "
                         "not kept.")
    ap.add_argument("--quarantine-bytes", type=int, default=QuarantineCap.bytes, metavar="BYTES",
                    help="The most bytes of refused samples the quarantine keeps.")
    ap.add_argument("--checkpoint-key", type=Path, default=None, metavar="KEY",
                    help="Sign every checkpoint with this checkpoint key (`gaps keys checkpoint`), record each run's "
                         "first signed head in KEY.pub, and refuse to extend a run whose stored tail does not "
                         "extend its last signed head (from --witness, else KEY.pub).")
    ap.add_argument("--witness", type=Path, default=None, metavar="FILE",
                    help="Append each signed checkpoint's tree head to FILE (JSON lines, fsynced), for "
                         "`gaps verify --against FILE`; needs --checkpoint-key.")
    ap.add_argument("--publish-heads", action="store_true",
                    help="Put each signed tree head on the Zenoh key gaps/@heads/<run>; needs --checkpoint-key.")
    ap.add_argument("--insecure-beyond-loopback", action="store_true",
                    help="Start even though the serve can be reached beyond loopback without --require-signatures "
                         "or without Zenoh authentication in --config (logged as serve.insecure).")
    ap.add_argument("--json", action="store_true", help="Print the final metrics as JSON on exit.")
    return ap


def main(argv: list[str] | None = None) -> None:
    args = parser().parse_args(argv)
    if args.status_every is not None and not args.status_every > 0:
        _fail(f"--status-every must be a positive number of seconds, not {args.status_every:g}", USAGE_ERROR)
    if args.quarantine_rows < 1 or args.quarantine_bytes < 1:
        _fail("--quarantine-rows and --quarantine-bytes must be at least 1", USAGE_ERROR)
    options = ServeOptions(db=args.db or Path(os.environ.get("GAPS_DB") or "gaps.db"),
                           listen=tuple(args.listen), connect=tuple(args.connect), mode=args.mode,
                           config_file=args.config, key=args.key, status_every_s=args.status_every,
                           require_signatures=args.require_signatures,
                           quarantine_cap=QuarantineCap(rows=args.quarantine_rows, bytes=args.quarantine_bytes),
                           checkpoint_key=args.checkpoint_key, witness=args.witness,
                           publish_heads=args.publish_heads, insecure=args.insecure_beyond_loopback)
    try:
        code = serve(options, json_out=args.json, out=sys.stdout, err=sys.stderr)
    except GapsError as exc:
        _fail(str(exc), exc.exit_code)
    except KeyboardInterrupt:  # before the handlers were in place
        sys.exit(130)
    sys.exit(code)


def _fail(message: str, code: int) -> None:
    print(f"gaps: {message}", file=sys.stderr)
    sys.exit(code)
