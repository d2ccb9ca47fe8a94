"""The store's edge: every sqlite3 error that leaves the store becomes one of its own errors.

Only the store speaks SQLite. What SQLite says of the file or the disk (locked, read-only, full,
not a database, malformed) reaches the other rooms as a StoreFault (store/errors.py), named for
what the user must do, with SQLite's words as its message; so the ingest can tell a store that
cannot write now from a sample it cannot take, and the command line can say the file may be
damaged, without importing sqlite3. The Store's methods translate as they return or as what they
return is iterated (`translate_methods`); `translating()` is the net a caller puts around a whole
command, for the store's other functions (its caches, read through the reasoner).

The kind is read from SQLite's result code where the error carries one, else from its message,
else from the sqlite3 class: https://sqlite.org/rescode.html
"""
from __future__ import annotations

import functools
import sqlite3
from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any, Callable, TypeVar

from .errors import DiskFailed, DiskFull, RowRefused, StoreBusy, StoreDamaged, StoreFault, StoreReadOnly

Kind = type[StoreFault]

# SQLite's primary result codes (the low byte of an extended code): what each is, and, for those
# that describe the file or the disk rather than what was being written, that condition.
_BY_CODE: dict[int, tuple[Kind, str | None]] = {
    5: (StoreBusy, "the store is busy"), 6: (StoreBusy, "the store is locked"),
    7: (DiskFailed, "out of memory"), 8: (StoreReadOnly, "the store is read-only"),
    10: (DiskFailed, "disk I/O error"), 13: (DiskFull, "the disk is full"),
    14: (DiskFailed, "the store file cannot be opened"), 15: (DiskFailed, "the store's lock protocol failed"),
    11: (StoreDamaged, None), 26: (StoreDamaged, None),       # CORRUPT, NOTADB
    18: (RowRefused, None), 19: (RowRefused, None), 20: (RowRefused, None),  # TOOBIG, CONSTRAINT, MISMATCH
}
# The same read from SQLite's words, for an error that carries no code.
_BY_MESSAGE: dict[str, tuple[Kind, str | None]] = {
    "database or disk is full": (DiskFull, "the disk is full"), "disk i/o error": (DiskFailed, "disk I/O error"),
    "database is locked": (StoreBusy, "the store is locked"),
    "readonly database": (StoreReadOnly, "the store is read-only"),
    "unable to open database": (DiskFailed, "the store file cannot be opened"),
    "not a database": (StoreDamaged, None), "malformed": (StoreDamaged, None),
}
_BY_CLASS: tuple[tuple[type[sqlite3.Error], Kind], ...] = (
    (sqlite3.IntegrityError, RowRefused), (sqlite3.DataError, RowRefused))

T = TypeVar("T")
F = TypeVar("F", bound=Callable[..., Any])


def translated(exc: sqlite3.Error) -> StoreFault:
    """The store's error for SQLite's, with SQLite's message and result code. A condition is only
    ever one of an OperationalError: SQLite's class for what the file or disk did."""
    code = getattr(exc, "sqlite_errorcode", None)
    kind, condition = _kind(exc, code)
    fault = kind(str(exc), code=code, condition=condition if isinstance(exc, sqlite3.OperationalError) else None)
    fault.__cause__ = exc
    return fault


def _kind(exc: sqlite3.Error, code: int | None) -> tuple[Kind, str | None]:
    if code is not None:
        return _BY_CODE.get(code & 0xFF, (StoreFault, None))
    text = str(exc).lower()
    found = next((kind for words, kind in _BY_MESSAGE.items() if words in text), None)
    if found is not None:
        return found
    return next((kind for cls, kind in _BY_CLASS if isinstance(exc, cls)), StoreFault), None


def store_fault(exc: BaseException) -> StoreFault | None:
    """The store's error that ``exc`` is or stands for (an sqlite3 error, translated), or None
    for an error that is not the store file's."""
    if isinstance(exc, StoreFault):
        return exc
    return translated(exc) if isinstance(exc, sqlite3.Error) else None


@contextmanager
def translating() -> Iterator[None]:
    """Within the block, an sqlite3 error is raised as the store's own (StoreFault)."""
    try:
        yield
    except sqlite3.Error as exc:
        raise translated(exc) from exc


def translates(method: F) -> F:
    """The method with its sqlite3 errors translated, those met while iterating what it returns
    (a lazy stream of rows) too."""
    @functools.wraps(method)
    def call(*args: Any, **kwargs: Any) -> Any:
        try:
            result = method(*args, **kwargs)
        except sqlite3.Error as exc:
            raise translated(exc) from exc
        return _translated_items(result) if isinstance(result, Iterator) else result
    return call  # type: ignore[return-value]  # the wrapper keeps the signature (functools.wraps), which F cannot say


def _translated_items(items: Iterator[T]) -> Iterator[T]:
    try:
        yield from items
    except sqlite3.Error as exc:
        raise translated(exc) from exc


def translate_methods(cls: type[T]) -> type[T]:
    """The class with every public method (and its construction, its use as a context manager,
    its class methods) translating sqlite3 errors: its callers never see SQLite's."""
    for name, member in list(vars(cls).items()):
        if name.startswith("_") and name not in ("__init__", "__enter__", "__exit__"):
            continue
        if isinstance(member, classmethod):
            setattr(cls, name, classmethod(translates(member.__func__)))
        elif callable(member) and not isinstance(member, (type, staticmethod)):
            setattr(cls, name, translates(member))
    return cls
