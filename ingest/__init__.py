"""Zenoh subscription, screening, quarantine, batching into the store, gap detection."""

from .service import IngestService
from .session_config import session_config

__all__ = ["IngestService", "session_config"]
