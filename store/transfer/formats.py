"""Which transfer format a file is in: by its extension, or as the user says."""

from __future__ import annotations

from pathlib import Path

from .errors import TransferError

EXTENSIONS = {".jsonl": "jsonl", ".ndjson": "jsonl", ".mcap": "mcap"}
FORMATS = ("jsonl", "mcap")


def format_of(path: str | Path, given: str | None = None) -> str:
    """The format to read or write `path` in; `given` (from --format) wins over the extension."""
    if given is not None:
        fmt = given.lower()
        if fmt not in FORMATS:
            raise TransferError(f"unknown format {given!r}: use one of {', '.join(FORMATS)}")
        return fmt
    suffix = Path(path).suffix.lower()
    if suffix not in EXTENSIONS:
        known = ", ".join(EXTENSIONS)
        raise TransferError(f"{path}: cannot tell the format from the extension {suffix or '(none)'!r}; "
                            f"use {known} or pass --format")
    return EXTENSIONS[suffix]
