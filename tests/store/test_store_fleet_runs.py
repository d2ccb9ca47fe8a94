"""A fleet's many short runs: what the store keeps of a run is let go once its run.end is stored,
without changing what a later event of it, or a repeat, becomes; a new run's sources cost no
look-up each; the append hook is called once per append, with every run it extended."""
from __future__ import annotations

import contextlib

import pytest

from store import Store
from tests.helpers.store_testkit import event

SOURCES = [f"vehicle/{n}" for n in range(30)]


def short_run(run: str, end: bool = True) -> list[dict]:
    events = [event(0, run=run, kind="run.start")]
    events += [event(seq, run=run, src=src, kind="entity.state") for seq in range(2) for src in SOURCES]
    if end:
        events.append(event(1, run=run, kind="run.end"))
    return events


@contextlib.contextmanager
def statements(store: Store):
    """Each SQL statement the store's connection runs inside the block, as SQLite traces it."""
    asked: list[str] = []
    store.connection.set_trace_callback(asked.append)
    try:
        yield asked
    finally:
        store.connection.set_trace_callback(None)


def test_an_ended_run_is_let_go_and_a_late_event_or_a_repeat_of_it_is_still_judged_by_the_store(store):
    store.append([e for n in range(5) for e in short_run(f"r{n}")] + short_run("live", end=False))
    kept = store._heads
    assert set(kept.chains) == {"live"}
    assert {run for run, _ in kept.max_seq} == {"live"}
    late = event(2, run="r3", src="vehicle/7", kind="entity.state")
    again = event(1, run="r3", src="vehicle/7", kind="entity.state")
    report = store.append([late, again])
    assert (report.stored, report.duplicates) == (1, 1)         # the chain loaded again, the repeat known
    forged = {**event(0, run="r2", src="vehicle/3", kind="entity.state"), "body": {"x": 9.0, "y": 0.0, "speed_mps": 1.0}}
    assert store.append([forged]).rejected                         # other content under a stored identity
    assert store.verify().ok


def test_a_new_runs_sources_are_not_looked_up_one_by_one(store):
    store.append(short_run("first"))
    with statements(store) as asked:
        for src in SOURCES:
            assert store.highest_seq("second", src) is None
    assert len(asked) == 1                                         # one probe for the run, none a source


def test_a_new_run_costs_the_append_one_probe_of_the_file_before_its_rows_are_written(store):
    store.append(short_run("first"))
    with statements(store) as asked:
        store.append([e for n in range(5) for e in short_run(f"new{n}")])
    before_rows = asked[:next(i for i, sql in enumerate(asked) if sql.startswith("INSERT"))]
    for n in range(5):
        assert [sql for sql in before_rows if f"'new{n}'" in sql] == [f"SELECT 1 FROM events WHERE run = 'new{n}' LIMIT 1"]


def test_a_run_found_empty_is_still_checked_against_its_signed_head_known_outside_the_file(store):
    from store.tail_check import TamperedTail
    from store.tail_check import anchored_chain
    from store.keys.tree_heads import TreeHead

    class Known:                                                   # a witness that saw 3 events of "gone"
        last = {"gone": (TreeHead("gone", 3, "00" * 32, "00" * 32, 0, 1), "the witness file")}
    key = object()
    with pytest.raises(TamperedTail, match="the run was deleted"):
        anchored_chain(store.connection, "gone", key, Known(), empty=True)


def test_the_append_hook_is_called_once_per_append_with_every_run(store):
    calls: list[dict] = []
    store.add_append_hook(lambda _store, earliest: calls.append(dict(earliest)))
    store.append([e for n in range(3) for e in short_run(f"r{n}")])
    assert len(calls) == 1 and sorted(calls[0]) == ["r0", "r1", "r2"]


def test_snapshot_watermarks_of_every_run_of_an_append_are_raised(db_path):
    from store.cache import enable_snapshots
    from store.cache.snapshots import marks
    with Store(db_path) as store:
        enable_snapshots(store)
        store.append([e for n in range(4) for e in short_run(f"r{n}")])
        assert all(not marks(store, f"r{n}").unchecked for n in range(4))


def test_shrinking_memory_forgets_the_run_names_the_envelope_check_remembers(store):
    from store import envelope
    store.append([e for n in range(3) for e in short_run(f"r{n}")])
    assert {"r0", "r1", "r2"} <= envelope._SEEN_RUNS
    store.shrink_memory()                                          # what a quiet ingest calls
    assert not envelope._SEEN_RUNS and not envelope._SEEN_SOURCES
    assert store.append(short_run("r3")).stored == len(short_run("r3"))   # remembered again as checked
    assert "r3" in envelope._SEEN_RUNS


def test_the_snapshot_hook_takes_each_runs_chain_end_from_the_append_not_from_the_file(db_path):
    from store.cache import enable_snapshots
    from store.cache.snapshots import chain_end, marks
    with Store(db_path) as store:
        enable_snapshots(store)
        with statements(store) as asked:
            store.append([e for n in range(4) for e in short_run(f"r{n}")])
        after_commit = asked[asked.index("COMMIT") + 1:]
        assert not [sql for sql in after_commit if "FROM events" in sql]   # no read-back of the chains' ends
        for n in range(4):                                             # and the watermarks are the file's ends
            seen = marks(store, f"r{n}")
            assert (seen.length, seen.head) == chain_end(store.connection, f"r{n}") and not seen.unchecked


def _cursor_refs(conn) -> list:
    """The weak references to its cursors a sqlite3 connection keeps (found among its referents)."""
    import gc
    import weakref
    return next(r for r in gc.get_referents(conn)
                if isinstance(r, list) and r and all(isinstance(x, weakref.ref) for x in r))


def test_shrinking_memory_lets_go_of_the_dead_cursors_made_by_appends(db_path):
    """A quiet ingest's connections keep no reference made during its last batches: each one, dead
    or not, held a 1 MB arena of the interpreter resident (store.opening.drop_dead_cursors)."""
    from store.cache import enable_snapshots
    with Store(db_path) as store:
        enable_snapshots(store)
        for n in range(6):                                       # a few hundred cursors, none a 200th
            store.append(short_run(f"r{n}"))
        conns = [store.connection, store.cache.connection]
        made = [list(_cursor_refs(conn)) for conn in conns]     # held here: no address reused
        assert all(len(refs) > 20 for refs in made)
        store.shrink_memory()                                    # what a quiet ingest calls
        for conn, before in zip(conns, made):
            kept = {id(ref) for ref in _cursor_refs(conn)}
            assert not [ref for ref in before if id(ref) in kept]
        assert store.append(short_run("r6")).stored == len(short_run("r6"))
