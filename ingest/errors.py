"""The ingest's errors a user can act on, in the project's one hierarchy (store.GapsError), so that
`gaps serve` and `python -m ingest` print one line and exit with a code that says what happened."""
from __future__ import annotations

from store import GapsError
from store.wire import WireConfigError, zenoh_message

EXIT_STORE_IN_USE = 4


IngestConfigError = WireConfigError
"""An option, a Zenoh config file, an endpoint or a key expression that cannot be used (exit 2): the
wire contract's own error (store/wire.py), under the name the ingest has always raised."""


class StoreInUse(GapsError):
    """Another `gaps serve` already writes this store (exit 4, so a supervisor can tell "already
    running" from a mistake in the options)."""

    exit_code = EXIT_STORE_IN_USE


__all__ = ["EXIT_STORE_IN_USE", "IngestConfigError", "StoreInUse", "zenoh_message"]
