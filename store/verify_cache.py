"""Verification results kept in the cache file, so that a run is re-hashed once per chain head.

Recomputing a run's chain reads and hashes every event (seconds on a long run); an explanation
or a report that cites the chain's verdict need not pay that each time. A result is recorded
under the run, its chain length and the stored hash of its last event, read in the same read
transaction as the verification itself, and is only handed back while the store still has that
length and head: an append, or any change to the last event, makes it a miss. `gaps verify`
never reads these: it always recomputes (a result in the cache is only as trustworthy as the
cache file, which nothing protects).
"""

from __future__ import annotations

import json
import sqlite3

from .outcomes import VerifyReport

ChainKey = tuple[int, str]  # (events in the run's chain, stored hash of the last one)


def chain_key(conn: sqlite3.Connection, run: str) -> ChainKey:
    """The run's chain as stored now: two index probes."""
    count, last = conn.execute("SELECT count(*), max(chain_pos) FROM events WHERE run = ?", (run,)).fetchone()
    if last is None:
        return (0, "")
    row = conn.execute("SELECT hash FROM events WHERE run = ? AND chain_pos = ?", (run, last)).fetchone()
    return (count, "" if row is None else str(row[0]))  # None: a damaged index lost the row it found


def recorded(cache: sqlite3.Connection, run: str, key: ChainKey) -> VerifyReport | None:
    """The verification recorded for exactly this chain, or None."""
    row = cache.execute(
        "SELECT report FROM verifications WHERE run = ? AND chain_len = ? AND head = ?", (run, *key)
    ).fetchone()
    if row is None:
        return None
    try:
        data = json.loads(row[0])
        return VerifyReport(ok=bool(data["ok"]), runs=list(data["runs"]), problem=data["problem"],
                            signatures=data.get("signatures"), integrity=data.get("integrity"))
    except (ValueError, KeyError, TypeError):
        return None  # damaged: recompute


def record(cache: sqlite3.Connection, run: str, key: ChainKey, report: VerifyReport) -> None:
    """Keep one result per run (the latest chain's); a locked cache is skipped, not waited on."""
    text = json.dumps(report.as_dict(), ensure_ascii=False)
    try:
        cache.execute("BEGIN IMMEDIATE")
    except sqlite3.OperationalError:
        return
    try:
        cache.execute("DELETE FROM verifications WHERE run = ?", (run,))
        cache.execute("INSERT INTO verifications (run, chain_len, head, report) VALUES (?, ?, ?, ?)",
                      (run, *key, text))
        cache.execute("COMMIT")
    except sqlite3.OperationalError:
        cache.execute("ROLLBACK")
