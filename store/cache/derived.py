"""Results a reader derived from one run's chain, kept in the cache file under that chain.

The reasoner measures every case of a run (where the vehicle was, what its passage shows, what
the state held at the act) before the rulebooks judge it; none of that depends on a rulebook,
and the measuring is most of the work (issue 12). Kept here, a second investigation of the
same chain re-runs the law on every case without measuring again.

An entry is named by the run, a kind (what the reader keeps: "measurement", "state", ...), a
version (the reader's digest of the code that derived it: another version is never used), the
chain it was derived from (count of events, stored hash of the last one) and a key; its payload
is text (JSON) the reader encodes and decodes. Entries of a run are only handed back while the
run's chain is exactly the one they were derived from, and only with their seal
(store/cache_seal.py): a forged or altered entry is dropped, counted and recomputed, never
believed, and `gaps verify` names it. Deleting the table changes no result.
"""
from __future__ import annotations

import sqlite3
from typing import TYPE_CHECKING, Any, Callable, Mapping

from ..sqlite_errors import translates
from .file import rollback
if TYPE_CHECKING:                       # annotations only: the store's faces load before db is done
    from ..db import Store
from .verified import ChainKey

TABLE = "derived"
MAX_PAYLOAD = 4 << 20           # an entry larger than this is not kept (recomputed instead)


@translates             # like the rest of the store's faces: sqlite3's errors leave as StoreFault
def current_chain(store: Store, run: str) -> ChainKey:
    """The run's chain as stored now (Store.chain_tip): what every entry is kept under."""
    return store.chain_tip(run)


class Sealed:
    """A run's entries of one kind, each handed back only if its seal opens, checked when it is
    asked for: a judgement that skips most of a run's cases reads the others' entries in one
    query, but frames and checks only the seals of those it uses. `fetch` (a kind read for a
    few of its entries): each entry is read by its key when first asked for, not all at once."""

    def __init__(self, rows: dict[str, tuple[str, bytes] | None], sealer: Any, where: tuple[str, str, str, ChainKey],
                 fetch: Callable[[str], tuple[str, bytes] | None] | None = None) -> None:
        self._rows, self._sealer, self._where = rows, sealer, where     # (run, kind, version, chain)
        self._fetch = fetch
        self._prefix = sealer.prefix(TABLE, _names(*where, "")[:-1]) if sealer is not None else b""

    def get(self, key: str) -> str | None:
        """The entry's payload, or None (never kept, or its seal did not open: then it is
        dropped, counted by the cache's sealer, and not asked again)."""
        row = self._rows.get(key)
        if row is None:
            if self._fetch is None or key in self._rows:
                return None
            row = self._rows[key] = self._fetch(key)
            if row is None:
                return None
        payload, mac = row
        if not self._sealer.opens_after(TABLE, self._prefix, key, payload, mac):
            self._rows[key] = None
            return None
        return payload


@translates
def load(store: Store, run: str, kind: str, version: str, chain: ChainKey, *, by_key: bool = False) -> Sealed:
    """The run's entries of this kind and version derived from exactly this chain, by key; each
    one whose seal does not open is left out when asked for (and counted by the cache's sealer).
    `by_key`: each read when asked for, by its key (a kind of which a reader needs a few
    entries: a regression reads the whole incidents of the changed ones, on the hour 214 of
    1,758, whose entries are 24 MB; reading them all took six times as long)."""
    where = (run, kind, version, chain)
    if not store.cache.exists():
        return Sealed({}, None, where)
    if by_key:
        @translates     # called later, from Sealed.get: its errors are the store's too
        def fetch(key: str) -> tuple[str, bytes] | None:
            return store.cache.connection.execute(
                "SELECT payload, mac FROM derived WHERE run = ? AND kind = ? AND version = ? AND key = ? "
                "AND chain_len = ? AND head = ?", (run, kind, version, key, *chain)).fetchone()
        return Sealed({}, store.cache.sealer, where, fetch)
    rows = store.cache.connection.execute(
        "SELECT key, payload, mac FROM derived WHERE run = ? AND kind = ? AND version = ? AND chain_len = ? "
        "AND head = ?", (run, kind, version, *chain)).fetchall()
    return Sealed({key: (payload, mac) for key, payload, mac in rows}, store.cache.sealer, where)


@translates
def save(store: Store, run: str, kind: str, version: str, chain: ChainKey, entries: Mapping[str, str]) -> bool:
    """Keep these entries for the chain they were derived from, replacing the run's entries of
    this kind derived from any other chain or version, provided the run's chain is still that
    one (else the reads may have seen part of an append: nothing is kept). False when nothing
    was written (a changed chain, a locked or read-only cache: it is an optimisation)."""
    if current_chain(store, run) != chain:
        return False
    sealer, cache = store.cache.sealer, store.cache.connection
    rows = [(run, kind, version, *chain, key, payload, sealer.seal(TABLE, _names(run, kind, version, chain, key), payload))
            for key, payload in entries.items() if len(payload) <= MAX_PAYLOAD]
    try:
        cache.execute("BEGIN IMMEDIATE")
        cache.execute("DELETE FROM derived WHERE run = ? AND kind = ? AND (version <> ? OR chain_len <> ? OR head <> ?)",
                      (run, kind, version, *chain))
        cache.executemany("INSERT OR REPLACE INTO derived (run, kind, version, chain_len, head, key, payload, mac) "
                          "VALUES (?, ?, ?, ?, ?, ?, ?, ?)", rows)
        cache.execute("COMMIT")
        return True
    except sqlite3.DatabaseError as exc:       # locked, a full disk, a read-only folder: not kept
        rollback(cache)
        store.cache.failed_to_write(exc)
        return False


@translates
def tampered_derived(store: Store, run: str) -> list[str]:
    """"kind key" of each of the run's entries whose seal does not open (for `gaps verify`)."""
    if not store.cache.exists():
        return []
    rows = store.cache.connection.execute(
        "SELECT kind, version, chain_len, head, key, payload, mac FROM derived WHERE run = ?", (run,)).fetchall()
    sealer = store.cache.sealer
    return [f"{kind} {key}" for kind, version, n, head, key, payload, mac in rows
            if not sealer.opens(TABLE, _names(run, kind, version, (n, head), key), payload, mac, count=False)]


def _names(run: str, kind: str, version: str, chain: ChainKey, key: str) -> tuple:
    return (run, kind, version, chain[0], chain[1], key)
