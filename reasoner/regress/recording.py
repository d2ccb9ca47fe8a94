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

A recording judged once is kept by its digest (store/kept_recording.py): the temporary store's
cache file, with the small part of the import a judged regression reads again, lives on in the
user's cache home, so regressing the same file again (another rulebook) reads none of its events:
on the hour, seconds where the import and first judgement take a quarter of an hour.
"""
from __future__ import annotations

import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator, TypeVar

from store import Store
from store.cache import kept_recording
from store.transfer import ImportReport, TransferError, check_source, import_file

from ..case_memo import code_version
from .books import RegressError

RECORDINGS = ("mcap", "jsonl")
T = TypeVar("T")
Judging = Callable[[Store, tuple[str, ...]], T]


def check_recording(path: str | Path) -> Path:
    """The recording's path, or a RegressError saying why it cannot be read as one."""
    try:
        found, fmt = check_source(path)
    except TransferError as exc:
        raise RegressError(str(exc)) from None
    if fmt not in RECORDINGS:
        raise RegressError(f"{path} is not a recording (.mcap or .jsonl)")
    return found


def judged_recording(path: str | Path, judging: Judging[T]) -> T:
    """`judging(store, problems)` of the recording's runs: from what was kept of it when a
    recording of the same digest was judged before by this code (store/kept_recording.py),
    else from its import into a temporary store, whose cache (and the small part of the import
    a later regression reads) is then kept. A kept recording asked anything it did not keep is
    put aside and the file imported, so what is kept makes a regression faster, never different."""
    path = check_recording(path)
    digest, version = kept_recording.recording_digest(path), code_version()
    kept = kept_recording.open_kept(digest, version)
    if kept is not None:
        with kept:
            try:
                out = judging(kept, _problems(path, kept.kept.rejected, kept.kept.cut))   # type: ignore[arg-type]
            except kept_recording.NotKept:
                pass
            if kept.missed is None:
                return out
    with recording_store(path, cache_at=kept_recording.cache_file(digest)) as (store, report):
        out = judging(store, _problems(path, report.rejected, report.truncated is not None))
        kept_recording.keep(store, digest, version, report.rejected, report.truncated is not None)
        return out


@contextmanager
def recording_store(path: str | Path, *, cache_at: str | None = None) -> Iterator[tuple[Store, ImportReport]]:
    """The recording imported into a temporary store (deleted after), and what its import
    found (events refused, a file cut short). `cache_at`: where the store's cache file is
    (else in the temporary folder, deleted with it)."""
    path = check_recording(path)
    with tempfile.TemporaryDirectory(prefix="gaps-regress-") as tmp:
        with Store(Path(tmp) / "recording.db", durable=False, cache_at=cache_at) as store:
            try:
                report = import_file(store, path)
            except TransferError as exc:
                raise RegressError(f"{path}: {exc}") from None
            yield store, report


def _problems(path: Path, rejected: int, cut: bool) -> tuple[str, ...]:
    """The import's problems, each naming the file as given this time."""
    out = []
    if rejected:
        out.append(f"{path}: {rejected} event(s) refused on import, not judged (`gaps import` says why)")
    if cut:
        out.append(f"{path}: the file is cut short; the events before the cut were judged")
    return tuple(out)
