"""`gaps fetch KEYEXPR --connect ENDPOINT`: recorded events over Zenoh from the ingests that hold
them into a local store. Argument parsing and printing only: the fetch is ingest.history_fetch's."""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Optional

import typer

from cli.app import db_path, fail, print_json
from cli.options import DbOption, JsonOption
from cli.progress import stderr_progress
from cli.safe_text import printable
from reasoner import format_seconds

if TYPE_CHECKING:                       # the command imports ingest when it runs, as before
    from ingest import FetchReport
    from store.wire import ReceivedChain

SHOWN = 10


def fetch(
    key: str = typer.Argument(..., metavar="KEYEXPR", help="What to fetch: gaps/RUN/** (one run), gaps/** "
                              "(everything the ingests hold), gaps/RUN/vehicle/173/** (one source), ..."),
    connect: list[str] = typer.Option([], "--connect", metavar="ENDPOINT", help="A Zenoh router or gaps serve "
                                      "to reach the ingests through, e.g. tcp/10.0.0.5:7447 (repeatable)."),
    mode: Optional[str] = typer.Option(None, "--mode", metavar="client|peer",
                                       help="Zenoh mode of this session (default: client, or the config file's)."),
    config: Optional[Path] = typer.Option(None, "--config", metavar="FILE", help="A Zenoh config file (JSON5); "
                                          "--connect/--mode given here override it."),
    t_from: Optional[str] = typer.Option(None, "--from", metavar="TIME", help="Only events at or after TIME: "
                                         "ISO 8601 with a zone, or ns since the epoch."),
    t_to: Optional[str] = typer.Option(None, "--to", metavar="TIME", help="Only events at or before TIME."),
    timeout: float = typer.Option(60.0, "--timeout", metavar="SECONDS", min=0.1,
                                  help="How long one page of answers (up to 100,000 events) may take."),
    db: Optional[Path] = DbOption,
    json_out: bool = JsonOption,
) -> None:
    """Fetch recorded events from the ingests over Zenoh into a local store (created if missing).

    Each run's chain is checked against the sender's: a run fetched from its first event on must
    end with the same chain head. Exit 0 when everything arrived and every chain matches; 1 when an
    answer was cut short (timeout, an ingest stopping) or a chain does not match; 2 for a mistake in
    the arguments; 3 when nothing answers history queries on the key. See docs/serve.md.
    """
    from ingest import FetchOptions, fetch as run
    from store import StoreFault, translating
    if not connect and config is None:
        fail("say where the ingests are: --connect tcp/HOST:PORT (a router or a gaps serve), or --config FILE")
    options = FetchOptions(key_expr=key, connect=tuple(connect),
                           mode=mode or ("client" if config is None else None), config_file=config,
                           t_from=_time("--from", t_from), t_to=_time("--to", t_to), timeout_s=timeout)
    path = db_path(db)
    try:
        with translating(), stderr_progress("fetching") as bar:
            report = run(path, options, None if bar is None else (lambda n: bar(n, None)))
    except (OSError, StoreFault) as exc:
        fail(f"cannot fetch into {path}: {exc}")
    if json_out:
        print_json(report.to_json())
    else:
        _print(report)
    raise typer.Exit(report.exit_code)


def _time(option: str, text: Optional[str]) -> Optional[int]:
    """A bound as ns; a time from the run start cannot be, since the run is not here yet."""
    if text is None:
        return None
    from reasoner import TimeError, parse_time
    try:
        return parse_time(text, None)
    except TimeError as exc:
        if "run start" in exc.problem:
            fail(f"{option} {text}: a time from the run start cannot be used before the run is fetched; "
                 "give ISO 8601 with a zone (2024-11-21T08:00:10Z) or ns since the epoch")
        fail(f"{option}: {exc}")


def _print(r: FetchReport) -> None:
    typer.echo(f"fetched {r.received:,} events on {printable(r.key_expr)} from {len(r.responders)} ingest(s) in "
               f"{r.pages} page(s), {format_seconds(round(r.elapsed_s, 3))} → {r.db}: stored {r.stored:,}, "
               f"duplicates {r.duplicates:,}, rejected {r.rejected:,}")
    for refused in r.details[:SHOWN]:
        typer.echo(f"  rejected {printable(refused.origin)}: {printable(refused.reason)}")
    for error in r.errors:
        typer.echo(f"  INCOMPLETE: an answer ended with {error.code}: {printable(error.message)}")
    for chain in r.chains:
        typer.echo("  " + _chain_line(chain))


def _chain_line(c: ReceivedChain) -> str:
    run, head = printable(c.run), (c.source_head or "?")[:16]
    if c.first_mismatch is not None:
        m = c.first_mismatch
        return (f"run {run}: BROKEN: the event at the sender's chain position {m.chain_pos} does not hash to "
                f"the hash sent with it ({m.stated_hash[:16]}…, recomputed {m.recomputed[:16]}…)")
    if c.match is None:
        return (f"run {run}: {c.received:,} events from the sender's chain positions {c.first_chain_pos}-"
                f"{c.last_chain_pos} (a window, not from the run's start): {c.links_checked:,} links checked, "
                "the chain heads are not comparable")
    if c.match:
        return (f"run {run}: the chain matches the sender's over its first {c.last_chain_pos + 1:,} events "
                f"(head {head}…)")
    return (f"run {run}: the chain does NOT match the sender's: this store has {c.store_events:,} events with "
            f"head {(c.store_head or 'none')[:16]}…, the sender {c.last_chain_pos + 1:,} with head {head}… "
            "(this store held other events of the run before, or refused some)")
