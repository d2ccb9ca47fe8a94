"""A recording regressed before, kept by its digest: the second regression of the same file reads
none of its events.

A fleet's logged runs do not change; its rulebooks do. Regressing a recording imports it into a
temporary store (reasoner/regress_recording.py), which on the hour's 455 MB file is most of a
quarter of an hour, and the store is deleted after. What a regression reads of that store once
every case is measured is small: the run names, each run's chain (length and head), its run.start
and its recorded potential violations; the measurements themselves are in the store's cache file,
keyed by that chain (store/derived_cache.py). So the temporary store's cache file is put here, in
the user's cache home under the recording's sha256, and with it one entry holding that small
part of the import: a later regression of a file with the same digest opens a KeptRecording in
place of a store and is judged from the cache alone.

Nothing here can change a verdict, only how long it takes:
- the file is named by the digest of its bytes, read in full each time (0.5 s on the hour), so
  an entry is only ever used for the very bytes it was made from;
- the entry is sealed like every cache entry (store/cache_seal.py) under the digest and the
  version of the code that judged it: an altered or moved entry does not open and the recording
  is imported again;
- a KeptRecording answers only what it kept; any other question raises NotKept and marks it
  missed, and the caller then imports the file and judges it as if nothing were kept.

The folder is bounded (GAPS_RECORDINGS_CACHE_MB, default 4096; 0 keeps nothing): past it, the
files used longest ago are deleted. The hour's is 187 MB.
"""
from __future__ import annotations

import hashlib
import heapq
import json
import os
import sqlite3
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Collection, Iterator

from ..sqlite_errors import translates
from .file import Cache
if TYPE_CHECKING:                       # annotations only: the store's faces load before db is done
    from ..db import Store
from ..wire.liveliness import LivelinessChange
from .verified import ChainKey

KEPT_KINDS = ("run.start", "monitor.potential_violation")
"""The kinds a regression reads of a run whose cases are all measured (run.start: its map and
start; the potential violations: its incidents)."""

BUDGET_ENV = "GAPS_RECORDINGS_CACHE_MB"
DEFAULT_BUDGET_MB = 4096
MAX_ENTRY = 64 << 20          # a recording whose kept part is larger is not kept
_TABLE, _KIND = "derived", "recording"
_SUFFIX = ".cache"


class NotKept(Exception):
    """A KeptRecording was asked what it did not keep: import the recording instead."""


def recording_digest(path: str | os.PathLike) -> str:
    """The sha256 of the file's bytes (hex): what names its kept part."""
    with open(path, "rb") as handle:
        return hashlib.file_digest(handle, "sha256").hexdigest()


def budget_bytes() -> int:
    """How much the kept recordings may take (GAPS_RECORDINGS_CACHE_MB; a value that is not a
    whole number of megabytes keeps the default)."""
    text = os.environ.get(BUDGET_ENV, "").strip()
    megabytes = int(text) if text.isdigit() else DEFAULT_BUDGET_MB
    return megabytes << 20


def folder() -> Path:
    """Where kept recordings live: the user's cache home, never beside the recording (a fleet's
    logs may sit on read-only or shared media, and a copy of a file elsewhere is the same file)."""
    home = os.environ.get("XDG_CACHE_HOME") or os.path.join(Path.home(), ".cache")
    return Path(home) / "mind-the-gaps" / "recordings"


def cache_file(digest: str) -> str | None:
    """The cache file for the recording of this digest, or None when nothing is to be kept."""
    return str(folder() / f"{digest}{_SUFFIX}") if budget_bytes() > 0 else None


@dataclass(frozen=True)
class KeptImport:
    """What the import of a recording found that a judged regression reads again."""

    runs: tuple[str, ...]
    chains: dict[str, ChainKey]
    events: dict[str, dict[str, list[dict[str, Any]]]]     # run -> kind -> events, in store order
    liveliness: dict[str, list[dict[str, Any]]]             # run -> LivelinessChange.to_json()s
    rejected: int
    cut: bool

    def text(self) -> str:
        return json.dumps({"runs": list(self.runs), "chains": {r: list(c) for r, c in self.chains.items()},
                           "events": self.events, "liveliness": self.liveliness, "rejected": self.rejected,
                           "cut": self.cut}, ensure_ascii=False, separators=(",", ":"))

    @classmethod
    def from_text(cls, text: str) -> KeptImport:
        data = json.loads(text)
        return cls(tuple(data["runs"]), {r: (int(n), str(h)) for r, (n, h) in data["chains"].items()},
                   data["events"], data["liveliness"], int(data["rejected"]), bool(data["cut"]))

    @classmethod
    def of(cls, store: Store, rejected: int, cut: bool) -> KeptImport:
        """What a judged regression reads again of the store a recording was imported into."""
        runs = tuple(store.run_names())
        return cls(runs, {run: store.chain_tip(run) for run in runs},
                   {run: {kind: list(store.events(run, kinds=[kind])) for kind in KEPT_KINDS} for run in runs},
                   {run: [change.to_json() for change in store.liveliness_changes(run)] for run in runs},
                   rejected, cut)


@translates             # like the rest of the store's faces: sqlite3's errors leave as StoreFault
def keep(store: Store, digest: str, version: str, rejected: int, cut: bool) -> bool:
    """After the recording imported into `store` was judged (its cache file is cache_file(digest)):
    keep its small part, sealed, then trim the folder. False when nothing was kept (the cache is
    in memory, locked, or the part is too large)."""
    if store.cache.path != cache_file(digest):
        return False
    text = KeptImport.of(store, rejected, cut).text()
    if len(text) > MAX_ENTRY:
        return False
    cache = store.cache.connection
    names = _names(digest, version)
    try:
        cache.execute("DELETE FROM derived WHERE run = '' AND kind = ? AND version <> ?", (_KIND, version))
        cache.execute("INSERT OR REPLACE INTO derived (run, kind, version, chain_len, head, key, payload, mac) "
                      "VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                      ("", _KIND, version, 0, digest, digest, text, store.cache.sealer.seal(_TABLE, names, text)))
    except sqlite3.Error as exc:
        store.cache.failed_to_write(exc)
        return False
    trim(keep_path=store.cache.path)
    return True


@translates
def open_kept(digest: str, version: str) -> KeptRecording | None:
    """The recording of this digest as kept by this version of the code, or None (never kept,
    kept by other code, or its seal does not open)."""
    path = cache_file(digest)
    if path is None or not os.path.isfile(path):
        return None
    cache = Cache(path, at=path)
    try:
        row = cache.connection.execute(
            "SELECT payload, mac FROM derived WHERE run = '' AND kind = ? AND version = ? AND chain_len = 0 "
            "AND head = ? AND key = ?", (_KIND, version, digest, digest)).fetchone()
    except sqlite3.Error:
        row = None
    if row is None or not cache.sealer.opens(_TABLE, _names(digest, version), row[0], row[1]):
        cache.close()
        return None
    _touch(path)
    return KeptRecording(cache, KeptImport.from_text(row[0]))


class KeptRecording:
    """A recording's kept part, read as a read-only Store is by a regression whose every case is
    kept. Anything else it is asked raises NotKept and sets `missed`."""

    def __init__(self, cache: Cache, kept: KeptImport) -> None:
        self.cache = cache
        self.kept = kept
        self.missed: str | None = None

    def run_names(self) -> list[str]:
        return list(self.kept.runs)

    def chain_tip(self, run: str) -> ChainKey:
        if run not in self.kept.chains:
            return self._not_kept(f"the chain of run {run!r}")
        return self.kept.chains[run]

    def events(self, run: str, *, kinds: Collection[str] | None = None, srcs: Collection[str] | None = None,
               t_from: int | None = None, t_to: int | None = None) -> Iterator[dict]:
        """The kept kinds of a run, whole, in (t, seq, src) order as the store gives them."""
        if kinds is None or isinstance(kinds, str) or srcs is not None or t_from is not None or t_to is not None \
                or not set(kinds) <= set(KEPT_KINDS) or run not in self.kept.events:
            return self._not_kept(f"events of run {run!r} (kinds {kinds!r}, srcs {srcs!r}, t {t_from!r}..{t_to!r})")
        streams = [iter(self.kept.events[run][kind]) for kind in sorted(set(kinds))]
        return heapq.merge(*streams, key=lambda e: (e["t"], e["seq"], e["src"]))

    def liveliness_changes(self, run: str, src: str | None = None) -> list[LivelinessChange]:
        if run not in self.kept.liveliness:
            return self._not_kept(f"the liveliness of run {run!r}")
        return [LivelinessChange(**change) for change in self.kept.liveliness[run]
                if src is None or change["src"] == src]

    def close(self) -> None:
        self.cache.close()

    def __enter__(self) -> KeptRecording:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def __getattr__(self, name: str) -> Any:
        if name.startswith("__"):
            raise AttributeError(name)
        return self._not_kept(f"Store.{name}")

    def _not_kept(self, what: str) -> Any:
        self.missed = self.missed or what
        raise NotKept(what)


def trim(keep_path: str | None = None) -> list[str]:
    """Delete the kept recordings used longest ago until the folder fits its budget (never
    `keep_path`, the one just kept); the paths deleted."""
    try:
        files = [(entry.stat().st_mtime, entry.stat().st_size, entry.path) for entry in os.scandir(folder())
                 if entry.name.endswith(_SUFFIX) and entry.is_file()]
    except OSError:
        return []
    total, budget, gone = sum(size for _, size, _ in files), budget_bytes(), []
    for _, size, path in sorted(files):
        if total <= budget:
            break
        if keep_path is not None and os.path.abspath(path) == os.path.abspath(keep_path):
            continue
        try:
            os.unlink(path)
        except OSError:
            continue
        total -= size
        gone.append(path)
    return gone


def _touch(path: str) -> None:
    try:
        os.utime(path)
    except OSError:
        pass


def _names(digest: str, version: str) -> tuple:
    """What the entry's seal covers besides its payload: the derived table's names of it."""
    return ("", _KIND, version, 0, digest, digest)
