"""Read queries over the events table, written to use its indexes.

Every query here is either a range scan of an index or a handful of index probes, so reads stay
fast as a store grows to millions of events.
"""

from __future__ import annotations

import sqlite3
from typing import Any, Collection, Iterator, cast

from .ddl import DENSE_KINDS, SPARSE_ONLY
from .errors import EvidenceError, IndexDisagrees
from .index_guard import AGREES
from .run_summary import RunSummary


def collection(name: str, values: Collection[str] | None) -> tuple[str, ...] | None:
    """A filter's values; a bare string is refused rather than read as a set of characters."""
    if values is None:
        return None
    if isinstance(values, str):
        raise TypeError(f"{name} must be a collection of strings, not a single string")
    return tuple(values)


def select_events(
    run: str,
    kinds: Collection[str] | None,
    srcs: Collection[str] | None,
    t_from: int | None,
    t_to: int | None,
) -> tuple[str, list[Any]]:
    """SQL and parameters for a run's events in (t, seq, src) order; t_to is inclusive. Rows are
    (t, seq, src, event, agrees): agrees is index_guard.AGREES for a read through the covering
    index by kind (its text is the index's copy), 1 for a read of the table's own rows."""
    clauses, params = ["run = ?"], [run]
    for column, values in (("kind", collection("kinds", kinds)), ("src", collection("srcs", srcs))):
        if values is not None:
            clauses.append(f"{column} IN ({','.join('?' * len(values))})")
            params.extend(values)
    wanted = collection("kinds", kinds)
    agrees = "1"
    if wanted is not None and not set(wanted) & set(DENSE_KINDS):
        clauses.append(SPARSE_ONLY)  # verbatim, so that SQLite may use the partial index by kind
        agrees = AGREES
    _time_window(clauses, params, t_from, t_to)
    sql = f"SELECT t, seq, src, event, {agrees} FROM events WHERE {' AND '.join(clauses)} ORDER BY t, seq, src"
    return sql, params


def _distinct(conn: sqlite3.Connection, column: str, where: str, params: tuple[Any, ...]) -> Iterator[str]:
    """Distinct values of an indexed column by hopping along the index (least value, then the
    least value above it, ...): one probe per value instead of a scan of every row. Each value is
    checked against the table row its index entry points at (one lookup by rowid): a value only
    a damaged index holds (a run "h09" read as "h0;") is IndexDisagrees, never a run or a source."""
    row_value = f"(SELECT x.{column} FROM events AS x WHERE x.rowid = events.rowid)"
    first = f"SELECT {column}, {row_value} FROM events WHERE {where}"
    after = f"{first} AND {column} > ?"
    found = conn.execute(f"{first} ORDER BY {column} LIMIT 1", params).fetchone()
    while found is not None:
        value, in_row = found
        if value != in_row:
            raise _index_disagrees(column, value, in_row)
        yield value
        found = conn.execute(f"{after} ORDER BY {column} LIMIT 1", (*params, value)).fetchone()


def _index_disagrees(column: str, value: Any, in_row: Any) -> IndexDisagrees:
    held = "no row" if in_row is None else f"its row holds {in_row!r}"
    return IndexDisagrees(f"an index of the events table holds {column} {value!r} where {held}: the file was "
                          "damaged or altered behind the store's back, so nothing is read through that index; "
                          "`gaps verify` names what SQLite's integrity check finds")


def sources(conn: sqlite3.Connection, run: str) -> list[str]:
    """A run's sources, one index probe each."""
    return list(_distinct(conn, "src", "run = ?", (run,)))


def run_names(conn: sqlite3.Connection) -> list[str]:
    return list(_distinct(conn, "run", "1", ()))


def chain_tip(conn: sqlite3.Connection, run: str) -> tuple[int, str]:
    """(last chain position + 1, the stored hash there) of a run; (0, "") for none."""
    last = conn.execute("SELECT max(chain_pos) FROM events WHERE run = ?", (run,)).fetchone()[0]
    if last is None:
        return (0, "")
    row = conn.execute("SELECT hash FROM events WHERE run = ? AND chain_pos = ?", (run, last)).fetchone()
    return (int(last) + 1, "" if row is None else str(row[0]))


def run_summary(conn: sqlite3.Connection, run: str) -> RunSummary:
    """The summary of one run that has events."""
    (count,) = conn.execute("SELECT count(*) FROM events WHERE run = ?", (run,)).fetchone()
    return RunSummary(run, count, _end_t(conn, run, "ASC"), _end_t(conn, run, "DESC"), tuple(sources(conn, run)))


def _end_t(conn: sqlite3.Connection, run: str, order: str) -> int:
    """The run's earliest (ASC) or latest (DESC) event time through the index by time, checked
    against the row its entry points at (IndexDisagrees: the index and the table differ)."""
    found = conn.execute(
        "SELECT t, (SELECT x.run = events.run AND x.t = events.t FROM events AS x WHERE x.rowid = events.rowid) "
        f"FROM events WHERE run = ? ORDER BY t {order} LIMIT 1", (run,)).fetchone()
    if found is None or found[1] != 1 or type(found[0]) is not int:
        raise IndexDisagrees(f"run {run}: the index by time (events_by_time) does not hold what the table holds for "
                             f"its {'first' if order == 'ASC' else 'last'} event: the file was damaged or altered "
                             "behind the store's back; `gaps verify` names what SQLite's integrity check finds")
    return found[0]


def gaps(conn: sqlite3.Connection, run: str | None) -> list[dict[str, Any]]:
    """Missing seq ranges per (run, src), one pass over the (run, src, seq) index. A source's
    seqs start at 0, so a first stored seq above 0 is a gap too."""
    where, params = ("WHERE run = ?", (run,)) if run is not None else ("", ())
    rows = conn.execute(
        f"""SELECT run, src, prev + 1, seq - 1, highest FROM (
                SELECT run, src, seq,
                       lag(seq, 1, -1) OVER (PARTITION BY run, src ORDER BY seq) AS prev,
                       max(seq) OVER (PARTITION BY run, src) AS highest
                FROM events {where})
            WHERE seq > prev + 1
            ORDER BY run, src, seq""",
        params,
    )
    found: dict[tuple[str, str], dict[str, Any]] = {}
    for run_, src, first, last, highest in rows:
        entry = found.setdefault((run_, src), {"run": run_, "src": src, "missing": [], "highest": highest})
        entry["missing"].append([first, last])
    return list(found.values())


def chain_positions(conn: sqlite3.Connection, run: str, keys: Collection[tuple[str, int]]) -> dict[tuple[str, int], int]:
    """Where each (src, seq) of a run sits in its hash chain: one probe of the (run, src, seq)
    index per event, so an explanation can say which link of the chain vouches for a fact."""
    sql = "SELECT chain_pos FROM events WHERE run = ? AND src = ? AND seq = ?"
    found = {}
    for src, seq in keys:
        row = conn.execute(sql, (run, src, seq)).fetchone()
        if row is not None:
            found[(src, seq)] = row[0]
    return found


def first_t(conn: sqlite3.Connection, run: str) -> int | None:
    """The t of the run's first event in read order: one probe of the time index."""
    row = conn.execute("SELECT t FROM events WHERE run = ? ORDER BY t, seq, src LIMIT 1", (run,)).fetchone()
    return None if row is None else row[0]


def earliest_of_kind(conn: sqlite3.Connection, run: str, kind: str, roles: Collection[str]) -> int | None:
    """The earliest t of a kind sent by sources of these roles: one probe per role, on the
    (run, src, seq) index ranges of the role's sources."""
    sql = "SELECT min(t) FROM events WHERE run = ? AND src >= ? AND src < ? AND kind = ?"
    found = [conn.execute(sql, (run, f"{role}/", f"{role}0", kind)).fetchone()[0] for role in roles]
    return min((t for t in found if t is not None), default=None)


def t_of(conn: sqlite3.Connection, run: str, src: str, seq: int) -> int | None:
    row = conn.execute("SELECT t FROM events WHERE run = ? AND src = ? AND seq = ?", (run, src, seq)).fetchone()
    return None if row is None else row[0]


def next_t(conn: sqlite3.Connection, run: str, src: str, after: int, until: int) -> int | None:
    """The earliest t of the source's events in (after, until]."""
    sql = "SELECT min(t) FROM events WHERE run = ? AND t > ? AND t <= ? AND src = ?"
    return conn.execute(sql, (run, after, until, src)).fetchone()[0]


def chain_length(conn: sqlite3.Connection, run: str) -> int:
    (last,) = conn.execute("SELECT max(chain_pos) FROM events WHERE run = ?", (run,)).fetchone()
    return 0 if last is None else last + 1


def seq_bounds(conn: sqlite3.Connection, run: str, src: str) -> tuple[int, int | None]:
    """(events stored, highest seq) of one source of a run."""
    return conn.execute("SELECT count(*), max(seq) FROM events WHERE run = ? AND src = ?", (run, src)).fetchone()


def highest_seq(conn: sqlite3.Connection, run: str, src: str) -> int | None:
    """One probe of the (run, src, seq) index."""
    return conn.execute("SELECT max(seq) FROM events WHERE run = ? AND src = ?", (run, src)).fetchone()[0]


def missing_seqs(conn: sqlite3.Connection, run: str, src: str) -> list[tuple[int, int]]:
    """The [first, last] ranges of seqs missing below the source's highest, in order."""
    count, highest = seq_bounds(conn, run, src)
    if not count or count == cast(int, highest) + 1:  # events stored: a highest seq
        return []
    out, expected = [], 0
    for (seq,) in conn.execute("SELECT seq FROM events WHERE run = ? AND src = ? ORDER BY seq", (run, src)):
        if seq > expected:
            out.append((expected, seq - 1))
        expected = seq + 1
    return out


# --- one source's events by time, through the (run, src, seq) index -----------------------------

SEQ_SLACK = 64   # places in its numbering a source's event may sit out of time order and still be found


def _at_or_after(conn: sqlite3.Connection, run: str, src: str, seq: int) -> tuple[int, int] | None:
    """(seq, t) of the source's first stored event at or after seq: one index probe."""
    return conn.execute("SELECT seq, t FROM events WHERE run = ? AND src = ? AND seq >= ? ORDER BY seq LIMIT 1",
                        (run, src, seq)).fetchone()


def _probe(conn: sqlite3.Connection, run: str, src: str, seq: int) -> tuple[int, int]:
    """_at_or_after for a seq at or below the source's highest: a row must be there. None means
    the file's indexes disagree (the highest seq read through one index, this probe through
    another): a damaged or altered file, said as such rather than crashing the search."""
    found = _at_or_after(conn, run, src, seq)
    if found is None:
        raise EvidenceError(f"run {run} src {src}: the store's indexes disagree about this source's events "
                            f"(no event at or after seq {seq}): the file was damaged or altered; "
                            "`gaps verify` says where")
    return found


def _first_seq_past(conn: sqlite3.Connection, run: str, src: str, highest: int, t: int, strict: bool) -> int:
    """The lowest seq whose t is >= t (or > t when strict), searching the source's numbering:
    exact when the source's t never decreases as its seq rises; highest + 1 when none is.

    A producer's events come at a steady rate, so the seq is guessed from t between the times
    known at the ends of the range (interpolation search: a handful of probes instead of the
    17 of bisecting 100,000 events); a guess that fails to halve the range is followed by a
    bisection step, so the worst case stays logarithmic."""
    def past(found_t: int) -> bool:
        return found_t > t or (found_t == t and not strict)

    lo, hi = 0, highest + 1
    t_lo, t_hi = _probe(conn, run, src, 0)[1], _probe(conn, run, src, highest)[1]
    bisect = False
    while lo < hi:
        if not bisect and t_hi > t_lo:
            mid = min(max(lo + int((t - t_lo) / (t_hi - t_lo) * (hi - lo)), lo), hi - 1)
        else:
            mid = (lo + hi) // 2
        width = hi - lo
        seq, found_t = _probe(conn, run, src, mid)
        if past(found_t):
            hi, t_hi = mid, found_t
        else:
            lo, t_lo = seq + 1, found_t
        bisect = hi - lo > width // 2
    return lo


def source_rows(conn: sqlite3.Connection, run: str, src: str, kinds: Collection[str] | None,
                t_from: int | None, t_to: int | None) -> list[tuple]:
    """(t, seq, src, event) of one source's events in [t_from, t_to] (inclusive; None: open),
    in (t, seq) order. The window's seq range is found by searching the numbering (a few probes),
    widened by SEQ_SLACK on either side, then read as one range of the (run, src, seq) index."""
    highest = highest_seq(conn, run, src)
    if highest is None:
        return []
    lo = 0 if t_from is None else max(0, _first_seq_past(conn, run, src, highest, t_from, False) - SEQ_SLACK)
    hi = highest if t_to is None else _first_seq_past(conn, run, src, highest, t_to, True) - 1 + SEQ_SLACK
    clauses, params = ["run = ?", "src = ?", "seq >= ?", "seq <= ?"], [run, src, lo, hi]
    wanted = collection("kinds", kinds)
    if wanted is not None:
        clauses.append(f"kind IN ({','.join('?' * len(wanted))})")
        params.extend(wanted)
    if t_from is not None:      # the slack's rows outside the window stay in SQLite; the unary + keeps
        clauses.append("+t >= ?")   # the planner on the (run, src, seq) index, not the one by time
        params.append(t_from)
    if t_to is not None:
        clauses.append("+t <= ?")
        params.append(t_to)
    sql = f"SELECT t, seq, src, event FROM events WHERE {' AND '.join(clauses)} ORDER BY seq"
    rows = conn.execute(sql, params).fetchall()
    rows.sort(key=lambda row: (row[0], row[1]))
    return rows


def observation_rows(conn: sqlite3.Connection, run: str, vehicle: str, srcs: Collection[str] | None,
                     t_from: int | None, t_to: int | None) -> Iterator[tuple]:
    """(t, seq, src, event, agrees) of the monitors' observations of one vehicle, in (t, seq,
    src) order: a range of the covering kind index, the vehicle compared in SQLite (its id as
    text, so that a producer writing 173 and one writing "173" are both found); agrees checks
    each entry against its table row (store/index_guard.py)."""
    clauses = ["run = ?", "kind = 'monitor.observation'", SPARSE_ONLY,
               "CAST(json_extract(event, '$.body.vehicle') AS TEXT) = ?"]
    params: list[Any] = [run, vehicle]
    chosen = collection("srcs", srcs)
    if chosen is not None:
        clauses.append(f"src IN ({','.join('?' * len(chosen))})")
        params.extend(chosen)
    _time_window(clauses, params, t_from, t_to)
    return conn.execute(f"SELECT t, seq, src, event, {AGREES} FROM events WHERE {' AND '.join(clauses)} "
                        "ORDER BY t, seq, src", params)


def _time_window(clauses: list[str], params: list[Any], t_from: int | None, t_to: int | None) -> None:
    """Add `t_from <= t <= t_to` (either end open when None) to a WHERE being built."""
    if t_from is not None:
        clauses.append("t >= ?")
        params.append(t_from)
    if t_to is not None:
        clauses.append("t <= ?")
        params.append(t_to)


# --- a run's events in chain order, for history queries (store/history.py) ----------------------

def _history_terms(run: str, wanted: Any) -> tuple[list[str], list[Any]]:
    """WHERE terms for a HistoryFilter. The filters on t, src and kind carry a unary + so that
    SQLite never picks their indexes for a chain-order read: it walks (run, chain_pos) and tests
    them, instead of sorting a whole source's or a whole time range's rows for every chunk."""
    return _filter_terms(run, wanted, "+")


def _filter_terms(run: str, wanted: Any, prefix: str = "") -> tuple[list[str], list[Any]]:
    """WHERE terms for a HistoryFilter's run, t, src and kind, each column written after `prefix`."""
    clauses, params = ["run = ?"], [run]
    for column, op, value in (("t", ">=", wanted.t_from), ("t", "<=", wanted.t_to),
                              ("src", "=", wanted.src), ("kind", "=", wanted.kind)):
        if value is not None:
            clauses.append(f"{prefix}{column} {op} ?")
            params.append(value)
    return clauses, params


def history_window(conn: sqlite3.Connection, run: str, wanted: Any) -> tuple[int, int] | None:
    """(first, last) chain position of the run's events that pass `wanted`, or None if none does.
    Asked as two statements, so that without filters each is one probe of (run, chain_pos) (min
    and max together would scan the run); with a time bound each walks the time index over the
    window, so the cost follows the events in the window, not the run's length."""
    clauses, params = _filter_terms(run, wanted)
    where = " AND ".join(clauses)
    (first,) = conn.execute(f"SELECT min(chain_pos) FROM events WHERE {where}", params).fetchone()
    if first is None:
        return None
    (last,) = conn.execute(f"SELECT max(chain_pos) FROM events WHERE {where}", params).fetchone()
    return first, last


def history_chunk(conn: sqlite3.Connection, run: str, wanted: Any, after: int, last: int,
                  limit: int) -> list[tuple]:
    """Up to `limit` rows (chain_pos, t, src, kind, event, hash) at chain positions in
    (after, last] that pass `wanted`, in chain order: one range of the (run, chain_pos) index."""
    clauses, params = _history_terms(run, wanted)
    sql = (f"SELECT chain_pos, t, src, kind, event, hash FROM events WHERE {' AND '.join(clauses)} "
           "AND chain_pos > ? AND chain_pos <= ? ORDER BY chain_pos LIMIT ?")
    return conn.execute(sql, [*params, after, last, limit]).fetchall()
