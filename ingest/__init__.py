"""Zenoh subscription, screening, quarantine, batching into the store, gap detection.

Its face: the service (`gaps serve`, `python -m ingest`), an in-process server (`gaps demo` and
`gaps sim --db` store through it) and the history fetch (`gaps fetch`)."""

from .history_fetch import AnswerError, FetchOptions, FetchReport, fetch
from .serve import Server, ServeOptions
from .serve import serve as run_service          # the module keeps the name `ingest.serve`
from .service import IngestService
from store.wire import session_config  # the wire contract (store/wire.py), as the ingest's API has always named it

__all__ = ["AnswerError", "FetchOptions", "FetchReport", "IngestService", "ServeOptions", "Server", "fetch",
           "run_service", "session_config"]
