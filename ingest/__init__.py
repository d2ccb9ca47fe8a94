"""Zenoh subscription, screening, quarantine, batching into the store, gap detection."""

from .service import IngestService
from store.wire import session_config  # the wire contract (store/wire.py), as the ingest's API has always named it

__all__ = ["IngestService", "session_config"]
