"""Making an index of a store file disagree with its table, as someone holding the file can.

SQLite keeps an index in step with its table on every write, so a plain UPDATE changes both. To
leave them apart: make the change with the index live (its entry follows), then hide the index
from SQLite (its definition rewritten through `PRAGMA writable_schema` to cover no row, its
pages untouched), put the row back (only the table changes), and restore the definition. The
table then holds what the chain covers, and the index the forgery (issue 15, finding 1).
"""
from __future__ import annotations

import sqlite3
from pathlib import Path

from tests.helpers.store_testkit import tamper


def _definition(path: Path, index: str) -> str:
    conn = sqlite3.connect(path)
    try:
        (sql,) = conn.execute("SELECT sql FROM sqlite_master WHERE type = 'index' AND name = ?", (index,)).fetchone()
        return sql
    finally:
        conn.close()


def _define(path: Path, index: str, sql: str) -> None:
    conn = sqlite3.connect(path, isolation_level=None)
    try:
        conn.execute("PRAGMA writable_schema = ON")
        conn.execute("UPDATE sqlite_master SET sql = ? WHERE type = 'index' AND name = ?", (sql, index))
    finally:
        conn.close()


def split(path: Path, index: str, rowid: int, **forged: object) -> None:
    """Leave `index`'s entry for the row `rowid` with the columns `forged` (column=value), and
    the row itself as it is: the table and the chain agree, the index does not."""
    columns = list(forged)
    conn = sqlite3.connect(path)
    try:
        original = conn.execute(f"SELECT {', '.join(columns)} FROM events WHERE rowid = ?", (rowid,)).fetchone()
    finally:
        conn.close()
    assignments = ", ".join(f"{column} = ?" for column in columns)
    tamper(path, (f"UPDATE events SET {assignments} WHERE rowid = ?", (*forged.values(), rowid)))
    sql = _definition(path, index)
    _define(path, index, sql + (" AND 0" if " WHERE " in sql else " WHERE 0"))
    tamper(path, (f"UPDATE events SET {assignments} WHERE rowid = ?", (*original, rowid)))
    _define(path, index, sql)


def rowid_of(path: Path, run: str, src: str, seq: int) -> int:
    conn = sqlite3.connect(path)
    try:
        (rowid,) = conn.execute("SELECT rowid FROM events WHERE run = ? AND src = ? AND seq = ?",
                                (run, src, seq)).fetchone()
        return rowid
    finally:
        conn.close()
