"""The event store: envelope and schemas, the append-only hash-chained log, time-indexed reads.

This is the store's public API: other rooms import from here (`import store` / `from store
import X`), never from a submodule, and never run SQL themselves; the submodules are the
store's own layout. docs/store.md describes it.
"""

from .canonical import canonical_json
from .fastjson import loads as parse_json, loads_all as parse_json_all
from .db import Store
from .errors import EvidenceError, GapsError, IndexDisagrees, NoSuchRun, StoreError
from .errors import DiskFailed, DiskFull, RowRefused, StoreBusy, StoreDamaged, StoreFault, StoreReadOnly
from .sqlite_errors import store_fault, translating
from .output_files import OutputRefused, check_output, write_bytes, write_text
from .cache import altered_caches, caches_opened, caches_opened_since, damaged_caches, go_without_caches, unread_caches, unwritten_caches
from .refs import EventRef
from .run_map import MapJunction, MapMonitor, MapStopLine, Pair, RunMap, read_map_body, read_run_map, whole, whole_line
from .run_map import number as finite_number
from .envelope import (
    MAX_EVENT_BYTES,
    EventError,
    decode_event,
    encode_event,
    SYNC_KEY,
    key_for,
    parse_event,
    plain_event,
    validate_event,
)
from .history import HistoryFilter, HistoryRow
from .intake import Candidate
from .keyfiles import PUBLIC_KEYS_FILE, KeyFolder, KeysError, Signer, TrustedKeys
from .liveliness import LivelinessChange, SourceLife, WireMiss
from .kinds import KINDS, SRC_ROLES
from .migration import MigrateReport, migrate_copy
from .outcomes import AppendReport, VerifyReport
from .quarantine import Pruned, QuarantineCap, parse_before
from .run_summary import RunSummary
from .signatures import SIG_FIELD, key_id, sign_event, signed_bytes
from .snapshots import enable_snapshots
from .tail_check import TamperedTail
from .tree_heads import CheckpointKey, TreeHead, load_public, public_path_of
from .trust_root import recorded_heads
from .anchors import AnchorReport, RunProof
from .witness import WitnessError, WitnessFile, read_heads
from .wire import (BLOCK_FOR_US, CACHE_S, LIVE_PREFIX, MODES, WireConfigError, audit_publisher_options, audit_qos,
                   live_key, live_slice, matched_within, session_config, source_of_live_key, zenoh_message)
from .reachability import INSECURE_FLAG, LOCAL_PROTOCOLS, Exposure, check_producer, exposure, is_loopback
from .cache_wire import (CACHE_PREFIX, CacheQuery, CacheQueryError, SourceSpan, cache_id_of_token, cache_query_options,
                         cache_token, index_selector, parse_cache_query, read_index, want_payload, want_selector,
                         write_index)
from .partial_state import entity_since, state_of
from . import derived_cache, kept_recording
from .received_chain import ReceivedChains
from .cache_check import CacheTampering, cache_tampering
from .verify_outcome import VerifyOutcome, check_store
from .verify_report import IntegrityResult, Problem, RunCheck, SignatureCount
from .presence import check_presence, sources_near
from .state import OBSERVATION_WINDOW_S, CollectorPaused, build_snapshots, check_snapshots, state_at
from .state_value import State
from .timeline import Timeline
from .transfer import (
    DEFAULT_ORDER,
    ORDERS,
    ExportReport,
    ImportReport,
    Recorder,
    TransferError,
    check_source,
    export_run,
    format_of,
    import_file,
)

__all__ = [
    "OutputRefused",
    "check_output",
    "write_bytes",
    "write_text",
    "unwritten_caches",
    "altered_caches",
    "damaged_caches",
    "caches_opened",
    "caches_opened_since",
    "go_without_caches",
    "unread_caches",
    "derived_cache",
    "kept_recording",
    "parse_json",
    "parse_json_all",
    "CheckpointKey",
    "TamperedTail",
    "TreeHead",
    "WitnessError",
    "WitnessFile",
    "load_public",
    "public_path_of",
    "read_heads",
    "recorded_heads",
    "AnchorReport",
    "RunProof",
    "BLOCK_FOR_US",
    "CACHE_PREFIX",
    "CACHE_S",
    "CacheQuery",
    "CacheQueryError",
    "SourceSpan",
    "cache_id_of_token",
    "cache_token",
    "index_selector",
    "parse_cache_query",
    "read_index",
    "want_payload",
    "want_selector",
    "write_index",
    "LIVE_PREFIX",
    "MODES",
    "audit_publisher_options",
    "live_key",
    "live_slice",
    "matched_within",
    "cache_query_options",
    "source_of_live_key",
    "WireConfigError",
    "INSECURE_FLAG", "LOCAL_PROTOCOLS", "Exposure", "check_producer", "exposure", "is_loopback",
    "audit_qos",
    "session_config",
    "zenoh_message",
    "AppendReport",
    "Pruned",
    "QuarantineCap",
    "parse_before",
    "Candidate",
    "LivelinessChange",
    "SourceLife",
    "WireMiss",
    "CollectorPaused",
    "DEFAULT_ORDER",
    "EventError",
    "EventRef",
    "MapJunction", "MapMonitor", "MapStopLine", "Pair", "RunMap", "finite_number", "read_map_body", "read_run_map",
    "whole", "whole_line",
    "ExportReport",
    "EvidenceError",
    "GapsError",
    "HistoryFilter",
    "HistoryRow",
    "ImportReport",
    "Recorder",
    "KINDS",
    "KeyFolder",
    "KeysError",
    "PUBLIC_KEYS_FILE",
    "SIG_FIELD",
    "Signer",
    "TrustedKeys",
    "MAX_EVENT_BYTES",
    "MigrateReport",
    "IndexDisagrees",
    "NoSuchRun",
    "OBSERVATION_WINDOW_S",
    "ORDERS",
    "ReceivedChains",
    "RunSummary",
    "SRC_ROLES",
    "State",
    "Store",
    "StoreError",
    "VerifyOutcome", "check_store", "IntegrityResult", "Problem", "RunCheck", "SignatureCount",
    "StoreFault", "StoreDamaged", "StoreBusy", "StoreReadOnly", "DiskFull", "DiskFailed", "RowRefused",
    "store_fault", "translating",
    "Timeline",
    "TransferError",
    "VerifyReport",
    "build_snapshots",
    "canonical_json",
    "CacheTampering",
    "cache_tampering",
    "check_presence",
    "check_snapshots",
    "check_source",
    "decode_event",
    "enable_snapshots",
    "encode_event",
    "export_run",
    "format_of",
    "import_file",
    "SYNC_KEY",
    "sources_near",
    "state_of",
    "entity_since",
    "key_for",
    "key_id",
    "migrate_copy",
    "parse_event",
    "plain_event",
    "sign_event",
    "signed_bytes",
    "state_at",
    "validate_event",
]

# The face's functions that read or write a store file speak the store's errors, as Store's methods
# do (store/sqlite_errors.py): a caller in another room never meets sqlite3's. The `derived_cache`
# and `kept_recording` modules handed out above are not wrapped: the command line's net
# (`translating`) covers what they let through.
from .sqlite_errors import translates as _translates

for _name in ("build_snapshots", "cache_tampering", "check_presence", "check_snapshots", "check_store",
              "entity_since", "export_run", "import_file", "migrate_copy", "sources_near", "state_at", "state_of"):
    globals()[_name] = _translates(globals()[_name])
del _name
