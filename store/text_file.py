"""A small text file a user names (a key, a witness), read with errors that say which and why."""
from __future__ import annotations

import os
from pathlib import Path


def read_named(path: str | os.PathLike, what: str, error: type[Exception], encoding: str = "utf-8",
               hint: str = "") -> str:
    """The file's text; `error` naming `what` it was meant to be when it is missing (with `hint`:
    how to make one) or unreadable."""
    try:
        return Path(path).read_text(encoding)
    except FileNotFoundError:
        raise error(f"no {what} at {path}{hint}") from None
    except (OSError, UnicodeDecodeError) as exc:
        raise error(f"cannot read the {what} {path}: {getattr(exc, 'strerror', None) or exc}") from None
