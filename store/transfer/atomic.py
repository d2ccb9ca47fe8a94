"""Writing an export so that a failed or interrupted one never leaves a plausible-looking file.

An investigator who finds x.mcap must be able to trust it is a whole export: the file is written
under a temporary name beside the target and renamed into place only once it is complete. The
target is checked first by store/output_files.py: never the store read from, its companions, any
other store, or a file that is not a regular one.
"""

from __future__ import annotations

import os
from typing import ContextManager, BinaryIO, Iterable

from ..output_files import replacing as _replacing


def replacing(path: str | os.PathLike, stores: Iterable[str | os.PathLike] = ()) -> ContextManager[BinaryIO]:
    """A binary file that becomes `path` when the block finishes without an exception; refused
    (OutputRefused) when `path` resolves to one of `stores`, their companions, or evidence."""
    return _replacing(path, stores)
