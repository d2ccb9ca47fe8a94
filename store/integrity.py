"""SQLite's own check of a store file, run by `gaps verify` beside the chains.

The chains prove the rows of the events table. The reads that judge a run do not all go through
those rows: the covering index `events_by_kind` holds a second copy of every sparse event's text,
and the time and (run, src, seq) indexes decide which rows a read finds. Someone holding the file
can rewrite an index entry so that it disagrees with its row (a forged rulebook in `run.start`,
an observation left out), and the chain walk, which reads the table, still matches. SQLite's
`integrity_check` compares every index with its table (and checks the file's pages); its
`quick_check` does not compare them, so it would not see this (tests/store/test_store_split_view.py).
It costs about a sixth of a verify: 2.3 s against 15 s on a 258,000-event, 148 MB store here,
79 s on a 9.75-million-event, 5.8 GB one (quick_check: 14 s).
"""
from __future__ import annotations

import sqlite3

SHOWN = 10  # messages kept from a failing check: one is enough to fail, a few help to see why


def integrity_problems(conn: sqlite3.Connection) -> list[str]:
    """What SQLite's integrity check finds wrong with the file (its first SHOWN messages); [] if
    nothing. A file too damaged for the check to run is a finding too, never an exception."""
    try:
        messages = [str(row[0]) for row in conn.execute(f"PRAGMA integrity_check({SHOWN})")]
    except sqlite3.DatabaseError as exc:
        return [f"the check could not run: {exc}"]
    return [] if messages == ["ok"] else messages


def integrity_problem(messages: list[str]) -> dict | None:
    """The verify problem a failed integrity check is: not tied to one event, so run, src, seq
    and chain position are None, and the message says what the failure means for the evidence."""
    if not messages:
        return None
    more = f" (and {len(messages) - 1} more)" if len(messages) > 1 else ""
    what = (f"the store file fails SQLite's integrity check: {messages[0]}{more}: an index or page of the "
            "file disagrees with the rows the chains cover, so a read through it could show other events "
            "than those verified")
    return {"run": None, "src": None, "seq": None, "chain_pos": None, "what": what}
