"""The cache file beside a store: derived data (state snapshots, where road users were, verified
chains, what readers derived from a run, recordings regressed before) that makes reads faster,
never different. This is its face: other rooms import from here (`from store.cache import X`),
never from a module inside.

    file            the cache file: opened, written, rolled back, and what each command did with it
    seal            seals on its entries, so that an altered entry is not used
    check           what `gaps verify` says of the entries that do not carry their seals
    snapshots       snapshots of folded state, per run and chain head
    presence        where each road user was, coarsely, per source and time bucket
    verified        verification results, kept per chain head
    derived         results a reader derived from one run's chain
    kept_recording  a recording regressed before, kept by its digest
"""
from ..state import build_snapshots, check_snapshots
from . import derived, kept_recording
from .check import CacheTampering, cache_tampering
from .file import (altered_caches, caches_opened, caches_opened_since, damaged_caches, go_without_caches, unread_caches,
                   unwritten_caches)
from .presence import check_presence, sources_near
from .snapshots import enable_snapshots

__all__ = [
    "CacheTampering", "altered_caches", "build_snapshots", "cache_tampering", "caches_opened", "caches_opened_since",
    "check_presence", "check_snapshots", "damaged_caches", "derived", "enable_snapshots", "go_without_caches",
    "kept_recording", "sources_near", "unread_caches", "unwritten_caches",
]

# Its functions that read or write a store file speak the store's errors (store/sqlite_errors.py);
# `derived` and `kept_recording` wrap their own functions the same way.
from ..sqlite_errors import translates as _translates

for _name in ("build_snapshots", "cache_tampering", "check_presence", "check_snapshots", "enable_snapshots",
              "sources_near"):
    globals()[_name] = _translates(globals()[_name])
del _name
