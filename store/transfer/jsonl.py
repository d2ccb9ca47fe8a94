"""JSONL in and out: one event per line, the envelope as canonical JSON.

Import streams the file line by line: a line is never longer in memory than the event limit
allows, except that an over-size line is kept whole for quarantine up to KEEP_BYTES (beyond that
its first KEEP_BYTES are kept, and the reason says how long it was and where it starts). Every
line that is not an event is quarantined by the store with its exact bytes and the reason, with
origin `FILE:LINE`; blank lines are counted as skipped.
"""

from __future__ import annotations

from pathlib import Path
from typing import BinaryIO, Callable, Iterator, NamedTuple

from ..db import Store
from ..envelope import MAX_EVENT_BYTES
from ..intake import Candidate, from_raw
from ..reading import one_snapshot
from .atomic import replacing
from .errors import TransferError
from .feed import feed
from .outcomes import ExportReport, ImportReport
from .rows import order_of, run_summary, stored_rows
from .whole_run import WholeRun

KEEP_BYTES = 16 * MAX_EVENT_BYTES  # how much of an over-size line quarantine keeps
_READ_LIMIT = MAX_EVENT_BYTES + 2  # the largest event, plus CR LF
_PIECE = 1 << 20  # how an over-size line is read on, piece by piece
_JSON_SPACE = b" \t\r"  # JSON's whitespace, besides the newline that ends the line
_BOM = b"\xef\xbb\xbf"

Progress = Callable[[int], None]  # told how many bytes (import) or events (export) are done


class Line(NamedTuple):
    number: int  # 1-based, as editors count
    offset: int  # byte offset of the line in the file
    data: bytes  # the line without its newline (only a prefix, if longer than KEEP_BYTES)
    length: int  # the full length without the newline


def read_lines(stream: BinaryIO) -> Iterator[Line]:
    """The file's lines; each is read with a bounded readline, so no line can exhaust memory."""
    number = offset = 0
    while chunk := stream.readline(_READ_LIMIT):
        number += 1
        consumed = len(chunk)
        if not chunk.endswith(b"\n") and len(chunk) == _READ_LIMIT:
            chunk, rest = _read_on(stream, chunk)
            consumed += rest
        data = chunk[:-1] if chunk.endswith(b"\n") else chunk
        length = consumed - (1 if chunk.endswith(b"\n") else 0)
        if number == 1 and data.startswith(_BOM):  # written by some Windows tools; not part of the event
            data, length = data[len(_BOM):], length - len(_BOM)
        yield Line(number, offset, data, length)
        offset += consumed


def _read_on(stream: BinaryIO, start: bytes) -> tuple[bytes, int]:
    """Finish an over-size line: keep up to KEEP_BYTES of it, count the rest; return what is kept
    (with its newline, if the line had one within the kept part) and how many more bytes were read."""
    kept, extra = bytearray(start), 0
    while piece := stream.readline(_PIECE):
        extra += len(piece)
        if len(kept) < KEEP_BYTES:
            kept += piece[: KEEP_BYTES - len(kept)]
        if piece.endswith(b"\n"):
            if len(kept) == KEEP_BYTES and not kept.endswith(b"\n"):
                kept += b"\n"  # marks the line as ended; stripped by the caller
            break
    return bytes(kept), extra


def candidates(lines: Iterator[Line], name: str, report: ImportReport) -> Iterator[Candidate]:
    """A store candidate per non-blank line, with origin `name:LINE`."""
    for line in lines:
        origin = f"{name}:{line.number}"
        if line.length > len(line.data):
            yield Candidate(origin, line.data, reason=_over_size(line))
        elif not line.data.strip(_JSON_SPACE):
            report.skip("blank lines", "a blank line holds no event")
        else:
            yield from_raw(line.data, origin)


def _over_size(line: Line) -> str:
    return (f"line is {line.length} bytes, over the {MAX_EVENT_BYTES}-byte event limit; quarantine keeps "
            f"its first {len(line.data)} bytes (the line starts at byte {line.offset} of the file)")


def import_jsonl(store: Store, path: Path, report: ImportReport, progress: Progress | None = None) -> None:
    """Import every line of a JSONL file into the store."""
    with _open(path) as stream:
        after = None if progress is None else (lambda: progress(stream.tell()))
        feed(store, candidates(read_lines(stream), str(path), report), report, after_batch=after)


def _open(path: Path) -> BinaryIO:
    try:
        return open(path, "rb")
    except OSError as exc:
        raise TransferError(f"cannot read {path}: {exc.strerror or exc}") from None


def export_jsonl(
    store: Store, run: str, path: Path, order: str = "time", progress: Progress | None = None
) -> ExportReport:
    """Write the run's events, one canonical JSON line each, in time or chain order."""
    run_summary(store, run)  # an unknown run is an error, not an empty file
    report = ExportReport(str(path), "jsonl", run, order_of(order))
    with one_snapshot(store.connection), replacing(path, [store.path]) as out:
        whole = WholeRun.of(store, run, order)
        for row in stored_rows(store, run, order):
            out.write(row.text.encode("utf-8"))
            out.write(b"\n")
            whole.see(row.text)
            report.events += 1
            if progress is not None and report.events % 10_000 == 0:
                progress(report.events)
        whole.check()  # before the file is put in place
        report.bytes = out.tell()
    if progress is not None:
        progress(report.events)
    return report
