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
    store.errors    the project's one error hierarchy (GapsError is its root, StoreFault the kinds of
                    SQLite's conditions); the root and the faults are also handed out here
    store.run_map   the run map of a run.start event, read once into typed values
"""

from .canonical import canonical_json
from .db import Store
from .envelope import MAX_EVENT_BYTES, EventError, decode_event, encode_event, parse_event, plain_event, validate_event
from .errors import EvidenceError, GapsError, IndexDisagrees, NoSuchRun, StoreError
from .errors import StoreFault
from .fastjson import loads as parse_json, loads_all as parse_json_all
from .intake import Candidate
from .kinds import KINDS
from .migration import MigrateReport, migrate_copy
from .outcomes import AppendReport, Rejection
from .output_files import OutputRefused, check_output, write_bytes, write_text
from .partial_state import entity_since, state_of
from .quarantine import Pruned, QuarantineCap, parse_before
from .refs import EventRef
from .run_summary import RunSummary
from .sqlite_errors import store_fault, translating
from .state import CollectorPaused, state_at
from .state_value import State
from .timeline import Timeline
from .verify_outcome import VerifyOutcome, check_store
from .verify_report import IntegrityResult, Problem, RunCheck, SignatureCount, VerifyReport

__all__ = [
    "AppendReport", "Candidate", "CollectorPaused", "EventError", "EventRef", "EvidenceError", "GapsError",
    "IndexDisagrees", "KINDS", "MAX_EVENT_BYTES", "MigrateReport", "NoSuchRun", "OutputRefused", "Pruned",
    "QuarantineCap", "Rejection", "RunSummary", "State", "Store", "StoreError", "Timeline", "VerifyReport",
    "canonical_json",
    "check_output", "decode_event", "encode_event", "entity_since", "migrate_copy", "parse_before", "parse_event",
    "parse_json", "parse_json_all", "plain_event", "state_at", "state_of", "validate_event", "write_bytes",
    "write_text",
    "StoreFault", "store_fault", "translating",
    "IntegrityResult", "Problem", "RunCheck", "SignatureCount", "VerifyOutcome", "check_store",
]

# The face's functions that read or write a store file speak the store's errors, as Store's methods
# do (store/sqlite_errors.py): a caller in another room never meets sqlite3's. The faces of the
# store's parts wrap theirs the same way (store/cache, store/transfer), the `derived` and
# `kept_recording` modules that store.cache hands out wrap their own functions, and a Timeline
# its methods (docs/guarantees.md, tests/store/test_store_cache_wall.py).
from .sqlite_errors import translates as _translates

for _name in ("check_store", "entity_since", "migrate_copy", "state_at", "state_of"):
    globals()[_name] = _translates(globals()[_name])
del _name
