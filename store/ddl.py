"""The SQLite schema of a store file and the migrations that bring a file up to date.

Migrations are numbered; each runs once, in its own transaction with the version row that
records it, so a file is never left half-migrated and opening a store is idempotent.
"""

from __future__ import annotations

import sqlite3

from .wire import liveliness
from .errors import StoreError

APPEND_ONLY_TABLES = ("events", "quarantine", "checkpoints", "rulebooks", "legacy_checkpoints", *liveliness.TABLES,
                      "wire_legacy", "wire_checkpoints", "quarantine_prunes", "quarantine_overflow")


def _append_only(table: str) -> tuple[str, ...]:
    """Triggers that refuse UPDATE and DELETE: the log only grows."""
    return tuple(
        f"CREATE TRIGGER {table}_no_{op.lower()} BEFORE {op} ON {table} "
        f"BEGIN SELECT RAISE(ABORT, 'append-only: {table} rows cannot be {verb}'); END"
        for op, verb in (("UPDATE", "updated"), ("DELETE", "deleted"))
    )


_V1 = (
    """CREATE TABLE events (
        run TEXT NOT NULL,
        chain_pos INTEGER NOT NULL,
        src TEXT NOT NULL,
        seq INTEGER NOT NULL,
        t INTEGER NOT NULL,
        kind TEXT NOT NULL,
        event TEXT NOT NULL,
        hash TEXT NOT NULL,
        UNIQUE (run, chain_pos),
        UNIQUE (run, src, seq)
    )""",
    # src completes the read order (t, seq, src), so reads stream without a sort.
    "CREATE INDEX events_by_time ON events (run, t, seq, src)",
    """CREATE TABLE quarantine (
        id INTEGER PRIMARY KEY,
        received_at INTEGER NOT NULL,
        origin TEXT NOT NULL,
        reason TEXT NOT NULL,
        raw BLOB NOT NULL
    )""",
    """CREATE TABLE checkpoints (
        id INTEGER PRIMARY KEY,
        run TEXT NOT NULL,
        count INTEGER NOT NULL,
        head TEXT NOT NULL,
        created_at INTEGER NOT NULL
    )""",
    "CREATE INDEX checkpoints_by_run ON checkpoints (run, id)",
    """CREATE TABLE rulebooks (
        sha256 TEXT PRIMARY KEY,
        name TEXT NOT NULL,
        version TEXT NOT NULL,
        text TEXT NOT NULL
    )""",
    *(trigger for table in ("events", "quarantine", "checkpoints", "rulebooks") for trigger in _append_only(table)),
)

# v2: checkpoints carry the Merkle root of the events they cover, the Merkle frontier (so a
# reopened store extends the tree without rereading the run) and the count of the run's
# previous checkpoint (so a checkpoint removed from the middle is noticed). Checkpoints written
# by v1 have none of these; legacy_checkpoints records the last of them, and verify demands the
# new columns of every later one. Rulebooks gain the time they were stored.
_V2 = (
    "ALTER TABLE checkpoints ADD COLUMN merkle_root TEXT",
    "ALTER TABLE checkpoints ADD COLUMN frontier TEXT",
    "ALTER TABLE checkpoints ADD COLUMN prev_count INTEGER",
    "CREATE TABLE legacy_checkpoints (through_id INTEGER NOT NULL)",
    "INSERT INTO legacy_checkpoints SELECT coalesce(max(id), 0) FROM checkpoints",
    *_append_only("legacy_checkpoints"),
    "ALTER TABLE rulebooks ADD COLUMN stored_at INTEGER",
    "CREATE INDEX rulebooks_by_name ON rulebooks (name, version)",
)

# The kinds recorded many times a second per source. Every other kind is indexed by kind too,
# so that the reasoner finds a run's potential violations, observations, decisions, spawns and
# ADS events without reading past millions of states; the dense ones are left out of that index
# so that it costs the append path little (a partial index: queries must repeat its WHERE term,
# see queries.select_events).
DENSE_KINDS = ("entity.state", "vehicle.perception", "vehicle.trace")
_NOT_IN = "kind NOT IN (" + ", ".join(f"'{k}'" for k in DENSE_KINDS) + ")"
_V3 = (f"CREATE INDEX events_by_kind ON events (run, kind, t, seq, src) WHERE {_NOT_IN}",)

# The same index with its condition as a chain of <>: SQLite tests it on every insert, and the
# NOT IN list cost the append 1.2-2 us an event more (bench/append.py, measured interleaved).
SPARSE_ONLY = " AND ".join(f"kind <> '{k}'" for k in DENSE_KINDS)
_V4 = ("DROP INDEX events_by_kind",
       f"CREATE INDEX events_by_kind ON events (run, kind, t, seq, src) WHERE {SPARSE_ONLY}")

# The index holds the event too (a covering index), so that a read by kind goes through it in
# order instead of looking each row up in the table: the reasoner's pass over a run's 506,214
# observations read in 0.64 s instead of 1.4-3.8 s. The cost, the sparse events stored twice,
# is measured by bench/append.py.
_V5 = ("DROP INDEX events_by_kind",
       f"CREATE INDEX events_by_kind ON events (run, kind, t, seq, src, event) WHERE {SPARSE_ONLY}")

# v6: what the ingest notices on the wire beside the events (store/liveliness.py): liveliness
# tokens appearing and disappearing, and samples lost beyond a publisher's cache. Append-only,
# outside the hash chains (they are the ingest's observations, not a source's events).
_V6 = (*liveliness.DDL, *(trigger for table in liveliness.TABLES for trigger in _append_only(table)))

# v7: the wire tables become hash chains, verified by `gaps verify` (store/liveliness.py): their
# rows are read by the reasoner's missing-evidence finding, so an edit must not pass unnoticed.
_V7_LIVELINESS = (*liveliness.DDL_V7, *_append_only("wire_legacy"), *_append_only("wire_checkpoints"))

# v7: a bounded quarantine (store/quarantine.py). A refusal identical to a kept one (same sha256
# of its bytes, source and reason: the unique index; the source is the origin without a place in
# a file) is counted on that row, whose count, last_at and last_origin are then all an UPDATE may
# change, count and last_at only upwards. Past the cap, refusals are counted
# per source in quarantine_overflow (which only grows). Rows are removed only by a prune recorded
# first in quarantine_prunes (append-only): the DELETE trigger lets a row go only if the latest
# prune record covers it (its id and last refusal time), so a bare DELETE is still refused. Rows
# kept before v7 have no digest (NULL: never merged with a later repeat) and count 1.
_V7_QUARANTINE = (
    "ALTER TABLE quarantine ADD COLUMN digest TEXT",
    "ALTER TABLE quarantine ADD COLUMN count INTEGER NOT NULL DEFAULT 1",
    "ALTER TABLE quarantine ADD COLUMN last_at INTEGER",
    "ALTER TABLE quarantine ADD COLUMN source TEXT",
    "ALTER TABLE quarantine ADD COLUMN last_origin TEXT",
    "CREATE UNIQUE INDEX quarantine_repeats ON quarantine (digest, source, reason)",
    "DROP TRIGGER quarantine_no_update",
    "CREATE TRIGGER quarantine_no_update BEFORE UPDATE ON quarantine WHEN NEW.id IS NOT OLD.id "
    "OR NEW.received_at IS NOT OLD.received_at OR NEW.origin IS NOT OLD.origin OR NEW.reason IS NOT OLD.reason "
    "OR NEW.raw IS NOT OLD.raw OR NEW.digest IS NOT OLD.digest OR NEW.source IS NOT OLD.source "
    "OR NEW.count < OLD.count OR (NEW.last_origin IS NOT OLD.last_origin AND NEW.count = OLD.count) "
    "OR coalesce(NEW.last_at, 0) < coalesce(OLD.last_at, OLD.received_at) "
    "BEGIN SELECT RAISE(ABORT, 'append-only: quarantine rows cannot be updated, but for counting a repeat (count and last_at grow)'); END",
    """CREATE TABLE quarantine_prunes (
        id INTEGER PRIMARY KEY,
        pruned_at INTEGER NOT NULL,
        before INTEGER NOT NULL,
        through_id INTEGER NOT NULL,
        rows INTEGER NOT NULL,
        samples INTEGER NOT NULL,
        bytes INTEGER NOT NULL,
        first_at INTEGER,
        last_at INTEGER,
        digest TEXT NOT NULL,
        summary TEXT NOT NULL
    )""",
    *_append_only("quarantine_prunes"),
    "DROP TRIGGER quarantine_no_delete",
    "CREATE TRIGGER quarantine_no_delete BEFORE DELETE ON quarantine WHEN NOT EXISTS (SELECT 1 FROM "
    "quarantine_prunes p WHERE p.id = (SELECT max(id) FROM quarantine_prunes) AND OLD.id <= p.through_id "
    "AND coalesce(OLD.last_at, OLD.received_at) < p.before) "
    "BEGIN SELECT RAISE(ABORT, 'append-only: quarantine rows cannot be deleted, but by a recorded prune "
    "(gaps quarantine --prune)'); END",
    """CREATE TABLE quarantine_overflow (
        origin TEXT PRIMARY KEY,
        samples INTEGER NOT NULL,
        bytes INTEGER NOT NULL,
        first_at INTEGER NOT NULL,
        last_at INTEGER NOT NULL
    )""",
    "CREATE TRIGGER quarantine_overflow_no_update BEFORE UPDATE ON quarantine_overflow WHEN "
    "NEW.origin IS NOT OLD.origin OR NEW.samples < OLD.samples OR NEW.bytes < OLD.bytes "
    "OR NEW.first_at IS NOT OLD.first_at OR NEW.last_at < OLD.last_at "
    "BEGIN SELECT RAISE(ABORT, 'append-only: quarantine_overflow counts only grow'); END",
    "CREATE TRIGGER quarantine_overflow_no_delete BEFORE DELETE ON quarantine_overflow "
    "BEGIN SELECT RAISE(ABORT, 'append-only: quarantine_overflow rows cannot be deleted'); END",
)

# v7: checkpoints signed by the ingest's checkpoint key (store/tree_heads.py): the Ed25519
# signature (base64) of the checkpoint's tree head statement, and the signing key's id. Null on
# checkpoints written without a key, and on every checkpoint written before v7.
_V7_CHECKPOINT_SIGNATURES = (
    "ALTER TABLE checkpoints ADD COLUMN signature TEXT",
    "ALTER TABLE checkpoints ADD COLUMN key_id TEXT",
)
_V7 = (*_V7_CHECKPOINT_SIGNATURES, *_V7_LIVELINESS, *_V7_QUARANTINE)

# v8: each checkpoint records where the wire tables' chains stood when it was written (their last
# row and its hash, as the JSON of store/wire_ends.py), which the checkpoint key signs with the
# run's tree head: rows cut off the end of a wire table, with their wire checkpoints, are then
# caught by a witness and by the key (issue 15). NULL on every checkpoint written before v8.
_V8 = ("ALTER TABLE checkpoints ADD COLUMN wire TEXT",)

MIGRATIONS: dict[int, tuple[str, ...]] = {1: _V1, 2: _V2, 3: _V3, 4: _V4, 5: _V5, 6: _V6, 7: _V7, 8: _V8}
SCHEMA_VERSION = max(MIGRATIONS)


def current_version(conn: sqlite3.Connection) -> int:
    row = conn.execute("SELECT max(version) FROM schema_version").fetchone()
    return row[0] or 0


def migrate(conn: sqlite3.Connection) -> int:
    """Create or upgrade the schema; return the version the file is now at.

    The connection must be in autocommit mode (isolation_level=None): transactions are explicit.
    """
    conn.execute("BEGIN IMMEDIATE")
    try:
        conn.execute("CREATE TABLE IF NOT EXISTS schema_version (version INTEGER NOT NULL)")
        version = current_version(conn)
        if version > SCHEMA_VERSION:
            raise StoreError(
                f"store schema version {version} is newer than this code understands ({SCHEMA_VERSION})"
            )
        for step in range(version + 1, SCHEMA_VERSION + 1):
            for statement in MIGRATIONS[step]:
                conn.execute(statement)
            conn.execute("INSERT INTO schema_version (version) VALUES (?)", (step,))
        conn.execute("COMMIT")
    except BaseException:
        if conn.in_transaction:   # a signal (SIGTERM, Ctrl-C) raised just after the COMMIT finds none
            conn.execute("ROLLBACK")
        raise
    return SCHEMA_VERSION
