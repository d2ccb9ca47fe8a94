"""Rulebooks, stored content-addressed: the key is the sha256 of the LE text.

A run names the rulebooks it was judged by with their hashes, so it can be re-judged with
exactly those rules years later; names and versions are for people looking one up.
"""

from __future__ import annotations

import hashlib
import re
import sqlite3
import time
from typing import Any

_COLUMNS = "sha256, name, version, text"
_DIGITS = re.compile(r"([0-9]+)")


def address_of(text: str) -> str:
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


def put(conn: sqlite3.Connection, name: str, version: str, text: str) -> str:
    """Store a rulebook (inside the caller's transaction); the same text again changes nothing."""
    address = address_of(text)
    conn.execute(
        "INSERT OR IGNORE INTO rulebooks (sha256, name, version, text, stored_at) VALUES (?, ?, ?, ?, ?)",
        (address, name, version, text, time.time_ns()),
    )
    return address


def by_hash(conn: sqlite3.Connection, sha256: str) -> dict[str, Any] | None:
    row = conn.execute(f"SELECT {_COLUMNS} FROM rulebooks WHERE sha256 = ?", (sha256,)).fetchone()
    return None if row is None else _checked(row)


def by_name(conn: sqlite3.Connection, name: str, version: str | None) -> dict[str, Any] | None:
    """The rulebook of this name and version; without a version, the newest: the highest
    version compared part by part, numbers as numbers ("2024.10" after "2024.9"), and among
    equal versions the one stored last."""
    if version is not None:
        row = conn.execute(
            f"SELECT {_COLUMNS} FROM rulebooks WHERE name = ? AND version = ? ORDER BY rowid DESC LIMIT 1",
            (name, version),
        ).fetchone()
        return None if row is None else _checked(row)
    rows = conn.execute(f"SELECT rowid, {_COLUMNS} FROM rulebooks WHERE name = ?", (name,)).fetchall()
    if not rows:
        return None
    newest = max(rows, key=lambda row: (version_key(row[3]), row[0]))
    return _checked(newest[1:])


def listing(conn: sqlite3.Connection) -> list[dict[str, Any]]:
    """Every rulebook without its text, by name and then version, oldest version first."""
    rows = conn.execute(
        "SELECT rowid, sha256, name, version, stored_at, length(CAST(text AS BLOB)) FROM rulebooks"
    ).fetchall()
    rows.sort(key=lambda row: (row[2], version_key(row[3]), row[0]))
    return [
        {"sha256": sha, "name": name, "version": version, "stored_at": stored_at, "bytes": size}
        for _, sha, name, version, stored_at, size in rows
    ]


def version_key(version: str) -> tuple:
    """Sort key of a version string: digit runs compare as numbers, the rest as text."""
    parts = (part for part in _DIGITS.split(version) if part)
    return tuple((0, int(part)) if _DIGITS.fullmatch(part) else (1, part) for part in parts)


def _checked(row: tuple) -> dict[str, Any]:
    """A rulebook as a dict, refused (ValueError) if its text no longer hashes to its address."""
    sha256, name, version, text = row
    if address_of(text) != sha256:
        raise ValueError(f"rulebook {sha256} does not match its text: the store was altered; run verify")
    return {"sha256": sha256, "name": name, "version": version, "text": text}
