"""The event store: envelope and schemas, the append-only hash-chained log, time-indexed reads.

This is the store's core face: other rooms import from here (`import store` / `from store
import X`) and from the faces of its parts, never from a module inside, and never run SQL
themselves; the modules are the store's own layout. docs/store.md describes it.

    store           the log and its reads: Store, State, EventRef, the envelope, the errors
    store.wire      the wire contract: Zenoh sessions, key expressions, liveliness, cache and
                    history queries
    store.cache     the cache file beside a store: snapshots, presence, verified chains, kept results
    store.keys      keys, signatures, signed tree heads and witnesses
    store.transfer  events in and out of the store as files (JSONL, MCAP)
    store.errors    the project's one error hierarchy (GapsError is its root), also handed out here
"""

from .canonical import canonical_json
from .db import Store
from .envelope import MAX_EVENT_BYTES, EventError, decode_event, encode_event, parse_event, plain_event, validate_event
from .errors import EvidenceError, GapsError, IndexDisagrees, NoSuchRun, StoreError
from .fastjson import loads as parse_json, loads_all as parse_json_all
from .intake import Candidate
from .kinds import KINDS
from .migration import MigrateReport, migrate_copy
from .outcomes import AppendReport, VerifyReport
from .output_files import OutputRefused, check_output, write_bytes, write_text
from .partial_state import entity_since, state_of
from .quarantine import Pruned, QuarantineCap, parse_before
from .refs import EventRef
from .run_summary import RunSummary
from .state import CollectorPaused, state_at
from .state_value import State
from .timeline import Timeline

__all__ = [
    "AppendReport", "Candidate", "CollectorPaused", "EventError", "EventRef", "EvidenceError", "GapsError",
    "IndexDisagrees", "KINDS", "MAX_EVENT_BYTES", "MigrateReport", "NoSuchRun", "OutputRefused", "Pruned",
    "QuarantineCap", "RunSummary", "State", "Store", "StoreError", "Timeline", "VerifyReport", "canonical_json",
    "check_output", "decode_event", "encode_event", "entity_since", "migrate_copy", "parse_before", "parse_event",
    "parse_json", "parse_json_all", "plain_event", "state_at", "state_of", "validate_event", "write_bytes",
    "write_text",
]
