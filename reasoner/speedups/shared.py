"""What investigations of one store read of a run alike (a regression's two sides), read once."""
from __future__ import annotations

from typing import Any, Callable


class SharedReading:
    """What investigations of one store read of a run alike, by what names it (the run, its chain,
    what it is): read and parsed once. Only the last run's is held."""

    def __init__(self) -> None:
        self._run: str | None = None
        self._read: dict[tuple, Any] = {}

    def get(self, key: tuple, read: Callable[[], Any]) -> Any:
        """The value read under `key` (its run first), else `read()` (kept unless None)."""
        if key[0] != self._run:
            self._run, self._read = key[0], {}
        found = self._read.get(key)
        if found is None:
            found = read()
            if found is not None:
                self._read[key] = found
        return found
