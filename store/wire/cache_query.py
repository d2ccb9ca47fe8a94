"""The producers' caches on the wire: where each announces itself, how an ingest asks one, and what
it answers (the wire contract's part for the caches; the cache itself is sim_replay/recent_events.py).

Every producer process (one ``EventPublisher``) keeps ONE cache of what it published in the last
CACHE_S seconds, for all its sources and kinds, rather than one per key: each per-key cache was a
Zenoh queryable, and declaring one per source and kind, for thousands of road users coming and
going, took the ingest's Zenoh thread most of a CPU (docs/serve.md "Recovery"). A cache:

- holds a liveliness token ``gaps/@cache/<id>`` while it lives (``<id>``: 32 hex digits, new per
  publisher), by which an ingest finds it, whenever either starts;
- answers queries on ``gaps/@cache/<id>/<rest>``, where ``gaps/<rest>`` is the asking ingest's own
  key expression (its slice): ``?_index`` gets one reply, the index, listing for each source the
  cache holds within the slice the lowest and highest seq held; a query whose payload is a
  ``want`` list (``{"want": [[run, src, first, last], ...]}``) gets every held event of those
  sources with a seq in those ranges, within the slice, each on its own key
  ``gaps/<run>/<src>/<kind>`` with its exact published bytes.

The chunks after ``gaps/`` start with @, which Zenoh treats as verbatim: ``gaps/**`` matches none
of them, so the events' subscribers and the history queryables never see a cache's token or query.
"""
from __future__ import annotations

import json
import re
from dataclasses import dataclass
from typing import Any

from ..errors import GapsError

__all__ = ["CACHE_PREFIX", "CACHE_QUERY_S", "CacheQuery", "CacheQueryError", "SourceSpan", "cache_id_of_token",
           "cache_query_options", "cache_token", "index_selector", "parse_cache_query", "read_index",
           "want_payload", "want_selector", "write_index"]

CACHE_PREFIX = "gaps/@cache"
CACHE_QUERY_S = 10.0   # how long an ingest waits for a cache's answer
_ID = re.compile(r"[0-9a-f]{32}")

Want = tuple[str, str, int, int]  # (run, src, first seq, last seq), inclusive


class CacheQueryError(GapsError, ValueError):
    """A query on a cache's key that the cache cannot answer (it replies with this as an error)."""


@dataclass(frozen=True, slots=True)
class SourceSpan:
    """What a cache holds of one source (within the slice asked): its lowest and highest seq."""

    run: str
    src: str
    first: int
    last: int


@dataclass(frozen=True, slots=True)
class CacheQuery:
    """A query a cache received: the slice asked (an events key expression, ``gaps/...``), and
    either the index or the wanted ranges."""

    slice: str
    index: bool
    want: tuple[Want, ...] = ()


def cache_token(cache_id: str) -> str:
    """The liveliness token a cache holds while it lives, and the prefix of its queryable."""
    return f"{CACHE_PREFIX}/{cache_id}"


def cache_id_of_token(key: str) -> str | None:
    """The cache id of a token's key, or None for a key of another shape."""
    prefix, _, ident = key.rpartition("/")
    return ident if prefix == CACHE_PREFIX and _ID.fullmatch(ident) else None


def _rest(slice_key: str) -> str:
    """``gaps/<rest>`` -> ``<rest>`` (an ingest's key always starts with gaps/)."""
    head, _, rest = slice_key.partition("/")
    if head != "gaps" or not rest:
        raise CacheQueryError(f"key expression {slice_key!r} is not under gaps/")
    return rest


def index_selector(cache_id: str, slice_key: str) -> str:
    """Ask one cache for its index of the sources within ``slice_key``."""
    return f"{cache_token(cache_id)}/{_rest(slice_key)}?_index"


def want_selector(slice_key: str, cache_id: str | None = None) -> str:
    """Where to send a want list: one cache, or every cache (``*``) when the ingest does not know
    which producer publishes a source (a hole seen in the live stream)."""
    return f"{CACHE_PREFIX}/{cache_id or '*'}/{_rest(slice_key)}"


def want_payload(want: list[Want]) -> bytes:
    """The want list as a query's payload."""
    return json.dumps({"want": [list(w) for w in want]}, separators=(",", ":")).encode()


def parse_cache_query(key: str, parameters: str, payload: bytes | None) -> CacheQuery:
    """What a query on ``gaps/@cache/<id>/<rest>`` asks, for the cache that received it."""
    parts = key.split("/", 3)
    if len(parts) != 4 or f"{parts[0]}/{parts[1]}" != CACHE_PREFIX:
        raise CacheQueryError(f"query on {key!r}: not gaps/@cache/<id>/<key expression>")
    slice_key = f"gaps/{parts[3]}"
    if "_index" in parameters.split(";"):
        return CacheQuery(slice_key, True)
    try:
        want = json.loads(payload or b"null")["want"]
        return CacheQuery(slice_key, False, tuple((str(r), str(s), int(a), int(b)) for r, s, a, b in want))
    except (ValueError, TypeError, KeyError) as exc:
        raise CacheQueryError(f"query on {key!r}: neither ?_index nor a payload "
                              f'{{"want": [[run, src, first, last], ...]}} ({exc})') from None


def write_index(spans: list[SourceSpan]) -> bytes:
    """The index reply's payload."""
    return json.dumps({"sources": [[s.run, s.src, s.first, s.last] for s in spans]}, separators=(",", ":")).encode()


def read_index(payload: bytes) -> list[SourceSpan]:
    """The spans of an index reply; a malformed one is an error naming what was wrong."""
    try:
        return [SourceSpan(str(r), str(s), int(a), int(b)) for r, s, a, b in json.loads(payload)["sources"]]
    except (ValueError, TypeError, KeyError) as exc:
        raise CacheQueryError(f"a cache's index is not {{\"sources\": [[run, src, first, last], ...]}}: {exc}") from None


def cache_query_options(timeout: float = CACHE_QUERY_S) -> dict[str, Any]:
    """How the ingest asks the caches: every reply of every cache (no consolidation, target ALL),
    and replies on the events' own keys, which are not the key asked."""
    import zenoh
    return {"consolidation": zenoh.ConsolidationMode.NONE, "accept_replies": zenoh.ReplyKeyExpr.ANY,
            "target": zenoh.QueryTarget.ALL, "timeout": timeout}
