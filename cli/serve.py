"""`gaps serve`: the ingest service, Zenoh to the store. Argument parsing only: the service, its
signals, lock, status line and logs are ingest.serve's (so that `python -m ingest` is the same)."""
from __future__ import annotations

import sys
from pathlib import Path
from typing import Optional

import typer

from cli.app import db_path
from cli.options import DbOption, JsonOption


def serve(
    db: Optional[Path] = DbOption,
    listen: list[str] = typer.Option([], "--listen", metavar="ENDPOINT", help="Zenoh endpoint to listen on "
                                     "(repeatable; default tcp/127.0.0.1:7447 when neither --connect nor --config "
                                     "is given)."),
    connect: list[str] = typer.Option([], "--connect", metavar="ENDPOINT", help="Zenoh endpoint to connect to: "
                                      "a router or a publisher (repeatable)."),
    mode: Optional[str] = typer.Option(None, "--mode", metavar="peer|client|router",
                                       help="Zenoh mode (default: peer, or the config file's)."),
    config: Optional[Path] = typer.Option(None, "--config", metavar="FILE", help="A Zenoh config file (JSON5); "
                                          "--listen/--connect/--mode given here override it."),
    key: str = typer.Option("gaps/**", "--key", help="Key expression to receive."),
    status_every: Optional[float] = typer.Option(None, "--status-every", metavar="SECONDS", min=0.01,
                                                 help="Seconds between status readings (default: 1 on a terminal, "
                                                      "10 in the logs)."),
    require_signatures: Optional[Path] = typer.Option(
        None, "--require-signatures", metavar="KEYS", help="Quarantine every event not signed by a key the public "
        "keys file KEYS trusts for its source (unsigned, unknown key, forged)."),
    quarantine_rows: int = typer.Option(1_000_000, "--quarantine-rows", min=1, metavar="N", help="The most rows "
                                        "the quarantine keeps; past it (or --quarantine-bytes) refusals are counted, "
                                        "not kept."),
    quarantine_bytes: int = typer.Option(512 * 2**20, "--quarantine-bytes", min=1, metavar="BYTES",
                                         help="The most bytes of refused samples the quarantine keeps."),
    checkpoint_key: Optional[Path] = typer.Option(
        None, "--checkpoint-key", metavar="KEY", help="Sign every checkpoint with this checkpoint key (`gaps keys "
        "checkpoint`), and refuse to extend a run whose stored tail its last signed checkpoint does not vouch for."),
    witness: Optional[Path] = typer.Option(
        None, "--witness", metavar="FILE", help="Append each signed checkpoint's tree head to FILE (JSON lines, "
        "fsynced), for `gaps verify --against FILE`; needs --checkpoint-key."),
    publish_heads: bool = typer.Option(
        False, "--publish-heads", help="Put each signed tree head on the Zenoh key gaps/@heads/RUN; needs "
        "--checkpoint-key."),
    insecure: bool = typer.Option(
        False, "--insecure-beyond-loopback", help="Start even though the serve can be reached beyond loopback "
        "without --require-signatures or without Zenoh authentication in --config (logged as serve.insecure)."),
    json_out: bool = JsonOption,
) -> None:
    """Receive audit events over Zenoh and append them to the store until SIGINT or SIGTERM.

    A live status line on a terminal, JSON lines on stderr otherwise; on SIGINT or SIGTERM it stores
    everything received, closes the store and exits 0 (1 if a sample could be neither stored nor
    quarantined). A second serve on the same store is refused (exit 4). It also answers history
    queries on its key from the store (`gaps/RUN/**?_time=[t1..t2]`; `gaps fetch`). See docs/serve.md.
    """
    from ingest import ServeOptions, run_service as run
    from store import QuarantineCap
    options = ServeOptions(db=db_path(db), listen=tuple(listen), connect=tuple(connect), mode=mode,
                           config_file=config, key=key, status_every_s=status_every,
                           require_signatures=require_signatures,
                           quarantine_cap=QuarantineCap(rows=quarantine_rows, bytes=quarantine_bytes),
                           checkpoint_key=checkpoint_key, witness=witness, publish_heads=publish_heads,
                           insecure=insecure)
    raise typer.Exit(run(options, json_out=json_out, out=sys.stdout, err=sys.stderr))
