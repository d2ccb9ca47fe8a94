"""The stored rulebooks as a hash chain, recomputed from the table's rows, whose end every
checkpoint records (issue 15: "evidence that holds up", the last gap).

A rulebook's text is proven by its address (the sha256 of the text), but the rest of its row is
evidence too: a run's events may cite a rulebook by address only, and the reasoner then loads
the text from this table (a row removed: a stage falls back to another rulebook, a verdict may
change), and a report shows the table's version when the run's `run.start` records none (a
version or name changed: the report changes). So the table is chained, in rowid order (the
order rows were put: the append-only triggers refuse DELETE, so rowids run 1, 2, 3 ... and the
last rowid is the number of rows; SQLite's VACUUM keeps that numbering, there being no gaps):
each link is sha256(previous hash || canonical JSON of {table, id (the rowid), sha256, name,
version, text_sha256 (recomputed from the text), stored_at}), the chain starting from GENESIS.
No hash is stored in the table (no schema change): the chain exists as recomputed, and what
anchors it is its end (last rowid, head) in every checkpoint's `wire` part, beside the wire
tables' ends (store/wire_ends.py), signed with the run's tree head.
"""
from __future__ import annotations

import hashlib
import sqlite3
from typing import Any, Iterator

from .canonical import canonical_json
from .chain import GENESIS, link

TABLE = "rulebooks"
_ROWS = "SELECT rowid, sha256, name, version, text, stored_at FROM rulebooks WHERE rowid > ? ORDER BY rowid"


def row_hash(prev: bytes, rowid: Any, sha256: Any, name: Any, version: Any, text: Any, stored_at: Any) -> bytes:
    """The link of one row after `prev`; TypeError for a value no put writes (text that is not a
    string, or not UTF-8): nothing from that row on can match what a checkpoint records."""
    if not isinstance(text, str):
        raise TypeError(f"a rulebook's text is {type(text).__name__}, not text")
    row = {"table": TABLE, "id": rowid, "sha256": sha256, "name": name, "version": version,
           "text_sha256": hashlib.sha256(text.encode("utf-8")).hexdigest(), "stored_at": stored_at}
    return link(prev, canonical_json(row))


def recomputed(conn: sqlite3.Connection, after: int = 0, prev: bytes | None = GENESIS) -> Iterator[tuple[Any, str]]:
    """(rowid, chain hash after that row, hex) for every row past `after` (`prev` being the hash
    after row `after`, None if the chain broke before), recomputed from the columns; from a value
    no put writes on, "" (which no recorded head equals)."""
    head: bytes | None = prev
    for rowid, *values in conn.execute(_ROWS, (after,)):
        if head is not None:
            try:
                head = row_hash(head, rowid, *values)
            except (TypeError, ValueError):  # bytes where text belongs, a lone surrogate
                head = None
        yield rowid, "" if head is None else head.hex()


def end(conn: sqlite3.Connection) -> tuple[int, str]:
    """The chain's end as the table stands: (last rowid, 0 when empty; its head, hex)."""
    last, head = 0, GENESIS.hex()
    for last, head in recomputed(conn):
        pass
    return last, head


class RulebookTip:
    """A writer's running end of the chain, so that an append hashes only the rows put since the
    previous one (one index probe when none was), not every stored text again. Forgotten, like
    the runs' heads (store/heads.py), when a transaction rolls back or another connection
    commits: then the next append recomputes it from the table."""

    def __init__(self) -> None:
        self._end: tuple[int, str] | None = None

    def forget(self) -> None:
        self._end = None

    def end(self, conn: sqlite3.Connection) -> tuple[int, str]:
        """(last rowid, head) now: call inside the write transaction whose checkpoints record it."""
        if self._end is None:
            self._end = end(conn)
            return self._end
        last, head = self._end
        for last, head in recomputed(conn, last, bytes.fromhex(head) if head else None):
            pass
        self._end = (last, head)
        return self._end
