"""Store.history: a run in chain order, read a chunk per short read transaction, within a window
fixed when the read starts."""
from __future__ import annotations

from store import Store
from store.wire import HistoryFilter
from tests.helpers.ingest_testkit import T0, make_event

STEP = 100_000_000


def test_chain_order_across_chunks_with_no_transaction_held_between_them(tmp_path):
    with Store(tmp_path / "s.db") as store:
        events = [make_event(f"vehicle/{v}", seq, "entity.state") for seq in range(10) for v in (1, 2)]
        store.append(events[5:] + events[:5])         # chained out of time order
        read = []
        for row in store.history("test-run", chunk=3):
            assert not store.connection.in_transaction   # no snapshot kept while the reader waits
            read.append(row)
        assert [r.chain_pos for r in read] == list(range(20))
        assert [(r.src, r.t) for r in read] == [(e["src"], e["t"]) for e in events[5:] + events[:5]]
        assert read[-1].hash == store.chain_head("test-run")[1]


def test_filters_and_a_resumed_read(tmp_path):
    with Store(tmp_path / "s.db") as store:
        store.append([make_event(f"vehicle/{v}", seq, "entity.state") for seq in range(10) for v in (1, 2)])
        window = HistoryFilter(t_from=T0 + 3 * STEP, t_to=T0 + 6 * STEP, src="vehicle/2", kind="entity.state")
        assert [(r.src, r.t) for r in store.history("test-run", window, chunk=2)] == [
            ("vehicle/2", T0 + s * STEP) for s in (3, 4, 5, 6)]
        assert [r.chain_pos for r in store.history("test-run", after=15)] == [16, 17, 18, 19]
        assert list(store.history("test-run", HistoryFilter(kind="signal.state"))) == []
        assert list(store.history("no-such-run")) == []


def test_events_appended_during_a_read_are_not_half_included(tmp_path):
    with Store(tmp_path / "s.db") as store, Store.open_read_only(tmp_path / "s.db") as reader:
        store.append([make_event("vehicle/1", seq, "entity.state") for seq in range(6)])
        rows = reader.history("test-run", chunk=2)
        first = next(rows)
        store.append([make_event("vehicle/1", seq, "entity.state") for seq in range(6, 9)])
        assert [first.chain_pos, *(r.chain_pos for r in rows)] == list(range(6))
        assert len(list(reader.history("test-run"))) == 9
