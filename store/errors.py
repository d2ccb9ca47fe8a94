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
