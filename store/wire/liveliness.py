"""What the ingest noticed about its sources on the wire, beside the events: when each source's
liveliness token appeared and disappeared, and samples a publisher's sequence numbers say were
missed and its cache could no longer give.

These are the ingest's own observations, not events a source sent, so they are kept in their own
append-only tables and stay out of the hash chains: two ingests of one stream notice at different
wall-clock moments, and a chain must come out the same in each (and from an export). Times here
are the ingest's wall clock (ns since the epoch) when it learned of the change; an event's ``t`` is
the source's world time, so a change is tied to the events by ``last_seq``: the highest seq of
the source the ingest had received when it noticed.

They are evidence all the same: the reasoner's missing-evidence finding ("stopped publishing at
...") reads them. So since schema v7 each table is a hash chain of its own, in id order: a row's
`hash` is sha256 of the previous row's stored hash and the row's canonical JSON (its table, id and
columns), and `gaps verify` recomputes every link (wire_problem). Every write ends with a
checkpoint in `wire_checkpoints` (the table, its last id and head), so that rows cut off the end
show as rows no checkpoint covers, as for the events. Rows written before v7 carry no hash;
`wire_legacy` records up to which id, and every later row must carry one. Like the events'
chains, the rows cut back to a checkpoint together with the checkpoints after it, or a whole table
rewritten with its hashes recomputed, cannot be seen from the file alone: since v8 each run's
checkpoint records where both chains stood (store/wire_ends.py), signed with its tree head, so a
witness and the checkpoint key show it (issue 15, "Anchored checkpoints").
"""
from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from typing import Any, Iterable

from ..canonical import canonical_json
from ..chain import GENESIS, link

DDL = (
    """CREATE TABLE liveliness (
        id INTEGER PRIMARY KEY,
        run TEXT NOT NULL,
        src TEXT NOT NULL,
        alive INTEGER NOT NULL,
        at INTEGER NOT NULL,
        last_seq INTEGER
    )""",
    "CREATE INDEX liveliness_by_source ON liveliness (run, src, id)",
    """CREATE TABLE wire_misses (
        id INTEGER PRIMARY KEY,
        run TEXT NOT NULL,
        src TEXT NOT NULL,
        kind TEXT NOT NULL,
        count INTEGER NOT NULL,
        at INTEGER NOT NULL,
        after_seq INTEGER
    )""",
    "CREATE INDEX wire_misses_by_source ON wire_misses (run, src, id)",
)
TABLES = ("liveliness", "wire_misses")
_COLUMNS = {"liveliness": ("run", "src", "alive", "at", "last_seq"),
            "wire_misses": ("run", "src", "kind", "count", "at", "after_seq")}

# v7: the tables chained (see above); `wire_legacy` holds, per table, the last id written before.
DDL_V7 = (
    *(f"ALTER TABLE {table} ADD COLUMN hash TEXT" for table in TABLES),
    "CREATE TABLE wire_legacy (tbl TEXT NOT NULL, through_id INTEGER NOT NULL)",
    "CREATE TABLE wire_checkpoints (id INTEGER PRIMARY KEY, tbl TEXT NOT NULL, through_id INTEGER NOT NULL, "
    "head TEXT NOT NULL)",
    *(f"INSERT INTO wire_legacy SELECT '{table}', coalesce(max(id), 0) FROM {table}" for table in TABLES),
)


@dataclass(frozen=True, slots=True)
class LivelinessChange:
    """A source's liveliness token appeared (``alive``) or disappeared, as the ingest saw it."""

    run: str
    src: str
    alive: bool
    at: int
    """The ingest's wall clock when it noticed (ns since the epoch)."""
    last_seq: int | None
    """The source's highest seq the ingest had received then (None: nothing yet)."""

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "src": self.src, "alive": self.alive, "at": self.at, "last_seq": self.last_seq}


@dataclass(frozen=True, slots=True)
class WireMiss:
    """Samples of one publisher (a source's kind) that its sequence numbers say were sent and that
    neither arrived nor could be fetched from its cache: lost, with where they were."""

    run: str
    src: str
    kind: str
    count: int
    at: int
    """The ingest's wall clock when it gave them up (ns since the epoch)."""
    after_seq: int | None
    """The source's highest seq the ingest had received then: the lost events come after it."""

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "src": self.src, "kind": self.kind, "count": self.count, "at": self.at,
                "after_seq": self.after_seq}


@dataclass(frozen=True, slots=True)
class SourceLife:
    """One source's liveliness as recorded: when its token was first and last seen to appear, and
    when it last disappeared (None if it never did, or came back after)."""

    run: str
    src: str
    appeared_at: int | None
    disappeared_at: int | None
    last_seq: int | None
    """The source's highest seq received when the token disappeared (None when it is alive)."""
    changes: int

    @property
    def alive(self) -> bool:
        """Whether its token was present at the last change the ingest recorded."""
        return self.disappeared_at is None and self.appeared_at is not None

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "src": self.src, "alive": self.alive, "appeared_at": self.appeared_at,
                "disappeared_at": self.disappeared_at, "last_seq": self.last_seq, "changes": self.changes}


def row_hash(table: str, prev: bytes, id_: Any, values: tuple) -> bytes:
    """The link of one row: its table, id and columns as canonical JSON, after the previous hash."""
    row = {"table": table, "id": id_, **dict(zip(_COLUMNS[table], values))}
    return link(prev, canonical_json(row))


def _append(conn: sqlite3.Connection, table: str, rows: list[tuple]) -> None:
    """Insert rows at the chain's end, each with its id and link (inside the caller's write
    transaction, which holds the lock: the end read is the end written after)."""
    last = conn.execute(f"SELECT id, hash FROM {table} ORDER BY id DESC LIMIT 1").fetchone()
    id_, prev = (0, GENESIS) if last is None else (last[0], bytes.fromhex(last[1]) if last[1] else GENESIS)
    out = []
    for values in rows:
        id_ += 1
        prev = row_hash(table, prev, id_, values)
        out.append((id_, *values, prev.hex()))
    columns = ", ".join(("id", *_COLUMNS[table], "hash"))
    conn.executemany(f"INSERT INTO {table} ({columns}) VALUES ({', '.join('?' * (len(_COLUMNS[table]) + 2))})", out)
    if out:
        conn.execute("INSERT INTO wire_checkpoints (tbl, through_id, head) VALUES (?, ?, ?)", (table, id_, prev.hex()))


def insert_changes(conn: sqlite3.Connection, changes: Iterable[LivelinessChange]) -> None:
    _append(conn, "liveliness", [(c.run, c.src, int(c.alive), c.at, c.last_seq) for c in changes])


def insert_misses(conn: sqlite3.Connection, misses: Iterable[WireMiss]) -> None:
    _append(conn, "wire_misses", [(m.run, m.src, m.kind, m.count, m.at, m.after_seq) for m in misses])


def wire_problem(conn: sqlite3.Connection) -> dict[str, Any] | None:
    """The first thing wrong with either table's chain, as verify reports a problem; None if all
    hold. Each link is recomputed from the stored hash of the row before, so the row named is the
    one changed (or the one after a row removed); each checkpoint must name a row and its head,
    and the last must name the last row."""
    for table in TABLES:
        what = _table_problem(conn, table)
        if what is not None:
            return {"run": None, "src": None, "seq": None, "chain_pos": None,
                    "what": what + ": the liveliness findings cannot be relied on"}
    return None


def _legacy_through(conn: sqlite3.Connection, table: str) -> int:
    """The last id of the table written before its chain began (v7), 0 if none."""
    (through,) = conn.execute("SELECT min(through_id) FROM wire_legacy WHERE tbl = ?", (table,)).fetchone()
    return through if isinstance(through, int) else 0


def chain_rows(conn: sqlite3.Connection, table: str) -> tuple[int, Iterable[tuple]]:
    """The table's legacy bound and every row as (id, columns ..., hash), in id order: for
    recomputing the chain elsewhere (store/wire_ends.py)."""
    return _legacy_through(conn, table), conn.execute(
        f"SELECT id, {', '.join(_COLUMNS[table])}, hash FROM {table} ORDER BY id")


def _table_problem(conn: sqlite3.Connection, table: str) -> str | None:
    through = _legacy_through(conn, table)
    marks: dict[int, str] = {}  # through_id -> head (hex)
    for mark_id, at, head in conn.execute("SELECT id, through_id, head FROM wire_checkpoints WHERE tbl = ? "
                                          "ORDER BY id", (table,)):
        if at in marks or (marks and at <= max(marks)):
            return f"{table}: wire checkpoint {mark_id} is out of order or recorded twice"
        marks[at] = head
    prev, last = GENESIS, through
    rows = conn.execute(f"SELECT id, {', '.join(_COLUMNS[table])}, hash FROM {table} WHERE id > ? ORDER BY id",
                        (through,))
    for id_, *values, stored in rows:
        if stored != row_hash(table, prev, id_, tuple(values)).hex():
            return (f"{table} row {id_} (run {values[0]!r}, src {values[1]!r}) does not match its hash chain: it "
                    "was altered, inserted or the row before it removed behind the store's back")
        if id_ in marks and marks.pop(id_) != stored:
            return f"{table}: the checkpoint of row {id_} records another head than the chain's"
        prev, last = bytes.fromhex(stored), id_
    if marks:
        return f"{table}: a checkpoint names row {min(marks)}, which the chain does not hold: rows were removed"
    covered = conn.execute("SELECT max(through_id) FROM wire_checkpoints WHERE tbl = ?", (table,)).fetchone()[0]
    if last > through and covered != last:
        return f"{table} row {last} is not covered by any wire checkpoint: rows or checkpoints were added or removed"
    return None


def changes(conn: sqlite3.Connection, run: str, src: str | None = None) -> list[LivelinessChange]:
    """A run's recorded changes (of one source), in the order noticed."""
    where, params = ("run = ?", (run,)) if src is None else ("run = ? AND src = ?", (run, src))
    rows = conn.execute(f"SELECT run, src, alive, at, last_seq FROM liveliness WHERE {where} ORDER BY id", params)
    return [LivelinessChange(r, s, bool(a), at, last) for r, s, a, at, last in rows]


def lives(conn: sqlite3.Connection, run: str) -> list[SourceLife]:
    """Per source of the run with any recorded change: first appearance, last disappearance."""
    found: dict[str, list[LivelinessChange]] = {}
    for change in changes(conn, run):
        found.setdefault(change.src, []).append(change)
    return [_life(run, src, seen) for src, seen in sorted(found.items())]


def _life(run: str, src: str, seen: list[LivelinessChange]) -> SourceLife:
    last = seen[-1]
    appeared = next((c.at for c in seen if c.alive), None)
    gone = None if last.alive else last
    return SourceLife(run, src, appeared, gone.at if gone else None, gone.last_seq if gone else None, len(seen))


def misses(conn: sqlite3.Connection, run: str | None = None) -> list[WireMiss]:
    """Samples recorded as lost on the wire (of one run), in the order noticed."""
    where, params = ("WHERE run = ?", (run,)) if run is not None else ("", ())
    rows = conn.execute(f"SELECT run, src, kind, count, at, after_seq FROM wire_misses {where} ORDER BY id", params)
    return [WireMiss(*row) for row in rows]
