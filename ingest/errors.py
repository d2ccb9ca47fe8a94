"""The ingest's errors a user can act on, in the project's one hierarchy (store.GapsError), so that
`gaps serve` and `python -m ingest` print one line and exit with a code that says what happened."""
from __future__ import annotations

from store import GapsError

EXIT_STORE_IN_USE = 4


class IngestConfigError(GapsError, ValueError):
    """An option, a Zenoh config file, an endpoint or a key expression that cannot be used (exit 2).
    A ValueError too, as a bad mode was before this class existed."""


class StoreInUse(GapsError):
    """Another `gaps serve` already writes this store (exit 4, so a supervisor can tell "already
    running" from a mistake in the options)."""

    exit_code = EXIT_STORE_IN_USE


def zenoh_message(exc: BaseException) -> str:
    """Zenoh's error text without the Rust source location it appends (`... at /root/.cargo/...`)."""
    text = str(exc)
    cut = text.find(" at /")
    return (text[:cut] if cut > 0 else text).rstrip(".") or type(exc).__name__
