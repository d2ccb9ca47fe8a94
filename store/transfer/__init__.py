"""Events in and out of the store as files: JSONL (one event per line) and MCAP.

    import_file(store, "run.mcap")                  # -> ImportReport
    export_run(store, "demo-001", "run.jsonl")      # -> ExportReport
    with Recorder("run.mcap") as rec: rec.add(event) # a producer's live recording (mcap_record.py)

The format comes from the extension (.jsonl, .ndjson, .mcap) unless given. A user's mistake (no
such file, an unknown format or run, a file that is not MCAP) raises TransferError; bad events
inside a file never do: they are quarantined and reported, and the rest is imported.
"""

from __future__ import annotations

from pathlib import Path
from typing import Callable

from ..db import Store
from ..sqlite_errors import translates
from .errors import TransferError
from .formats import FORMATS, format_of
from .jsonl import export_jsonl, import_jsonl
from .mcap_in import import_mcap
from .mcap_out import export_mcap
from .mcap_record import Recorder
from .chain_check import ChainResult, Mismatch
from .mcap_records import Cut, Damage
from .outcomes import ExportReport, ImportReport, Rejection, Skip, Truncation
from .rows import ORDERS, Order

DEFAULT_ORDER = {"jsonl": "chain", "mcap": "chain"}

__all__ = ["DEFAULT_ORDER", "FORMATS", "ORDERS", "ChainResult", "Cut", "Damage", "ExportReport", "ImportReport",
           "Mismatch", "Order", "Recorder", "Rejection", "Skip", "TransferError", "Truncation", "check_source",
           "export_run", "format_of", "import_file"]


def check_source(path: str | Path, fmt: str | None = None) -> tuple[Path, str]:
    """The file to import and its format, or a TransferError: callers check before they create
    a store, so that a mistyped file name does not leave an empty store behind."""
    path = Path(path)
    fmt = format_of(path, fmt)
    if not path.exists():
        raise TransferError(f"no such file: {path}")
    if not path.is_file():
        raise TransferError(f"{path} is not a file")
    return path, fmt


@translates            # the face speaks the store's errors, never sqlite3's (store/sqlite_errors.py)
def import_file(
    store: Store, path: str | Path, fmt: str | None = None, progress: Callable[[int], None] | None = None
) -> ImportReport:
    """Import every event in the file; `progress` is told how many bytes have been read."""
    path, fmt = check_source(path, fmt)
    report = ImportReport(str(path), fmt)
    (import_mcap if fmt == "mcap" else import_jsonl)(store, path, report, progress)
    return report


@translates
def export_run(
    store: Store,
    run: str,
    path: str | Path,
    fmt: str | None = None,
    order: str | None = None,
    progress: Callable[[int], None] | None = None,
    scene: bool = True,
) -> ExportReport:
    """Write one run to a file; `progress` is told how many events have been written; scene=False
    leaves out the Foxglove channels of an MCAP export.

    The default order is the chain's, for both formats: a re-import appends the events in the
    order they were first appended, so it rebuilds the identical chain heads the report cites
    (and, for MCAP, checks them against the checkpoints in the file; viewers order MCAP messages
    by log time themselves). order="time" writes (t, seq, src) order, which reads naturally but
    rebuilds another chain when events arrived out of time order.
    """
    path = Path(path)
    fmt = format_of(path, fmt)
    order = order or DEFAULT_ORDER[fmt]
    if order not in ORDERS:
        raise TransferError(f"unknown order {order!r}: use one of {', '.join(ORDERS)}")
    if fmt == "mcap":
        return export_mcap(store, run, path, order, progress, scene=scene)
    return export_jsonl(store, run, path, order, progress)
