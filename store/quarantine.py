"""The quarantine, kept bounded: a repeat counted on one row, a cap on what is kept, recorded prunes.

Hostile input is cheap to send and the quarantine keeps every refusal's bytes: 10 MB of junk lines
once became 5.2 million rows (570 MB) that nothing could remove (issue 15, finding 6). Three rules
bound it without losing count of anything:

- a refusal identical to a kept one (same source, reason and sha256 of the bytes) adds one to that
  row's ``count`` and moves its ``last_at`` and ``last_origin``; it keeps no second copy. The source
  is the origin without its place in a file (``run.jsonl:17`` is from ``run.jsonl``; see
  ``source_of``): the same junk line repeated down a file is one row, as on one Zenoh key;
- past a cap (rows and bytes, ``QuarantineCap``) a new refusal's bytes are not kept: it is counted,
  per source, in ``quarantine_overflow`` (samples, bytes, first and last time), and the caller is told;
- ``prune`` removes rows only together with a record in ``quarantine_prunes`` of what it removed
  (rows, samples, bytes, time span, counts per reason and origin, a digest of the rows' ids, byte
  digests and counts), written in the same transaction. The DELETE trigger lets a row go only if the
  latest prune record covers it, so a bare DELETE is refused (store/ddl.py, ``_V7_QUARANTINE``).
"""
from __future__ import annotations

import hashlib
import json
import re
import sqlite3
from collections import Counter
from dataclasses import dataclass
from datetime import datetime, timezone
from typing import Any

from .errors import StoreError

OVERFLOW_ORIGINS = 10_000   # origins counted one by one past the cap; the rest share OTHER_ORIGINS
OTHER_ORIGINS = "(other origins)"
SUMMARY_KEYS = 50           # reasons and origins named in a prune's summary; the rest are summed
OTHERS = "(others)"

_REPEAT = ("UPDATE quarantine SET count = count + 1, last_at = max(coalesce(last_at, received_at), ?), "
           "last_origin = ? WHERE digest = ? AND source = ? AND reason = ?")
_INSERT = ("INSERT INTO quarantine (received_at, origin, reason, raw, digest, count, last_at, source, last_origin) "
           "VALUES (?, ?, ?, ?, ?, 1, ?, ?, ?)")
_PLACE = re.compile(r"(?::\d+|:message \d+ \(.*\))$")
_OVERFLOW = ("INSERT INTO quarantine_overflow (origin, samples, bytes, first_at, last_at) VALUES (?, 1, ?, ?, ?) "
             "ON CONFLICT (origin) DO UPDATE SET samples = samples + 1, bytes = bytes + excluded.bytes, "
             "last_at = max(last_at, excluded.last_at)")
_LAST_AT = "coalesce(last_at, received_at)"


@dataclass(frozen=True)
class QuarantineCap:
    """How much the quarantine keeps: rows, and bytes of what was received. Past either, refusals
    are counted, not kept. The defaults hold a day of a badly broken fleet (a million distinct
    refusals) in well under a gigabyte."""

    rows: int = 1_000_000
    bytes: int = 512 * 2**20

    def __post_init__(self) -> None:
        if self.rows < 1 or self.bytes < 1:
            raise ValueError(f"a quarantine cap must be at least one row and one byte, not {self.rows}, {self.bytes}")


@dataclass(frozen=True)
class Kept:
    """What one append did with its refusals: new rows, repeats counted on a row, and refusals
    past the cap (counted in quarantine_overflow, bytes not kept)."""

    new: int = 0
    repeats: int = 0
    over_cap: int = 0


class QuarantineTally:
    """The rows and bytes the quarantine holds, counted once and then kept up to date by this
    connection's appends; ``forget`` when another connection wrote or a transaction failed."""

    def __init__(self, conn: sqlite3.Connection) -> None:
        self._conn = conn
        self._held: tuple[int, int] | None = None

    def forget(self) -> None:
        self._held = None

    def held(self) -> tuple[int, int]:
        if self._held is None:
            rows, size = self._conn.execute("SELECT count(*), coalesce(sum(length(raw)), 0) FROM quarantine").fetchone()
            self._held = (rows, size)
        return self._held

    def add(self, size: int) -> None:
        rows, total = self.held()
        self._held = (rows + 1, total + size)


def keep(conn: sqlite3.Connection, refused: list[tuple], cap: QuarantineCap, tally: QuarantineTally) -> Kept:
    """Write refusals (received_at, origin, reason, raw) inside the caller's transaction: a repeat
    is counted on its row, a new one kept while the cap allows, else counted as over the cap."""
    new = repeats = over = 0
    for received_at, origin, reason, raw in refused:
        digest, source = hashlib.sha256(raw).hexdigest(), source_of(origin)
        if conn.execute(_REPEAT, (received_at, origin, digest, source, reason)).rowcount:
            repeats += 1
            continue
        rows, size = tally.held()
        if rows + 1 > cap.rows or size + len(raw) > cap.bytes:
            _count_overflow(conn, received_at, source, len(raw))
            over += 1
            continue
        conn.execute(_INSERT, (received_at, origin, reason, raw, digest, received_at, source, origin))
        tally.add(len(raw))
        new += 1
    return Kept(new, repeats, over)


def source_of(origin: str) -> str:
    """Where a refusal came from, without its place there: a JSONL file's ``:LINE`` and an MCAP
    file's ``:message N (log_time T, ...)`` are dropped; a Zenoh key is its own source."""
    return _PLACE.sub("", origin)


def _count_overflow(conn: sqlite3.Connection, at: int, origin: str, size: int) -> None:
    """Count one refusal past the cap under its source (or OTHER_ORIGINS once OVERFLOW_ORIGINS are
    counted: hostile input may invent origins too)."""
    known = conn.execute("SELECT 1 FROM quarantine_overflow WHERE origin = ?", (origin,)).fetchone()
    if known is None and conn.execute("SELECT count(*) FROM quarantine_overflow").fetchone()[0] >= OVERFLOW_ORIGINS:
        origin = OTHER_ORIGINS
    conn.execute(_OVERFLOW, (origin, size, at, at))


@dataclass(frozen=True)
class Pruned:
    """One recorded prune: what it removed, summarised (the row of quarantine_prunes)."""

    id: int
    pruned_at: int
    before: int          # rows whose last refusal was before this time (ns) were removed
    through_id: int      # ... and whose id is at most this
    rows: int
    samples: int         # refusals those rows stood for (their counts summed)
    bytes: int
    first_at: int | None
    last_at: int | None
    digest: str          # sha256 over "id sha256(raw) count\n" of each row removed, in id order
    by_reason: dict[str, int]
    by_origin: dict[str, int]

    def to_json(self) -> dict[str, Any]:
        return dict(self.__dict__)


def prune(conn: sqlite3.Connection, before: int, now: int) -> Pruned | None:
    """Remove the quarantine rows whose last refusal came before ``before`` (ns), recording first
    what they were; inside the caller's transaction. None if there was nothing to remove."""
    through = conn.execute("SELECT max(id) FROM quarantine").fetchone()[0]
    if through is None:
        return None
    rows = conn.execute(f"SELECT id, received_at, {_LAST_AT}, coalesce(source, origin), reason, raw, count FROM quarantine "
                        f"WHERE id <= ? AND {_LAST_AT} < ? ORDER BY id", (through, before))
    summary = _Summary()
    for row in rows:
        summary.add(*row)
    if not summary.rows:
        return None
    record = summary.record(now, before, through)
    cur = conn.execute(
        "INSERT INTO quarantine_prunes (pruned_at, before, through_id, rows, samples, bytes, first_at, last_at, "
        "digest, summary) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
        (now, before, through, record.rows, record.samples, record.bytes, record.first_at, record.last_at,
         record.digest, json.dumps({"by_reason": record.by_reason, "by_origin": record.by_origin}, sort_keys=True)))
    gone = conn.execute(f"DELETE FROM quarantine WHERE id <= ? AND {_LAST_AT} < ?", (through, before)).rowcount
    if gone != record.rows:
        raise StoreError(f"a prune removed {gone} quarantine rows, having recorded {record.rows}: nothing was removed")
    return Pruned(**{**record.__dict__, "id": cur.lastrowid})


class _Summary:
    """Running totals of the rows a prune removes."""

    def __init__(self) -> None:
        self.rows = self.samples = self.bytes = 0
        self.first_at: int | None = None
        self.last_at: int | None = None
        self.by_reason: Counter[str] = Counter()
        self.by_origin: Counter[str] = Counter()
        self._digest = hashlib.sha256()

    def add(self, id_: int, received_at: int, last_at: int, origin: str, reason: str, raw: bytes, count: int) -> None:
        raw = bytes(raw)
        self.rows += 1
        self.samples += count
        self.bytes += len(raw)
        self.first_at = received_at if self.first_at is None else min(self.first_at, received_at)
        self.last_at = last_at if self.last_at is None else max(self.last_at, last_at)
        self.by_reason[reason] += count
        self.by_origin[origin] += count
        self._digest.update(f"{id_} {hashlib.sha256(raw).hexdigest()} {count}\n".encode())

    def record(self, now: int, before: int, through: int) -> Pruned:
        return Pruned(0, now, before, through, self.rows, self.samples, self.bytes, self.first_at, self.last_at,
                      self._digest.hexdigest(), _named(self.by_reason), _named(self.by_origin))


def _named(counts: Counter[str]) -> dict[str, int]:
    """The SUMMARY_KEYS largest counts by name, the rest summed under OTHERS."""
    top = dict(counts.most_common(SUMMARY_KEYS))
    rest = sum(counts.values()) - sum(top.values())
    return {**top, OTHERS: rest} if rest else top


def prunes(conn: sqlite3.Connection) -> list[Pruned]:
    """Every recorded prune, oldest first."""
    out = []
    for id_, at, before, through, rows, samples, size, first, last, digest, summary in conn.execute(
            "SELECT id, pruned_at, before, through_id, rows, samples, bytes, first_at, last_at, "
            "digest, summary FROM quarantine_prunes ORDER BY id"):
        counts = json.loads(summary)
        out.append(Pruned(id_, at, before, through, rows, samples, size, first, last, digest,
                          counts["by_reason"], counts["by_origin"]))
    return out


def overflow(conn: sqlite3.Connection) -> list[dict[str, Any]]:
    """Refusals counted past the cap, per origin: {origin, samples, bytes, first_at, last_at}."""
    cur = conn.execute("SELECT origin, samples, bytes, first_at, last_at FROM quarantine_overflow "
                       "ORDER BY samples DESC, origin")
    return [dict(zip(("origin", "samples", "bytes", "first_at", "last_at"), row)) for row in cur]


def held(conn: sqlite3.Connection) -> dict[str, int]:
    """What the quarantine holds: rows, the refusals they stand for (samples) and their bytes."""
    rows, samples, size = conn.execute(
        "SELECT count(*), coalesce(sum(count), 0), coalesce(sum(length(raw)), 0) FROM quarantine").fetchone()
    return {"rows": rows, "samples": samples, "bytes": size}


_AGO = re.compile(r"(\d+(?:\.\d+)?)\s*(s|m|h|d)")
_UNIT_S = {"s": 1, "m": 60, "h": 3600, "d": 86400}


def parse_before(text: str, now_ns: int) -> int:
    """A prune's cut-off as ns: an RFC 3339 time (2026-11-26T08:00:00Z) or an age (7d, 12h, 30m,
    45s: that long before now). ValueError saying what is accepted otherwise."""
    text = text.strip()
    if found := _AGO.fullmatch(text):
        return now_ns - int(float(found[1]) * _UNIT_S[found[2]] * 1e9)
    try:
        moment = datetime.fromisoformat(text)
    except ValueError:
        raise ValueError(f"--before {text!r} is neither a time (2026-11-26T08:00:00Z) nor an age (7d, 12h, 30m, 45s)") \
            from None
    if moment.tzinfo is None:
        raise ValueError(f"--before {text!r} has no time zone: add Z for UTC (2026-11-26T08:00:00Z)")
    return int(moment.astimezone(timezone.utc).timestamp()) * 10**9 + moment.microsecond * 1000
