"""The event store: envelope and schemas, the append-only hash-chained log, time-indexed reads.

Everything other rooms need is importable from here; the submodules are the store's own layout.
"""

from .canonical import canonical_json
from .db import Store
from .errors import GapsError, NoSuchRun, StoreError
from .refs import EventRef
from .envelope import (
    MAX_EVENT_BYTES,
    EventError,
    decode_event,
    encode_event,
    key_for,
    parse_event,
    validate_event,
)
from .intake import Candidate
from .kinds import KINDS
from .migration import MigrateReport, migrate_copy
from .reports import AppendReport, VerifyReport

__all__ = [
    "AppendReport",
    "Candidate",
    "EventError",
    "EventRef",
    "GapsError",
    "NoSuchRun",
    "StoreError",
    "KINDS",
    "MAX_EVENT_BYTES",
    "MigrateReport",
    "Store",
    "VerifyReport",
    "canonical_json",
    "decode_event",
    "encode_event",
    "key_for",
    "migrate_copy",
    "parse_event",
    "validate_event",
]
