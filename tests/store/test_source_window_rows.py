"""A source's window is read through its seq range widened by SEQ_SLACK on either side (an event a
little out of time order is still found); the rows of that slack outside the window are dropped
in SQLite, not brought into Python with their text: a first judgement reads thousands of windows,
each a few dozen events, and the slack was most of the rows it fetched."""
from store import queries
from tests.helpers.store_testkit import T0, event

MS = 1_000_000


class _Counting:
    """A connection that counts the rows the window's own read (the one returning the events'
    text) hands to Python."""

    def __init__(self, conn):
        self.conn, self.rows = conn, 0

    def execute(self, sql, params=()):
        cursor = self.conn.execute(sql, params)
        return _Rows(cursor, self) if "event FROM" in sql else cursor


class _Rows:
    def __init__(self, cursor, counter):
        self.cursor, self.counter = cursor, counter

    def __iter__(self):
        for row in self.cursor:
            self.counter.rows += 1
            yield row

    def fetchall(self):
        rows = self.cursor.fetchall()
        self.counter.rows += len(rows)
        return rows


def test_only_the_windows_rows_reach_python(store):
    store.append([event(seq, src="vehicle/173", kind="entity.state", t=T0 + seq * 100 * MS, body={"x": 0.0, "y": 0.0, "speed_mps": 5.0})
                  for seq in range(500)])
    counting = _Counting(store.connection)
    rows = queries.source_rows(counting, "r1", "vehicle/173", ["entity.state"], T0 + 20_000 * MS, T0 + 20_900 * MS)
    assert [row[1] for row in rows] == list(range(200, 210))
    assert counting.rows == 10
