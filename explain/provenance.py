"""Which tool wrote a report and from which store file: the version of mind-the-gaps and the
sha256 of the store file's bytes, printed on every page of the report.

A printed report travels without the store. The sha256 lets whoever holds a copy of the store
file check that it is the one the report was made from (`sha256sum gaps.db`); the version says
which code drew the conclusions. The hash is of the main file's bytes as read when the report is
started, before anything of the run is read; SQLite keeps the latest appends in a `-wal` file
beside the store until a checkpoint (when the last connection closes, at the latest), so the
record says when such a file held bytes that the hash does not cover. It says only whether, not
how many: the log's size changes with every write and would make two reports of one unchanged
run differ.
"""
from __future__ import annotations

import hashlib
import os
from dataclasses import dataclass
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path
from typing import Any

TOOL = "mind-the-gaps"
CHUNK = 1 << 20


@dataclass(frozen=True)
class Provenance:
    """The report's maker and source: tool name and version, the store file and its sha256."""

    tool: str
    version: str
    store_path: str
    store_sha256: str | None    # None for a store with no file (":memory:")
    store_bytes: int
    wal_pending: bool           # the store's -wal file held bytes when hashed: the hash does not cover them

    def to_json(self) -> dict[str, Any]:
        return {"tool": self.tool, "version": self.version,
                "store": {"path": self.store_path, "sha256": self.store_sha256, "bytes": self.store_bytes,
                          "wal_pending": self.wal_pending}}


def tool_version() -> str:
    """The installed version of mind-the-gaps ("unknown" when run from a tree never installed)."""
    try:
        return version(TOOL)
    except PackageNotFoundError:
        return "unknown"


def file_sha256(path: Path) -> tuple[str, int]:
    """The sha256 (hex) of a file's bytes and how many there were, read in chunks so a store of
    gigabytes is not held in memory."""
    digest, size = hashlib.sha256(), 0
    with open(path, "rb") as fh:
        while block := fh.read(CHUNK):
            digest.update(block)
            size += len(block)
    return digest.hexdigest(), size


def provenance(store_path: str | os.PathLike[str]) -> Provenance:
    """This tool's version and the store file's sha256, its absolute path and size (no sha256
    for an in-memory store: there are no bytes anyone else could hold)."""
    if os.fspath(store_path) in ("", ":memory:"):
        return Provenance(TOOL, tool_version(), ":memory:", None, 0, False)
    path = Path(store_path).resolve()
    sha, size = file_sha256(path)
    wal = path.with_name(path.name + "-wal")
    return Provenance(tool=TOOL, version=tool_version(), store_path=str(path), store_sha256=sha,
                      store_bytes=size, wal_pending=wal.is_file() and wal.stat().st_size > 0)
