"""Where the wire tables' hash chains stand, as a checkpoint records it, and whether a store still
holds that.

The liveliness changes and wire misses (store/liveliness.py) are hash chains with checkpoints of
their own in `wire_checkpoints`, in the same file: rows cut off the end together with those
checkpoints, or a table rewritten with its hashes recomputed, leave a file that agrees with
itself. So since schema v8 every checkpoint of a run also records, per wire table, its last row
(`count`: the tables' rows are numbered 1, 2, 3 ... by the appends, so the last id is the number
of rows written) and that row's hash, as they stand in the transaction that writes it; the
checkpoint key signs that with the run's tree head (store/tree_heads.py), and the witness keeps
it. A store still holds such an end if the table's chain, recomputed from the rows' columns, has
that hash at that row: the tables may have grown since, never shrunk or changed.

The part records one more chain, under the key `rulebooks`: the stored rulebooks' chain
(store/rulebook_chain.py), which has no hashes of its own in the file and is recomputed from
the rows, checked the same way (outcomes `rulebooks cut back`, `rulebooks rewritten`). A part
written before it was (no `rulebooks` key) still reads, and checks the wire tables it names: the
rulebooks are then not covered by it.
"""
from __future__ import annotations

import json
import sqlite3
from dataclasses import dataclass
from typing import Any, Iterable

from .. import rulebook_chain
from ..chain import GENESIS, is_digest_hex
from .liveliness import TABLES, chain_rows, row_hash

CUT_BACK = "wire cut back"
REWRITTEN = "wire rewritten"
RULEBOOKS = rulebook_chain.TABLE  # the part's optional key: the stored rulebooks' chain
RULEBOOKS_CUT_BACK = "rulebooks cut back"
RULEBOOKS_REWRITTEN = "rulebooks rewritten"


@dataclass(frozen=True)
class WireEnd:
    """One chain of the wire part at one moment (a wire table's, or the rulebooks'): its last row
    and that row's hash (hex)."""

    table: str
    count: int   # id of the table's last row, 0 for an empty table
    head: str    # that row's hash; GENESIS for none (or a row written before v7, which has none)


def ends_now(conn: sqlite3.Connection, tip: rulebook_chain.RulebookTip | None = None) -> tuple[WireEnd, ...]:
    """Each wire table's end as it stands (two index probes), and the rulebooks' (from a writer's
    running `tip`, else recomputed from the table); inside a write transaction, what the
    checkpoints written in it record."""
    found = []
    for table in TABLES:
        last = conn.execute(f"SELECT id, hash FROM {table} ORDER BY id DESC LIMIT 1").fetchone()
        found.append(WireEnd(table, 0, GENESIS.hex()) if last is None
                     else WireEnd(table, last[0], last[1] or GENESIS.hex()))
    count, head = rulebook_chain.end(conn) if tip is None else tip.end(conn)
    found.append(WireEnd(RULEBOOKS, count, head))
    return tuple(found)


def covers_rulebooks(ends: tuple[WireEnd, ...] | None) -> bool:
    """Whether a wire part records the rulebooks' end (parts written before they were chained do not)."""
    return any(end.table == RULEBOOKS for end in ends or ())


def to_part(ends: tuple[WireEnd, ...]) -> dict[str, dict[str, Any]]:
    """The JSON form a tree head carries: {table: {"count", "head"}}."""
    return {end.table: {"count": end.count, "head": end.head} for end in ends}


def from_part(data: Any) -> tuple[WireEnd, ...]:
    """The ends of a tree head's `wire` part, the wire tables' and, if it has them, the
    rulebooks'; ValueError saying what is wrong with it."""
    if not isinstance(data, dict) or set(data) - {RULEBOOKS} != set(TABLES):
        raise ValueError(f"wire must name the tables {', '.join(TABLES)} (and may name {RULEBOOKS})")
    ends = []
    for table in (*TABLES, *((RULEBOOKS,) if RULEBOOKS in data else ())):
        end = data[table]
        if not isinstance(end, dict) or set(end) != {"count", "head"}:
            raise ValueError(f"wire.{table} must hold count and head")
        count, head = end["count"], end["head"]
        if type(count) is not int or count < 0:
            raise ValueError(f"wire.{table}.count must be a non-negative integer")
        if not is_digest_hex(head):
            raise ValueError(f"wire.{table}.head must be 64 hex digits")
        ends.append(WireEnd(table, count, head))
    return tuple(ends)


def problems(conn: sqlite3.Connection, ends: Iterable[WireEnd]) -> dict[WireEnd, tuple[str, str] | None]:
    """Each end checked against the store: None if its table's chain, recomputed from the rows,
    has that hash at that row; else (outcome, what). One pass over each table asked about."""
    wanted: dict[str, set[WireEnd]] = {}
    for end in ends:
        wanted.setdefault(end.table, set()).add(end)
    found: dict[WireEnd, tuple[str, str] | None] = {}
    for table, its_ends in wanted.items():
        found.update(_table(conn, table, its_ends))
    return found


def first_problem(found: dict[WireEnd, tuple[str, str] | None], ends: Iterable[WireEnd]) -> tuple[str, str] | None:
    """The first of a head's ends that `problems` found wrong, as (outcome, what); None if all hold."""
    return next((found[end] for end in ends if found[end] is not None), None)


def recorded_as(outcome: str) -> str:
    """What a checkpoint recorded, for a problem's account: the rulebooks' end or the wire tables'."""
    return "the rulebooks' end" if outcome in (RULEBOOKS_CUT_BACK, RULEBOOKS_REWRITTEN) else "the wire tables' ends"


def checkpoint_problem(conn: sqlite3.Connection, run: str | None = None) -> str | None:
    """What `gaps verify` says of the wire parts the checkpoints record (of one run): the first
    that is not one, or whose ends the store no longer holds; None if all hold. (Someone holding
    the file can change the checkpoints too: the checkpoint key and a witness catch that.)"""
    where, params = ("AND run = ? ", (run,)) if run is not None else ("", ())
    recorded: list[tuple[Any, Any, tuple[WireEnd, ...]]] = []
    for id_, name, count, text in conn.execute(f"SELECT id, run, count, wire FROM checkpoints WHERE wire IS NOT NULL "
                                               f"{where}ORDER BY id", params):
        try:
            recorded.append((name, count, from_part(json.loads(text) if isinstance(text, str) else None)))
        except (ValueError, RecursionError):
            return f"checkpoint {id_} (run {name!r}, {count} events) records a wire part that is not one"
    found = problems(conn, [end for _, _, ends in recorded for end in ends])
    for name, count, ends in recorded:
        problem = first_problem(found, ends)
        if problem is not None:
            return (f"the checkpoint of {count} events of run {name} records {recorded_as(problem[0])}, and "
                    f"{problem[1]} ({problem[0]})")
    return None


def _table(conn: sqlite3.Connection, table: str, ends: set[WireEnd]) -> dict[WireEnd, tuple[str, str] | None]:
    books = table == RULEBOOKS
    cut_back, rewritten = (RULEBOOKS_CUT_BACK, RULEBOOKS_REWRITTEN) if books else (CUT_BACK, REWRITTEN)
    changed = ("a stored rulebook's address, name, version, text or time was changed, or a rulebook removed or "
               "inserted, up to it" if books else "the table was rewritten up to it")
    by_count: dict[int, list[WireEnd]] = {}
    for end in ends:
        by_count.setdefault(end.count, []).append(end)
    found: dict[WireEnd, tuple[str, str] | None] = {end: None for end in by_count.pop(0, [])}  # empty then
    last = 0
    for id_, recomputed in (rulebook_chain.recomputed(conn) if books else _recomputed(conn, table)):
        last = id_
        for end in by_count.pop(id_, []):
            found[end] = None if recomputed == end.head else (rewritten, (
                f"{table} row {id_} recomputes to hash {_short(recomputed)}, the head records {_short(end.head)}: "
                f"{changed}"))
    for count, missing in by_count.items():
        held = f"its last is {last}" if last else "it holds none"
        for end in missing:
            found[end] = (cut_back, f"{table} holds no row {count} ({held}), which the head records as its last: "
                                    f"rows were removed")
    return found


def _recomputed(conn: sqlite3.Connection, table: str) -> Iterable[tuple[Any, str]]:
    """(id, hash after that row) for every row, the hash recomputed from the row's columns; rows
    before the chain began (wire_legacy) give GENESIS, as the appends treat them. After a value no
    append writes (not JSON: a blob), no hash is recomputed: nothing from it on matches a head."""
    through, rows = chain_rows(conn, table)
    prev: bytes | None = GENESIS
    for id_, *values, _ in rows:
        if isinstance(id_, int) and id_ <= through:
            yield id_, GENESIS.hex()
            continue
        if prev is not None:
            try:
                prev = row_hash(table, prev, id_, tuple(values))
            except (TypeError, ValueError):
                prev = None
        yield id_, "" if prev is None else prev.hex()


def _short(head: str) -> str:
    return f"{head[:12]}…"
