"""The wire contract: how every gaps session meets Zenoh, what travels on which key, and what the
ingest notes about the wire beside the events. This is its face: other rooms import from here
(`from store.wire import X`), never from a module inside.

    contract        the session config builder, the live key space, QoS and the message form
    reachability    whether a session can be reached from beyond this machine
    cache_query     the producers' caches on the wire: announcing, asking, answering
    history         a run's stored events in chain order, as a history query answers them
    received_chain  a run received from another store, checked against that store's chain
    liveliness      what the ingest noticed about its sources on the wire
    ends            where the wire tables' hash chains stand, as a checkpoint records it

The event envelope's key expressions (store/envelope.py) are part of the contract, so they are
handed out here too.
"""
from ..envelope import SYNC_KEY, key_for
from .cache_query import (CACHE_PREFIX, CacheQuery, CacheQueryError, SourceSpan, cache_id_of_token, cache_query_options,
                          cache_token, index_selector, parse_cache_query, read_index, want_payload, want_selector,
                          write_index)
from .contract import (BLOCK_FOR_US, CACHE_S, LIVE_PREFIX, MODES, WireConfigError, audit_publisher_options, audit_qos,
                       live_key, live_slice, matched_within, session_config, source_of_live_key, zenoh_message)
from .history import HistoryFilter, HistoryRow
from .liveliness import LivelinessChange, SourceLife, WireMiss
from .reachability import INSECURE_FLAG, LOCAL_PROTOCOLS, Exposure, check_producer, exposure, is_loopback
from .received_chain import BrokenLink, ReceivedChain, ReceivedChains

__all__ = [
    "BLOCK_FOR_US", "BrokenLink", "CACHE_PREFIX", "CACHE_S", "CacheQuery", "CacheQueryError", "Exposure",
    "HistoryFilter", "HistoryRow", "INSECURE_FLAG", "LIVE_PREFIX", "LOCAL_PROTOCOLS", "LivelinessChange", "MODES",
    "ReceivedChain", "ReceivedChains",
    "SYNC_KEY", "SourceLife", "SourceSpan", "WireConfigError", "WireMiss", "audit_publisher_options", "audit_qos",
    "cache_id_of_token", "cache_query_options", "cache_token", "check_producer", "exposure", "index_selector",
    "is_loopback", "key_for", "live_key", "live_slice", "matched_within", "parse_cache_query", "read_index",
    "session_config", "source_of_live_key", "want_payload", "want_selector", "write_index", "zenoh_message",
]
