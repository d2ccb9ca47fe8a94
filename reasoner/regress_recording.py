"""Regression straight from recordings (`gaps regress FILES.mcap ...`), with nothing prepared.

A recording is imported into a temporary store of its own, with the store's own checks (a refused
event is counted, and said as a problem of the runs it held), then judged as a store's runs are.
That store is never the evidence: it lives in a temporary directory, is written without fsync
(durable=False), and is deleted when the recording's runs are judged; the recording stays the
record. Its chain is the file's own (the MCAP chain-order attachment puts the events back in the
order they were first appended), so the verdicts are those of `gaps import` then `gaps regress`.

Every event channel is read. The reasoner does not read every kind (vehicle.trace, ads.event,
collision, entity.despawn, run.end are never asked for), but those share their sources' sequence
numbers with kinds it does read: left out, they would show as gaps in each vehicle's sequence, and
a gap is a finding the verdicts take into account. On the golden run they are 2% of the events.
The derived Foxglove channels of an MCAP export are skipped (as `gaps import` skips them).
"""
from __future__ import annotations

import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator

from store import Store, TransferError, check_source, import_file

from .regress_books import RegressError

RECORDINGS = ("mcap", "jsonl")


def check_recording(path: str | Path) -> Path:
    """The recording's path, or a RegressError saying why it cannot be read as one."""
    try:
        found, fmt = check_source(path)
    except TransferError as exc:
        raise RegressError(str(exc)) from None
    if fmt not in RECORDINGS:
        raise RegressError(f"{path} is not a recording (.mcap or .jsonl)")
    return found


@contextmanager
def recording_store(path: str | Path) -> Iterator[tuple[Store, tuple[str, ...]]]:
    """The recording imported into a temporary store (deleted after), and the problems its
    import found (events refused, a file cut short), each naming the file."""
    path = check_recording(path)
    with tempfile.TemporaryDirectory(prefix="gaps-regress-") as tmp:
        with Store(Path(tmp) / "recording.db", durable=False) as store:
            try:
                report = import_file(store, path)
            except TransferError as exc:
                raise RegressError(f"{path}: {exc}") from None
            yield store, _problems(path, report.rejected, report.truncated is not None)


def _problems(path: Path, rejected: int, cut: bool) -> tuple[str, ...]:
    out = []
    if rejected:
        out.append(f"{path}: {rejected} event(s) refused on import, not judged (`gaps import` says why)")
    if cut:
        out.append(f"{path}: the file is cut short; the events before the cut were judged")
    return tuple(out)
