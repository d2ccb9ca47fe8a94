"""The one error a transfer raises for a user's mistake (a missing file, an unknown format, a run
that is not in the store, a file that is not MCAP at all).

Everything else that can be wrong with input is a per-event matter: it is quarantined and
reported, and the rest of the file is still imported. This error is for when nothing can be.
"""

from __future__ import annotations

from ..errors import EvidenceError, GapsError


class TransferError(GapsError, ValueError):
    """A message for the person at the command line, naming the file and what is wrong."""


class ExportIncomplete(EvidenceError):
    """An export that did not write the run the chain holds (store/transfer/whole_run.py): no file
    is left in its place, and the message says how many events were written and how many the
    chain holds. Exit 1: the store's indexes disagree with its chain; `gaps verify` says where."""
