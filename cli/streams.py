"""`-` for a file argument: standard input read into, or standard output copied from, a
temporary file, so the rooms that read and write files need no second code path for pipes."""
from __future__ import annotations

import shutil
import sys
import tempfile
from contextlib import contextmanager
from pathlib import Path
from typing import Iterator


@contextmanager
def stdin_file(suffix: str) -> Iterator[Path]:
    """Standard input's bytes as a temporary file named *suffix (which tells its format)."""
    with tempfile.TemporaryDirectory(prefix="gaps-stdin-") as tmp:
        path = Path(tmp) / f"stdin{suffix}"
        with open(path, "wb") as out:
            shutil.copyfileobj(sys.stdin.buffer, out)
        yield path


@contextmanager
def stdout_file(suffix: str) -> Iterator[Path]:
    """A temporary file named *suffix whose bytes go to standard output once it is written."""
    with tempfile.TemporaryDirectory(prefix="gaps-stdout-") as tmp:
        path = Path(tmp) / f"stdout{suffix}"
        yield path
        with open(path, "rb") as written:
            shutil.copyfileobj(written, sys.stdout.buffer)
        sys.stdout.buffer.flush()
