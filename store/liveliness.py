"""What the ingest noticed about its sources on the wire, beside the events: when each source's
liveliness token appeared and disappeared, and samples a publisher's sequence numbers say were
missed and its cache could no longer give.

These are the ingest's own observations, not events a source sent, so they are kept in their own
append-only tables and stay out of the hash chains: two ingests of one stream notice at different
wall-clock moments, and a chain must come out the same in each (and from an export). Times here
are the ingest's wall clock (ns since the epoch) when it learned of the change; an event's ``t`` is
the source's world time, so a change is tied to the events by ``last_seq``: the highest seq of
the source the ingest had received when it noticed.
"""
from __future__ import annotations

import sqlite3
from dataclasses import dataclass
from typing import Any, Iterable

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


def insert_changes(conn: sqlite3.Connection, changes: Iterable[LivelinessChange]) -> None:
    conn.executemany("INSERT INTO liveliness (run, src, alive, at, last_seq) VALUES (?, ?, ?, ?, ?)",
                     [(c.run, c.src, int(c.alive), c.at, c.last_seq) for c in changes])


def insert_misses(conn: sqlite3.Connection, misses: Iterable[WireMiss]) -> None:
    conn.executemany("INSERT INTO wire_misses (run, src, kind, count, at, after_seq) VALUES (?, ?, ?, ?, ?, ?)",
                     [(m.run, m.src, m.kind, m.count, m.at, m.after_seq) for m in misses])


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
