"""`gaps import FILE` and `gaps export --run R -o FILE`: JSONL and MCAP in and out of the store.

FILE may be `-`: import reads standard input (with --format), export writes standard output
(JSONL unless --format mcap) and its summary goes to stderr, so the pipe carries only events.
"""
from __future__ import annotations

import json
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path
from typing import TYPE_CHECKING, Callable, Iterator, Optional

import typer

from cli.app import db_path, fail, open_existing, print_json, require_run, writable_output
from cli.options import DbOption, JsonOption, RunRequired, is_stdio
from cli.streams import stdin_file, stdout_file

if TYPE_CHECKING:           # annotations only: the store's transfer face loads when a command runs
    from store.transfer import ChainResult, ExportReport, ImportReport, Truncation

FormatOption = typer.Option(None, "--format", help="jsonl or mcap (default: from the file's extension).")
STDIN_FORMAT = "reading standard input needs --format jsonl or --format mcap"
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


def import_(file: Path = typer.Argument(..., help="A .jsonl/.ndjson or .mcap file of events; - for stdin."),
            db: Optional[Path] = DbOption, json_out: bool = JsonOption, fmt: Optional[str] = FormatOption,
            fast: bool = typer.Option(False, "--fast", help=(
                "Bulk import with synchronous=NORMAL instead of FULL: faster, but a power loss may lose "
                "the last batches committed; repeat the import then (duplicates are ignored).")),
            checkpoint_key: Optional[Path] = typer.Option(
                None, "--checkpoint-key", metavar="KEY", help="Sign every checkpoint written with this checkpoint "
                                                              "key (`gaps keys checkpoint`)."),
            witness: Optional[Path] = typer.Option(
                None, "--witness", metavar="FILE", help="Append each signed checkpoint's tree head to FILE (JSON "
                                                        "lines, fsynced), for `gaps verify --against`; needs "
                                                        "--checkpoint-key.")) -> None:
    """Import events from JSONL or MCAP into the store, creating it if missing.

    Bad events are quarantined with their bytes and the reason; the rest is still imported (exit 0).
    With --checkpoint-key the checkpoints are signed, each run's first signed head is recorded in
    KEY.pub, and a run whose stored tail does not extend its last signed head (from --witness, else
    KEY.pub) is refused, exit 1; --witness keeps their heads outside the store.
    """
    anchoring = _anchoring(checkpoint_key, witness)
    if is_stdio(file):
        if fmt is None:
            fail(STDIN_FORMAT)
        with stdin_file(f".{fmt.lower()}") as path:
            report = replace(_import(path, db, fmt, fast, anchoring), file="-")
    else:
        report = _import(file, db, fmt, fast, anchoring)
    if json_out:
        print_json(report.to_json())
    else:
        _print_import(report, db_path(db))


def _anchoring(checkpoint_key: Optional[Path], witness: Optional[Path]):
    """(the checkpoint key, the witness file's path), checked before anything is read."""
    from store.keys import CheckpointKey
    if witness is not None and checkpoint_key is None:
        fail("--witness keeps signed tree heads: give --checkpoint-key KEY too")
    return (CheckpointKey.load(checkpoint_key) if checkpoint_key else None), witness


def _import(file: Path, db: Optional[Path], fmt: Optional[str], fast: bool, anchoring=(None, None)) -> ImportReport:
    from store import Store, StoreFault, translating
    from store.keys import WitnessFile
    from store.transfer import TransferError, check_source, import_file
    key, witness_path = anchoring
    try:
        path, fmt = check_source(file, fmt)
        with _progress(f"importing {path.name}", path.stat().st_size,
                       path.stat().st_size >= PROGRESS_BYTES) as progress:
            witness = WitnessFile(witness_path) if witness_path else None  # checked as an output first
            try:
                with translating(), Store(db_path(db), durable=not fast, checkpoint_key=key,
                                          witness=witness_path) as store:
                    if witness is not None:
                        store.add_checkpoint_hook(witness.append)
                    return import_file(store, path, fmt, progress)
            finally:
                if witness is not None:
                    witness.close()
    except TransferError as exc:
        fail(str(exc))
    except (OSError, StoreFault) as exc:
        fail(f"cannot import {file} into {db_path(db)}: {exc}")


def _print_import(r: ImportReport, db: Path) -> None:
    typer.echo(f"{r.file} ({r.format}) → {db}: stored {r.stored}, duplicates {r.duplicates}, "
               f"rejected {r.rejected}, skipped {r.skipped}")
    for skip in r.skips.values():
        typer.echo(f"  skipped {skip.count} × {skip.what}: {skip.reason}")
    if r.rejected:
        typer.echo(f"  {r.rejected} rejected, kept in the store's quarantine with their raw bytes and reasons "
                   f"(`gaps quarantine` lists them):")
        for item in r.details[:SHOWN]:
            typer.echo(f"    {item.origin}: {item.reason}")
        if r.rejected > SHOWN:
            typer.echo(f"    … {r.rejected - SHOWN} more (--json lists the first {len(r.details)})")
    if r.quarantine_full:
        typer.echo(f"  QUARANTINE FULL: {r.quarantine_full} of the rejected were past the quarantine's cap: counted "
                   f"per origin, their bytes not kept (`gaps quarantine --prune` makes room)")
    for damage in r.damaged:
        typer.echo(f"  DAMAGED {damage.record} at byte {damage.offset} skipped: {damage.reason}")
    if r.truncated:
        _print_cut(r.truncated)
    for chain in r.chains:
        _print_chain(chain)


def _print_cut(t: Truncation) -> None:
    cut = t.cut
    typer.echo(f"  TRUNCATED at byte {cut.offset} of {cut.file_size}: {cut.reason}.")
    if cut.data_complete:
        typer.echo("  Every message was read (the data section is complete); only the index and footer are missing.")
    else:
        typer.echo(f"  Imported what was intact before the cut: {t.messages_read} event messages read, "
                   f"{t.stored} stored; the last {cut.unreadable_bytes} bytes could not be read.")


def _print_chain(c: ChainResult) -> None:
    head = (c.exported_head or "?")[:16]
    if c.match is None:
        typer.echo(f"  run {c.run}: exported in {c.order} order; its chain head ({head}…) is "
                   f"not rebuilt by an import, the events are")
    elif c.match:
        typer.echo(f"  run {c.run}: the chain matches the export ({c.file_events:,} events, "
                   f"{c.checkpoints_matched} of {c.checkpoints} checkpoints, head {head}…)")
    else:
        typer.echo(f"  run {c.run}: the chain does NOT match the export: {_chain_difference(c)}")


def _chain_difference(c: ChainResult) -> str:
    if c.first_mismatch:
        m = c.first_mismatch
        return (f"after event {m.count} of the file the exported head is {m.exported_head[:16]}…, "
                f"the file's events give {m.file_head[:16]}…")
    if c.file_events != c.exported_events:
        return (f"the file holds {c.file_events:,} of the {c.exported_events:,} events exported "
                f"({c.checkpoints_matched} of {c.checkpoints} checkpoints reached and matched)")
    if c.file_head != c.exported_head:
        return "the file's events do not hash to the exported head"
    return (f"the store's chain of this run has head {(c.store_head or 'none')[:16]}… "
            "(it held events of this run before, or refused some)")


def export(run: str = RunRequired,
           output: Path = typer.Option(..., "-o", "--output",
                                       help="The file to write (.jsonl, .ndjson or .mcap); - for stdout."),
           db: Optional[Path] = DbOption, json_out: bool = JsonOption, fmt: Optional[str] = FormatOption,
           order: Optional[str] = typer.Option(None, "--order", help=(
               "chain (default): a re-import appends the events as they were appended, rebuilding the "
               "identical hash chain (MCAP is written in log-time order, with the chain order beside it); "
               "time: (t, seq, src), which reads naturally but chains differently on re-import.")),
           no_scene: bool = typer.Option(False, "--no-scene", help=(
               "MCAP: leave out the Foxglove scene and log channels (a faster export, for moving "
               "events between stores rather than watching them)."))) -> None:
    """Write a run to JSONL or MCAP, with the chain checkpoints.

    MCAP also carries Foxglove scene and log channels for watching the run.
    """
    writable_output(output, db)         # before the store is opened: evidence is never an output
    if is_stdio(output):
        fmt = fmt or "jsonl"
        with stdout_file(f".{fmt.lower()}") as path:
            report = replace(_export(run, path, db, fmt, order, no_scene), file="-")
    else:
        report = _export(run, output, db, fmt, order, no_scene)
    say = is_stdio(output)    # the summary goes to stderr when stdout carries the events
    if json_out:
        typer.echo(json.dumps(report.to_json(), indent=2, ensure_ascii=False, default=str), err=say)
        return
    drawn = f" and {report.derived} Foxglove scene/log messages" if report.format == "mcap" else ""
    typer.echo(f"exported run {report.run}: {report.events:,} events{drawn} in {report.order} order "
               f"→ {report.file} ({report.bytes:,} bytes)", err=say)


def _export(run: str, output: Path, db: Optional[Path], fmt: Optional[str], order: Optional[str],
            no_scene: bool) -> ExportReport:
    from store import StoreFault, translating
    from store.transfer import TransferError, export_run, format_of
    try:
        format_of(output, fmt)  # before opening the store: a wrong extension is the commonest mistake
        with translating(), open_existing(db) as store:
            require_run(store, run)
            with _progress(f"exporting {run}", store.count(run), store.count(run) >= PROGRESS_EVENTS) as progress:
                return export_run(store, run, output, fmt, order, progress, scene=not no_scene)
    except TransferError as exc:
        fail(str(exc))
    except (OSError, StoreFault) as exc:
        fail(f"cannot export run {run} to {output}: {exc}")
