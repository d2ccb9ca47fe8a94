"""One `gaps serve` per store: an OS lock on a file beside it, ``<store>.serve.lock``.

Two ingests on one store would both chain events onto the same runs and race for SQLite's write lock;
the second one is refused before it opens Zenoh or the store. ``flock`` is held by the open file, so the
kernel releases it when the process ends however it ends (kill -9, a crash, a power cut of the host
clears it too): no stale lock to clean up by hand. The file holds the pid of its holder, so that the
refusal can say who holds the store; a holder removes it as it lets go (issue 39: every demo and sim
left one behind with a dead pid), so only a process that was killed leaves one, and the next takes it
over. Because the file can vanish, a lock is only taken on the file the path still names: one
opened just before its holder removed it is a file nobody else can find, and is opened again.

flock is advisory and local: it keeps out another `gaps serve` (or `gaps demo`/`gaps sim` writing through
their in-process ingest) on this machine, not a process that ignores it, and not a host writing the
same file over a network file system (do not put a live store there).
"""
from __future__ import annotations

import fcntl
import os
from pathlib import Path
from types import TracebackType

from .errors import IngestConfigError, StoreInUse


def lock_path(db_path: str | os.PathLike) -> Path:
    """Where the lock of the store at ``db_path`` lives: beside it, named after it."""
    db = Path(db_path)
    return db.with_name(db.name + ".serve.lock")


class ServeLock:
    """Held from ``acquire`` (or ``with``) to ``release``; refuses with StoreInUse, naming the holder."""

    def __init__(self, db_path: str | os.PathLike) -> None:
        self.db = Path(db_path)
        self.path = lock_path(db_path)
        self._fd: int | None = None

    def acquire(self) -> ServeLock:
        """Take the lock without waiting and write our pid into the file."""
        while True:
            fd = self._open()
            try:
                fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except BlockingIOError:
                holder = _read_pid(fd)
                os.close(fd)
                who = f"pid {holder}" if holder else "another process"
                raise StoreInUse(f"the store {self.db} is already being written by a gaps serve ({who}, holding "
                                 f"{self.path}): stop that one first, or give this one another --db") from None
            except BaseException:
                os.close(fd)
                raise
            if _is_at(fd, self.path):
                break
            os.close(fd)                # removed by the holder we raced with: open the path again
        os.ftruncate(fd, 0)
        os.write(fd, f"{os.getpid()}\n".encode())
        self._fd = fd
        return self

    def _open(self) -> int:
        try:
            return os.open(self.path, os.O_RDWR | os.O_CREAT | os.O_CLOEXEC, 0o644)
        except OSError as exc:
            raise IngestConfigError(f"cannot create the lock file {self.path} beside the store: "
                                    f"{exc.strerror or exc}") from None

    def release(self) -> None:
        """Remove the file, then drop the lock (closing the file drops it). Safe to call twice."""
        if self._fd is not None:
            fd, self._fd = self._fd, None
            try:
                if _is_at(fd, self.path):
                    os.unlink(self.path)
            except OSError:
                pass                    # a read-only folder: the file stays, and only the lock matters
            os.close(fd)

    def __enter__(self) -> ServeLock:
        return self.acquire()

    def __exit__(self, exc_type: type[BaseException] | None, exc: BaseException | None,
                 tb: TracebackType | None) -> None:
        self.release()


def _read_pid(fd: int) -> int | None:
    """The pid the holder wrote, if it wrote one yet (a holder that just took the lock may not have)."""
    try:
        text = os.pread(fd, 32, 0).decode("ascii", "replace").strip()
    except OSError:
        return None
    return int(text) if text.isdigit() else None


def _is_at(fd: int, path: Path) -> bool:
    """Whether the open file is the one `path` names now."""
    try:
        here, there = os.fstat(fd), os.stat(path)
    except OSError:
        return False
    return (here.st_dev, here.st_ino) == (there.st_dev, there.st_ino)
