"""Verification results kept in the cache file, so that a run is re-hashed once per chain head.

Recomputing a run's chain reads and hashes every event (seconds on a long run); an explanation
or a report that cites the chain's verdict need not pay that each time. A result is recorded
under the run, its chain length and the stored hash of its last event, read in the same read
transaction as the verification itself, and is only handed back while the store still has that
length and head: an append, or any change to the last event, makes it a miss. `gaps verify`
never reads these: it always recomputes. Each result is sealed (store/cache_seal.py) over its
run, chain length, head and report: a result written behind the store's back (an altered run
declared intact) does not open, and is dropped and recomputed, never cited.
"""

from __future__ import annotations

import json
import sqlite3

from .file import Cache, rollback
from ..verify_report import VerifyReport

ChainKey = tuple[int, str]  # (events in the run's chain, stored hash of the last one)


def chain_key(conn: sqlite3.Connection, run: str) -> ChainKey:
    """The run's chain as stored now: two index probes."""
    count, last = conn.execute("SELECT count(*), max(chain_pos) FROM events WHERE run = ?", (run,)).fetchone()
    if last is None:
        return (0, "")
    row = conn.execute("SELECT hash FROM events WHERE run = ? AND chain_pos = ?", (run, last)).fetchone()
    return (count, "" if row is None else str(row[0]))  # None: a damaged index lost the row it found


TABLE = "verifications"


def recorded(cache: Cache, run: str, key: ChainKey) -> VerifyReport | None:
    """The verification recorded for exactly this chain and sealed by this code, or None."""
    row = cache.connection.execute(
        "SELECT report, mac FROM verifications WHERE run = ? AND chain_len = ? AND head = ?", (run, *key)
    ).fetchone()
    if row is None or not cache.sealer.opens(TABLE, (run, *key), row[0], row[1]):
        return None
    try:
        data = json.loads(row[0])
        return VerifyReport.from_json(data)
    except (ValueError, KeyError, TypeError):
        return None  # damaged: recompute


def record(sealed: Cache, run: str, key: ChainKey, report: VerifyReport) -> None:
    """Keep one result per run (the latest chain's), sealed; a locked cache is skipped, not waited on."""
    text = json.dumps(report.to_json(), ensure_ascii=False)
    cache, mac = sealed.connection, sealed.sealer.seal(TABLE, (run, *key), text)
    try:
        cache.execute("BEGIN IMMEDIATE")
        cache.execute("DELETE FROM verifications WHERE run = ?", (run,))
        cache.execute("INSERT INTO verifications (run, chain_len, head, report, mac) VALUES (?, ?, ?, ?, ?)",
                      (run, *key, text, mac))
        cache.execute("COMMIT")
    except sqlite3.DatabaseError as exc:       # locked, a full disk, a read-only folder: not kept
        rollback(cache)
        sealed.failed_to_write(exc)


def unsealed(cache: Cache) -> list[tuple]:
    """(run, chain length, head) of every recorded result whose seal does not open (for verify)."""
    rows = cache.connection.execute("SELECT run, chain_len, head, report, mac FROM verifications").fetchall()
    return [(run, n, head) for run, n, head, report, mac in rows
            if not cache.sealer.opens(TABLE, (run, n, head), report, mac, count=False)]
