"""Memory given back when the ingest goes quiet: a fleet's burst must not stay resident for ever.

While events arrive, the writer keeps what makes it fast: SQLite's page cache (store/opening.py's
CACHE_KIB a connection), Python's free lists and the C heap's freed blocks. Once nothing has
arrived for QUIET_S, the writer gives them back, once per quiet spell: the store's connections
shrink their page caches, the collector runs in full, and glibc's `malloc_trim` returns the
heap's free pages to the kernel (elsewhere than glibc, that step is skipped). Just before, the inbox
renews its subscription (ingest/inbox.py `renew`), so that Zenoh's channel, which never shrinks, is
among what goes back. bench/ingest_fleet.py
measures the serve's resident memory before and after 10,000 runs.
"""
from __future__ import annotations

import ctypes
import ctypes.util
import gc
import logging

from store import Store

log = logging.getLogger(__name__)

QUIET_S = 1.0

_libc = None
try:
    _path = ctypes.util.find_library("c")
    _libc = ctypes.CDLL(_path) if _path else None
    _trim = getattr(_libc, "malloc_trim", None)
except OSError:
    _trim = None


def give_back(store: Store) -> None:
    """Shrink the store's page caches, collect, and trim the C heap; a failure costs only this."""
    try:
        store.shrink_memory()
    except Exception as exc:            # a busy or broken cache: the events are not at stake
        log.warning("ingest: shrinking SQLite's memory failed: %r", exc)
    gc.collect()
    if _trim is not None:
        _trim(0)
