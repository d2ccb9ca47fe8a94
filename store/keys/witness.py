"""Signed tree heads kept outside the store: a witness file of JSON lines, appended and fsynced.

Whoever holds the store file can rewrite it, checkpoints included; they cannot rewrite a copy of
the heads they do not hold. The ingest appends each signed checkpoint's tree head
(store/tree_heads.py) to a witness file, one JSON object a line, and fsyncs it before the next
batch, so that the file can go to another machine, a write-once medium or a notary; `gaps verify
--against FILE` checks a store against it (store/anchors.py).
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Iterable

from ..errors import GapsError
from .files import KeysError
from ..output_files import check_output
from ..text_file import read_named
from .tree_heads import TreeHead


class WitnessError(GapsError):
    """A witness file that cannot be written or read; the message names the file (and line)."""


class WitnessFile:
    """Appends signed tree heads to a file, one JSON line each, fsynced before returning."""

    def __init__(self, path: str | os.PathLike) -> None:
        self.path = Path(path)
        check_output(self.path)     # appended to, never a store, its companions or a special file
        try:
            self._fd = os.open(self.path, os.O_WRONLY | os.O_CREAT | os.O_APPEND, 0o644)
        except OSError as exc:
            raise WitnessError(f"cannot open the witness file {self.path}: {exc.strerror or exc}") from None

    def append(self, heads: Iterable[TreeHead]) -> None:
        data = "".join(json.dumps(head.to_json(), sort_keys=True, separators=(",", ":")) + "\n" for head in heads)
        if not data:
            return
        try:
            os.write(self._fd, data.encode("utf-8"))
            os.fsync(self._fd)
        except OSError as exc:
            raise WitnessError(f"cannot write the witness file {self.path}: {exc.strerror or exc}") from None

    def close(self) -> None:
        if self._fd >= 0:
            os.close(self._fd)
            self._fd = -1


def read_heads(path: str | os.PathLike) -> list[TreeHead]:
    """Every tree head of a witness file, in order; a WitnessError names the line that is wrong."""
    lines = read_named(path, "witness file", WitnessError).splitlines()
    heads = []
    for number, line in enumerate(lines, 1):
        if not line.strip():
            continue
        where = f"{path}:{number}"
        try:
            heads.append(TreeHead.from_json(json.loads(line), where))
        except ValueError as exc:
            raise WitnessError(f"{where}: not a JSON line ({exc})") from None
        except KeysError as exc:
            raise WitnessError(str(exc)) from None
    if not heads:
        raise WitnessError(f"{path} holds no tree heads")
    return heads
