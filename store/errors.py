"""The one error hierarchy of the project.

Every error raised on purpose — a user's mistake, hostile or malformed input, an environment that
cannot run us — is a `GapsError`, so the command line turns each into one message and an exit
code and never a traceback, and a script can catch them all with one `except`. It lives in the
store because the store is the room every other room may import (DESIGN's table); each room
subclasses it for its own failures.
"""
from __future__ import annotations

from typing import Iterable


SHOWN = 20      # runs a message names; a fleet's store holds thousands


class GapsError(Exception):
    """Something went wrong that the user can act on; `exit_code` is what `gaps` exits with
    (2: the user's input; 1: evidence that does not verify; 3: the set-up)."""

    exit_code = 2


class StoreError(GapsError):
    """The store file cannot be used as asked (missing, not a store, a schema we cannot read)."""


class NoSuchRun(StoreError, LookupError):
    """A run id that is not in the store; the message lists the runs that are."""

    def __init__(self, run: str, known: Iterable[str]) -> None:
        self.run = run
        self.known = list(known)
        shown = ", ".join(self.known[:SHOWN]) or "none"
        more = len(self.known) - SHOWN
        super().__init__(f"no run {run!r}; runs: {shown}" + (f" and {more} more" if more > 0 else ""))


class EvidenceError(GapsError):
    """What the store file holds disagrees with its own hash chains: a read cannot go on without
    showing something the chains do not vouch for. Exit 1, as a failed `gaps verify`."""

    exit_code = 1


class IndexDisagrees(EvidenceError):
    """An index entry read in place of its row (the covering index by kind holds each sparse
    event's text a second time) is not the row the chain covers (store/index_guard.py)."""


class StoreFault(GapsError):
    """SQLite could not do what was asked of the store file: its condition, said as the store's
    own error (store/sqlite_errors.py translates every sqlite3 error where it leaves the store, so
    no other room knows SQLite). The message is SQLite's own words; the subclass says what the
    user must do. `condition` is the state of the file or disk that fails every write alike until
    it changes ("the disk is full"), None where the failure is the written row's own; `code` is
    SQLite's extended result code where it gave one. Exit 1: a read command that meets one says
    the file may be damaged and `gaps verify` says what and where (cli/app.py)."""

    exit_code = 1

    def __init__(self, message: str, *, code: int | None = None, condition: str | None = None) -> None:
        super().__init__(message)
        self.code = code
        self.condition = condition


class StoreDamaged(StoreFault):
    """The file is not a database, or its pages are malformed: run `gaps verify`, and read a copy
    kept from before."""


class StoreBusy(StoreFault):
    """Another connection holds the lock: wait for it (another writer, a long read) and try again."""


class StoreReadOnly(StoreFault):
    """The file, its folder or its medium cannot be written: give write permission, or write a copy."""


class DiskFull(StoreFault):
    """The disk (or the store's page limit) is full: free space, then try again."""


class DiskFailed(StoreFault):
    """The disk or the file system failed (an I/O error, a file that cannot be opened, memory):
    check the disk and the path."""


class RowRefused(StoreFault):
    """The store refused what was written, not the file's condition (an integrity constraint, a
    value too big): the written data's own fault, which writing again will not mend."""
