"""`gaps migrate SRC DST`: a store of an older schema, copied to a new file at the current one.

Reading never migrates (a read must not change the evidence), so a store written by an older
version of gaps is brought up to date explicitly, into a copy: SRC is opened read-only and never
changed, DST must not exist, and DST appears only once it is complete (written under a
temporary name beside it, then renamed). The events, chains and checkpoints are copied page for
page, so every hash the old file verified still verifies in the copy.
"""

from __future__ import annotations

import os
import sqlite3
import tempfile
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from . import ddl, opening
from .errors import StoreError


@dataclass(frozen=True)
class MigrateReport:
    """What a migration wrote: from which file and schema version, to which."""

    src: str
    dst: str
    from_version: int
    to_version: int
    events: int

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


def migrate_copy(src: str | os.PathLike, dst: str | os.PathLike) -> MigrateReport:
    """Write a copy of the store at `src` migrated to the current schema at `dst`."""
    src, dst = os.fspath(src), os.fspath(dst)
    if os.path.lexists(dst):
        raise StoreError(f"{dst} already exists: gaps migrate writes a new file and never overwrites one")
    source = opening.connect_read_only(src, oldest=1)
    try:
        version = opening.check_schema(source, src, oldest=1)
        temp = _copy(source, dst)
    finally:
        source.close()
    try:
        try:
            events = _migrate(temp)
        except sqlite3.Error as exc:
            raise StoreError(f"cannot migrate {src}: {exc}") from None
        try:
            os.link(temp, dst)      # never replaces: a file that appeared meanwhile is left as it is
        except FileExistsError:
            raise StoreError(f"{dst} appeared while the copy was written: it was left as it is") from None
    finally:
        Path(temp).unlink(missing_ok=True)
    return MigrateReport(src, dst, version, ddl.SCHEMA_VERSION, events)


def _copy(source: sqlite3.Connection, dst: str) -> str:
    """SQLite's backup of the source into a new file beside dst; its name."""
    folder = os.path.dirname(os.path.abspath(dst))
    try:
        fd, temp = tempfile.mkstemp(prefix=f".{os.path.basename(dst)}.", suffix=".partial", dir=folder)
    except OSError as exc:
        raise StoreError(f"cannot write {dst}: {exc.strerror or exc}") from None
    os.close(fd)
    target = sqlite3.connect(temp, isolation_level=None)
    try:
        source.backup(target)
    except BaseException:
        target.close()
        Path(temp).unlink(missing_ok=True)
        raise
    target.close()
    return temp


def _migrate(path: str) -> int:
    """Bring the copy to the current schema, durably, and leave it in rollback-journal mode."""
    conn = sqlite3.connect(path, isolation_level=None)
    try:
        conn.execute("PRAGMA journal_mode=DELETE")
        conn.execute("PRAGMA synchronous=FULL")
        ddl.migrate(conn)
        return conn.execute("SELECT count(*) FROM events").fetchone()[0]
    finally:
        conn.close()
