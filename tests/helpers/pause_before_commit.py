"""`gaps ARGS` in a child process whose Nth store transaction stops dead after its writes and before
its COMMIT: the moment a power cut hurts most, held still so a test can kill -9 the process there.

    GAPS_PAUSE_AT=N GAPS_PAUSE_MARKER=FILE python -m tests.helpers.pause_before_commit import run.jsonl --db F

Only this child is changed (Store._transaction wrapped here): the store's code has no hook for it.
The page cache is made tiny for that one (GAPS_PAUSE_CACHE_PAGES, default 4), so that a large transaction spills
its pages into the WAL before its commit, as SQLite does under memory pressure: the file then holds
written, uncommitted frames when the process dies. At the pause the marker file gets JSON: the WAL's
size when the transaction began and now.
"""
from __future__ import annotations

import json
import os
import sys
import time
from contextlib import contextmanager
from pathlib import Path

from store import Store

_original = Store._transaction
_seen = [0]


def _wal_bytes(store: Store) -> int:
    wal = Path(store.path + "-wal")
    return wal.stat().st_size if wal.exists() else 0


@contextmanager
def _pausing_transaction(self: Store):
    if _seen[0] + 1 == int(os.environ["GAPS_PAUSE_AT"]):  # the next writing transaction may be the one
        self.connection.execute(f"PRAGMA cache_size={int(os.environ.get('GAPS_PAUSE_CACHE_PAGES', '4'))}")
    with _original(self) as conn:
        began, changes = _wal_bytes(self), conn.total_changes
        yield conn
        if conn.total_changes > changes:
            _seen[0] += 1
            if _seen[0] == int(os.environ["GAPS_PAUSE_AT"]):
                marker = Path(os.environ["GAPS_PAUSE_MARKER"])
                marker.write_text(json.dumps({"wal_at_begin": began, "wal_now": _wal_bytes(self)}))
                while True:       # until kill -9
                    time.sleep(60)


def main() -> None:
    Store._transaction = _pausing_transaction
    from cli.main import app
    sys.argv = ["gaps", *sys.argv[1:]]
    app()


if __name__ == "__main__":
    main()
