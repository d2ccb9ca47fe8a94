"""Helpers for the store tests: a factory of valid events and direct access to a store file.

A module of the tests.helpers package (not a conftest), imported by name from any test.
"""

from __future__ import annotations

import hashlib
import sqlite3
from pathlib import Path
from typing import Any

from store import Store, canonical_json
from store.ddl import APPEND_ONLY_TABLES, MIGRATIONS

T0 = 1_732_184_100_000_000_000  # 2024-11-21T10:15:00Z in ns

BODIES: dict[str, dict[str, Any]] = {
    "run.start": {"seed": 7},
    "run.end": {"reason": "duration reached"},
    "entity.spawn": {"type": "car", "driver": "autonomous"},
    "entity.state": {"x": 1.5, "y": -2.0, "speed_mps": 8.25, "junction": None},
    "entity.despawn": {"reason": "left the map"},
    "signal.state": {"junction": "J1", "colour": "red"},
    "vehicle.perception": {"facts": ["173 is of type car", "173 has red light"]},
    "vehicle.decision": {"goal": "173 can enter the junction", "action": "enter the junction", "proceeds": False},
    "vehicle.trace": {"query": "173 can enter the junction", "answer": False},
    "ads.event": {"event": "activated"},
    "monitor.observation": {"vehicle": "173", "facts": ["173 has red light"]},
    "monitor.potential_violation": {"vehicle": "173", "action": "enter the junction"},
    "collision": {"entities": ["173", "12"]},
}


# A source of a role allowed to send each kind (DESIGN's src column).
SOURCES: dict[str, str] = {
    "run.start": "sim/world",
    "run.end": "sim/world",
    "collision": "sim/world",
    "signal.state": "signal/J1",
    "monitor.observation": "monitor/m1",
    "monitor.potential_violation": "monitor/m1",
}


def event(
    seq: int = 0,
    *,
    run: str = "r1",
    src: str | None = None,
    t: int | None = None,
    kind: str = "vehicle.perception",
    body: dict[str, Any] | None = None,
) -> dict[str, Any]:
    """A valid event; t defaults to 100 ms per seq after T0, src to one allowed for the kind."""
    return {
        "v": 1,
        "run": run,
        "src": SOURCES.get(kind, "vehicle/173") if src is None else src,
        "seq": seq,
        "t": T0 + seq * 100_000_000 if t is None else t,
        "kind": kind,
        "body": dict(BODIES[kind]) if body is None else body,
    }


def old_schema(path: Path, version: int) -> sqlite3.Connection:
    """A connection to a new file with the tables gaps wrote at schema `version` (its migration
    steps 1..version, as an older gaps left them): for tests of reading and migrating old stores."""
    conn = sqlite3.connect(path, isolation_level=None)
    conn.execute("CREATE TABLE schema_version (version INTEGER NOT NULL)")
    for step in range(1, version + 1):
        for statement in MIGRATIONS[step]:
            conn.execute(statement)
        conn.execute("INSERT INTO schema_version VALUES (?)", (step,))
    return conn


def tamper(db_path: Path, *statements: tuple[str, tuple]) -> None:
    """Alter a closed store file behind the store's back, as an attacker with file access
    would: drop the append-only triggers, then run the statements."""
    conn = sqlite3.connect(db_path)
    try:
        conn.execute("PRAGMA synchronous=OFF")  # a test's file need not survive a power cut: no fsync
        for table in APPEND_ONLY_TABLES:
            conn.execute(f"DROP TRIGGER IF EXISTS {table}_no_update")
            conn.execute(f"DROP TRIGGER IF EXISTS {table}_no_delete")
        for sql, params in statements:
            conn.execute(sql, params)
        conn.commit()
    finally:
        conn.close()


def rows(db_path: Path, sql: str, params: tuple = ()) -> list[tuple]:
    """Read the file directly, bypassing the store."""
    conn = sqlite3.connect(db_path)
    try:
        return conn.execute(sql, params).fetchall()
    finally:
        conn.close()


def write_v1_file(db_path, evs, calls):
    """What v1 code wrote: events with their chain, one checkpoint per run per append call
    (count and head only), a rulebook without stored_at. `calls` splits evs into calls."""
    conn = sqlite3.connect(db_path, isolation_level=None)
    conn.execute("CREATE TABLE schema_version (version INTEGER NOT NULL)")
    for statement in MIGRATIONS[1]:
        conn.execute(statement)
    conn.execute("INSERT INTO schema_version VALUES (1)")
    head, count, start = bytes(32), 0, 0
    for size in calls:
        for ev in evs[start:start + size]:
            text = canonical_json(ev)
            head = hashlib.sha256(head + text).digest()
            conn.execute("INSERT INTO events VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
                         (ev["run"], count, ev["src"], ev["seq"], ev["t"], ev["kind"], text.decode(), head.hex()))
            count += 1
        conn.execute("INSERT INTO checkpoints (run, count, head, created_at) VALUES ('r1', ?, ?, 0)", (count, head.hex()))
        start += size
    conn.execute("INSERT INTO rulebooks VALUES (?, 'hc', '1', 'old rules')",
                 (hashlib.sha256(b"old rules").hexdigest(),))
    conn.close()


def heads(store: Store) -> dict[str, str]:
    """Each run's chain head, as verify recomputes it."""
    return {r.run: r.head for r in store.verify().runs}


def out_of_order_store(path: Path) -> Path:
    """Two runs (r1, r2) whose sources' batches arrive after each other's, so chain order is not
    time order: what an export must keep for the copy to reach the same chain heads."""
    ms = 1_000_000
    with Store(path) as store:
        for run in ("r1", "r2"):
            late = [event(seq, run=run, src="vehicle/2", kind="entity.state", t=T0 + seq * 10 * ms,
                          body={"x": 1.0, "y": 2.0, "speed_mps": 3.0}) for seq in range(30)]
            early = [event(seq, run=run, src="vehicle/1", t=T0 + seq * 10 * ms + 5 * ms) for seq in range(30)]
            store.append(late[15:] + early[:20])
            store.append(late[:15] + early[20:])
    return path


def careful(raw: bytes) -> tuple:
    """What the careful road makes of raw bytes (the standard parser, which refuses duplicate keys
    and NaN, then encode_event): ("ok", event, canonical bytes) or ("refused", reason). The fast
    roads of store/envelope.py are held to it."""
    from store import EventError
    from store.envelope import _parse_json, encode_event
    try:
        ev = _parse_json(raw)
        return ("ok", ev, encode_event(ev))
    except EventError as exc:
        return ("refused", str(exc))
