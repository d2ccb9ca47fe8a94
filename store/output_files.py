"""Every file a command writes, opened here: evidence is never an output.

An export, a report, a picture, a JUnit file, a recording, a truth file or a public key file is
written by one of the functions below, which refuse (OutputRefused, exit 2, naming the path and
why) a path that is, or resolves to (symlinks followed; hard links by device and inode), an
event store this process opened or was told of, or one of its companions (its -wal, -shm and
-journal, its cache file, its serve lock); any existing SQLite database (an output is never a
store: `gaps migrate` makes new stores, and only as a new file); or anything that is not a
regular file (a device, a fifo, a folder). A regular file is replaced atomically: the bytes go to
a temporary file beside it, renamed over it once complete, so a failed write leaves the old file
and a device is never renamed over. `-` (standard output) is the command line's to handle.

It lives in the store because the store is where evidence is known (DESIGN: store/ imports
nothing of ours, every room may import it), and the exports written by store/transfer use it.
"""
from __future__ import annotations

import os
import stat
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import BinaryIO, Iterable, Iterator

from .errors import GapsError

SQLITE_HEADER = b"SQLite format 3\x00"
_COMPANIONS = (("-wal", "write-ahead log"), ("-shm", "shared-memory index"), ("-journal", "rollback journal"),
               (".cache", "cache file"), (".cache-journal", "cache file's journal"),
               (".cache-wal", "cache file's write-ahead log"), (".serve.lock", "serve lock file"))
_opened: dict[str, str] = {}    # realpath -> what it is, for every store and cache file this process opened

Protected = Iterable["str | os.PathLike[str]"]


class OutputRefused(GapsError):
    """An output path that would write over evidence, or over something that is not a regular file."""


def note_evidence(path: str | os.PathLike[str], what: str = "event store") -> None:
    """Remember a file this process opened as evidence (Store, Cache call it): no output may be it,
    even after it is closed (`gaps regress --junit` writes once the store is closed)."""
    name = os.fspath(path)
    if name and name != ":memory:" and not name.startswith("file:"):
        _opened.setdefault(os.path.realpath(name), what)


def _guarded(stores: Protected) -> dict[str, str]:
    """realpath -> what, for the stores given and every one opened, with their companions."""
    found: dict[str, str] = {}
    bases = [(os.fspath(s), "event store") for s in stores] + list(_opened.items())
    for base, what in bases:
        found.setdefault(os.path.realpath(base), what)
        if what == "event store":
            for suffix, role in _COMPANIONS:
                found.setdefault(os.path.realpath(base + suffix), f"event store's {role}")
    return found


def check_output(path: str | os.PathLike[str], stores: Protected = ()) -> Path:
    """The real path an output to `path` would write, after refusing one that resolves to evidence
    or to something other than a regular file (OutputRefused, saying which and why)."""
    given = os.fspath(path)
    real = os.path.realpath(given)
    guarded = _guarded(stores)
    what = guarded.get(real)
    if what is not None:
        raise OutputRefused(f"refusing to write {given}: it {_is(given, real)} the {what} {real}; "
                            "evidence is never an output, choose another file")
    try:
        st = os.stat(real)
    except FileNotFoundError:
        if not os.path.isdir(os.path.dirname(real) or "."):
            raise OutputRefused(f"cannot write {given}: no such folder {os.path.dirname(real)}") from None
        return Path(real)
    except OSError as exc:
        raise OutputRefused(f"cannot write {given}: {exc.strerror or exc}") from None
    if not stat.S_ISREG(st.st_mode):
        raise OutputRefused(f"refusing to write {given}: it {_is(given, real)} {_kind(st.st_mode)} ({real}), not a "
                            "regular file; an output only ever replaces a regular file")
    for other, other_what in guarded.items():
        try:
            if os.path.samestat(st, os.stat(other)):
                raise OutputRefused(f"refusing to write {given}: it is a hard link to the {other_what} {other}; "
                                    "evidence is never an output, choose another file")
        except FileNotFoundError:
            continue
    if _is_sqlite(real):
        raise OutputRefused(f"refusing to write {given}: it {_is(given, real)} an SQLite database ({real}: an event "
                            "store or its cache?); an output never replaces one, choose another file")
    return Path(real)


@contextmanager
def replacing(path: str | os.PathLike[str], stores: Protected = ()) -> Iterator[BinaryIO]:
    """A binary file that becomes `path` (its real path) when the block ends without an exception,
    after check_output; checked again just before the rename, which is atomic."""
    target = check_output(path, stores)
    try:
        fd, temp = tempfile.mkstemp(prefix=f".{target.name}.", suffix=".partial", dir=target.parent)
    except OSError as exc:
        raise OutputRefused(f"cannot write {os.fspath(path)}: {exc.strerror or exc}") from None
    try:
        with os.fdopen(fd, "wb") as out:
            yield out
            out.flush()
            os.fsync(out.fileno())
        os.chmod(temp, 0o666 & ~_umask())      # mkstemp's 0600 would hide the file from its readers
        if check_output(path, stores) != target:
            raise OutputRefused(f"refusing to write {os.fspath(path)}: it changed while it was written")
        os.replace(temp, target)
    except BaseException:
        Path(temp).unlink(missing_ok=True)
        raise


def write_bytes(path: str | os.PathLike[str], data: bytes, stores: Protected = ()) -> Path:
    """`data` as the file at `path`, replaced atomically (see replacing); its real path."""
    target = check_output(path, stores)
    with replacing(path, stores) as out:
        out.write(data)
    return target


def write_text(path: str | os.PathLike[str], text: str, stores: Protected = ()) -> Path:
    """`text` (UTF-8) as the file at `path`, replaced atomically (see replacing); its real path."""
    return write_bytes(path, text.encode("utf-8"), stores)


def create_new(path: str | os.PathLike[str], mode: int = 0o600, stores: Protected = ()) -> int:
    """A file descriptor of a new file at `path` (FileExistsError if anything is there, a
    dangling symlink included: O_EXCL never follows one), after check_output."""
    check_output(path, stores)
    return os.open(os.fspath(path), os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), mode)


def _is(given: str, real: str) -> str:
    return "is" if os.path.abspath(given) == real else "resolves to"


def _kind(mode: int) -> str:
    for test, name in ((stat.S_ISDIR, "a folder"), (stat.S_ISCHR, "a character device"),
                       (stat.S_ISBLK, "a block device"), (stat.S_ISFIFO, "a fifo"), (stat.S_ISSOCK, "a socket")):
        if test(mode):
            return name
    return "a special file"


def _is_sqlite(path: str) -> bool:
    try:
        with open(path, "rb") as handle:
            return handle.read(len(SQLITE_HEADER)) == SQLITE_HEADER
    except OSError:
        return False


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask
