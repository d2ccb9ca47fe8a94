"""Judging many acts of a run, the vehicles' perceptions and traces (dense kinds, no index by kind)
are read in one walk of the run's chain once the per-source reads have walked an eighth of it, not
by walking each vehicle's states to its spawn one source at a time (store/partial_state.py
`_whole_run`); every answer stays the fold's, and a longer chain is not answered from the walk of a
shorter one."""
import re
import sqlite3

import store.partial_state as partial_state
from store import Store
from store.partial_state import entity_at
from store.state import state_at
from tests.helpers.store_testkit import BODIES, T0, event

MS = 1_000_000
VEHICLES = 12


def _run(n: int, first_seq: int = 0, start_ms: int = 0, run: str = "r1") -> list[dict]:
    """VEHICLES vehicles publishing together at 10 Hz, in time order: a spawn, then states, a
    perception every 150 events and a trace every 220 (vehicle 0 neither perceives nor traces)."""
    out = []
    for step in range(first_seq, first_seq + n):
        for v in range(VEHICLES):
            kind = ("entity.spawn" if step == 0 else "vehicle.perception" if v and step % 150 == 0
                    else "vehicle.trace" if v and step % 220 == 0 else "entity.state")
            out.append(event(step, run=run, src=f"vehicle/{v}", t=T0 + (start_ms + step * 100) * MS + v,
                             kind=kind, body=dict(BODIES[kind])))
    return out


def _per_source_reads(conn: sqlite3.Connection, fn) -> tuple[object, int, int]:
    """fn's result, how many per-source reads of a dense kind it made, and how many whole-run reads."""
    seen: list[str] = []
    conn.set_trace_callback(seen.append)        # each statement as run, its parameters written in
    try:
        result = fn()
    finally:
        conn.set_trace_callback(None)
    return (result, sum(re.search(r"seq <= -?\d+ AND kind = ", sql) is not None for sql in seen),
            sum("chain_pos <" in sql and "vehicle.perception" in sql for sql in seen))


def _judged(store: Store, times: list[int], run: str = "r1") -> tuple[int, int]:
    """Every vehicle's record at each time, each the fold's; the reads it took."""
    per_source = whole = 0
    for t in times:
        expected = state_at(store, run, t, use_snapshots=False).entities
        for v in range(VEHICLES):
            found, a, b = _per_source_reads(store.connection, lambda: entity_at(store, run, f"vehicle/{v}", t))
            assert found == expected.get(f"vehicle/{v}"), (v, t)
            per_source, whole = per_source + a, whole + b
    return per_source, whole


def test_many_vehicles_acts_read_the_runs_rare_kinds_in_one_walk(db_path):
    with Store(db_path) as store:
        store.append(_run(1000))                       # 12,000 events, 100 s
        per_source, whole = _judged(store, [T0 + ms * MS for ms in (95_000, 40_000, 99_950, 15_500, 70_000)])
    assert whole == 1
    assert per_source < VEHICLES / 2, per_source      # one source at a time: at least one read per vehicle


def test_a_longer_chain_is_not_answered_from_the_walk_of_a_shorter_one(db_path):
    with Store(db_path) as store:
        store.append(_run(1000))
        _, whole = _judged(store, [T0 + 99_000 * MS])
        assert whole == 1
        store.append(_run(400, first_seq=1000))      # perceptions at seq 1050 and 1200, traces at 1100 and 1320
        _, whole = _judged(store, [T0 + ms * MS for ms in (139_000, 121_000, 99_000)])
        assert whole == 1


def test_too_many_rare_rows_are_read_one_source_at_a_time(db_path, monkeypatch):
    monkeypatch.setattr(partial_state, "_MAX_KIND_ROWS", 50)
    with Store(db_path) as store:
        store.append(_run(1000))
        per_source, whole = _judged(store, [T0 + ms * MS for ms in (95_000, 40_000, 99_950)])
    assert whole == 1                                   # read once, found too many, not kept nor read again
    assert per_source >= VEHICLES


def test_one_runs_rows_are_kept_at_a_time(db_path):
    """Judging a second run lets the first run's rows go (memory holds one run's), and judging the
    first again reads them again, each answer still the fold's."""
    with Store(db_path) as store:
        store.append(_run(600))
        store.append(_run(600, run="r2"))
        times = [T0 + ms * MS for ms in (59_000, 30_000)]
        assert _judged(store, times)[1] == 1
        assert _judged(store, times, run="r2")[1] == 1
        assert _judged(store, times)[1] == 1
