"""`gaps import FILE` and `gaps export --run R -o FILE`: JSONL and MCAP in and out of the store."""
from __future__ import annotations

import sqlite3
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator, Optional

import typer

from cli.app import DbOption, JsonOption, app, db_path, fail, open_existing, print_json

FormatOption = typer.Option(None, "--format", help="jsonl or mcap (default: from the file's extension).")
SHOWN = 10            # rejections listed in text output; --json lists up to 100
PROGRESS_BYTES = 8 << 20
PROGRESS_EVENTS = 100_000


@contextmanager
def _progress(label: str, total: int, worth_showing: bool) -> Iterator[Callable[[int], None] | None]:
    """A rich progress bar on stderr, for big jobs on a terminal; None (no bar) otherwise."""
    from rich.console import Console
    console = Console(stderr=True)
    if not (worth_showing and console.is_terminal):
        yield None
        return
    from rich.progress import BarColumn, Progress, TaskProgressColumn, TextColumn, TimeRemainingColumn
    with Progress(TextColumn(label), BarColumn(), TaskProgressColumn(), TimeRemainingColumn(),
                  console=console, transient=True) as bar:
        task = bar.add_task(label, total=total)
        yield lambda done: bar.update(task, completed=done)


@app.command("import")
def import_(file: Path = typer.Argument(..., help="A .jsonl/.ndjson or .mcap file of events."),
            db: Optional[Path] = DbOption, json_out: bool = JsonOption, fmt: Optional[str] = FormatOption,
            fast: bool = typer.Option(False, "--fast", help=(
                "Bulk import with synchronous=NORMAL instead of FULL: faster, but a power loss may lose "
                "the last batches committed; repeat the import then (duplicates are ignored)."))) -> None:
    """Import events from JSONL or MCAP into the store (created if missing). Bad events are
    quarantined with their bytes and the reason; the rest is still imported (exit 0)."""
    from store import Store
    from store import TransferError, check_source, import_file
    try:
        path, fmt = check_source(file, fmt)
        with _progress(f"importing {path.name}", path.stat().st_size,
                       path.stat().st_size >= PROGRESS_BYTES) as progress:
            with Store(db_path(db), durable=not fast) as store:
                report = import_file(store, path, fmt, progress)
    except TransferError as exc:
        fail(str(exc))
    except (OSError, sqlite3.Error) as exc:
        fail(f"cannot import {file} into {db_path(db)}: {exc}")
    if json_out:
        print_json(report.as_dict())
    else:
        _print_import(report.as_dict(), db_path(db))


def _print_import(r: dict, db: Path) -> None:
    typer.echo(f"{r['file']} ({r['format']}) → {db}: stored {r['stored']}, duplicates {r['duplicates']}, "
               f"rejected {r['rejected']}, skipped {r['skipped']}")
    for skip in r["skips"]:
        typer.echo(f"  skipped {skip['count']} × {skip['what']}: {skip['reason']}")
    if r["rejected"]:
        typer.echo(f"  {r['rejected']} rejected, kept in the store's quarantine with their raw bytes and reasons "
                   f"(`gaps quarantine` lists them):")
        for item in r["details"][:SHOWN]:
            typer.echo(f"    {item['origin']}: {item['reason']}")
        if r["rejected"] > SHOWN:
            typer.echo(f"    … {r['rejected'] - SHOWN} more (--json lists the first {len(r['details'])})")
    for damage in r["damaged"]:
        typer.echo(f"  DAMAGED {damage['record']} at byte {damage['offset']} skipped: {damage['reason']}")
    if r["truncated"]:
        _print_cut(r["truncated"])
    for chain in r["chains"]:
        _print_chain(chain)


def _print_cut(cut: dict) -> None:
    typer.echo(f"  TRUNCATED at byte {cut['offset']} of {cut['file_size']}: {cut['reason']}.")
    if cut["data_complete"]:
        typer.echo("  Every message was read (the data section is complete); only the index and footer are missing.")
    else:
        typer.echo(f"  Imported what was intact before the cut: {cut['messages_read']} event messages read, "
                   f"{cut['stored']} stored; the last {cut['unreadable_bytes']} bytes could not be read.")


def _print_chain(c: dict) -> None:
    head = (c["exported_head"] or "?")[:16]
    if c["match"] is None:
        typer.echo(f"  run {c['run']}: exported in {c['order']} order; its chain head ({head}…) is "
                   f"not rebuilt by an import, the events are")
    elif c["match"]:
        typer.echo(f"  run {c['run']}: the chain matches the export ({c['file_events']} events, "
                   f"{c['checkpoints_matched']} of {c['checkpoints']} checkpoints, head {head}…)")
    else:
        typer.echo(f"  run {c['run']}: the chain does NOT match the export: {_chain_difference(c)}")


def _chain_difference(c: dict) -> str:
    if c["first_mismatch"]:
        m = c["first_mismatch"]
        return (f"after event {m['count']} of the file the exported head is {m['exported_head'][:16]}…, "
                f"the file's events give {m['file_head'][:16]}…")
    if c["file_events"] != c["exported_events"]:
        return (f"the file holds {c['file_events']} of the {c['exported_events']} events exported "
                f"({c['checkpoints_matched']} of {c['checkpoints']} checkpoints reached and matched)")
    if c["file_head"] != c["exported_head"]:
        return "the file's events do not hash to the exported head"
    return (f"the store's chain of this run has head {(c['store_head'] or 'none')[:16]}… "
            "(it held events of this run before, or refused some)")


@app.command()
def export(run: str = typer.Option(..., "--run", help="The run to export."),
           output: Path = typer.Option(..., "-o", "--output", help="The file to write (.jsonl, .ndjson or .mcap)."),
           db: Optional[Path] = DbOption, json_out: bool = JsonOption, fmt: Optional[str] = FormatOption,
           order: Optional[str] = typer.Option(None, "--order", help=(
               "chain (default): as appended, so that a re-import rebuilds the identical hash chain; "
               "time: (t, seq, src), which reads naturally but chains differently on re-import.")),
           no_scene: bool = typer.Option(False, "--no-scene", help=(
               "MCAP: leave out the Foxglove scene and log channels (a faster export, for moving "
               "events between stores rather than watching them)."))) -> None:
    """Write a run to JSONL or MCAP (with Foxglove scene and log channels and the chain checkpoints)."""
    from store import TransferError, export_run, format_of
    try:
        format_of(output, fmt)  # before opening the store: a wrong extension is the commonest mistake
        with open_existing(db) as store:
            with _progress(f"exporting {run}", store.count(run), store.count(run) >= PROGRESS_EVENTS) as progress:
                report = export_run(store, run, output, fmt, order, progress, scene=not no_scene)
    except TransferError as exc:
        fail(str(exc))
    except (OSError, sqlite3.Error) as exc:
        fail(f"cannot export run {run} to {output}: {exc}")
    if json_out:
        print_json(report.as_dict())
        return
    drawn = f" and {report.derived} Foxglove scene/log messages" if report.format == "mcap" else ""
    typer.echo(f"exported run {report.run}: {report.events} events{drawn} in {report.order} order "
               f"→ {report.file} ({report.bytes:,} bytes)")
