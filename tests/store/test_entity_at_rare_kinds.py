"""A vehicle's latest perception (a dense kind, not in the index by kind) is found without walking
back through all its states for every act: the source's perceptions and traces are read once per
chain and answered from memory (store/partial_state.py `_kind_rows`), each answer the fold's."""
import random
import sqlite3

from store import Store
from store.partial_state import entity_at
from store.state import state_at
from tests.helpers.store_testkit import BODIES, T0, event

MS = 1_000_000


def _vehicle(n: int, perceive_every: int) -> list[dict]:
    out = [event(0, src="vehicle/1", t=T0, kind="entity.spawn", body=dict(BODIES["entity.spawn"]))]
    for seq in range(1, n):
        kind = "vehicle.perception" if seq % perceive_every == 0 else "entity.state"
        out.append(event(seq, src="vehicle/1", t=T0 + seq * 100 * MS, kind=kind, body=dict(BODIES[kind])))
    return out


def _steps(conn: sqlite3.Connection, fn) -> tuple[object, int]:
    """fn's result and how many SQLite virtual machine steps (in thousands) it took."""
    count = [0]

    def tick():
        count[0] += 1
        return 0
    conn.set_progress_handler(tick, 1000)
    try:
        return fn(), count[0]
    finally:
        conn.set_progress_handler(None, 0)


def test_a_rare_perceivers_later_acts_do_not_walk_back_through_its_states(db_path):
    with Store(db_path) as store:
        store.append(_vehicle(4000, 500))             # 4,000 events, a perception every 500
        at = [T0 + ms * MS for ms in (350_000, 390_000, 120_000, 399_000, 60_000, 250_000)]
        first, cost = _steps(store.connection, lambda: entity_at(store, "r1", "vehicle/1", at[0]))
        assert first == state_at(store, "r1", at[0], use_snapshots=False).entities["vehicle/1"]
        later = []
        for t in at[1:]:
            found, steps = _steps(store.connection, lambda: entity_at(store, "r1", "vehicle/1", t))
            assert found == state_at(store, "r1", t, use_snapshots=False).entities["vehicle/1"], t
            later.append(steps)
        assert max(later) * 5 < cost, (cost, later)


def test_kept_rows_serve_only_the_chain_they_were_read_for(tmp_path):
    """Read for one chain, the kept rows are not used for a longer one: a perception appended
    later (numbered inside the kept range, arriving late) is found; and the later acts of the
    longer chain are answered from memory again."""
    events = _vehicle(1200, 300)
    late = [e for e in events if e["seq"] in (450, 451)]
    with Store(tmp_path / "s.db") as store:
        store.append([e for e in events if e not in late])
        t = T0 + 60_000 * MS
        assert entity_at(store, "r1", "vehicle/1", t) == state_at(store, "r1", t, use_snapshots=False).entities["vehicle/1"]
        store.append([{**late[0], "kind": "vehicle.perception", "body": dict(BODIES["vehicle.perception"])}, late[1]])
        _, cost = _steps(store.connection, lambda: entity_at(store, "r1", "vehicle/1", T0 + 119_000 * MS))
        _, again = _steps(store.connection, lambda: entity_at(store, "r1", "vehicle/1", T0 + 118_000 * MS))
        assert again * 3 < cost, (cost, again)
        rng = random.Random(4)
        for t in rng.sample(range(T0, T0 + 120_000 * MS, 997 * MS), 12):
            expected = state_at(store, "r1", t, use_snapshots=False).entities.get("vehicle/1")
            assert entity_at(store, "r1", "vehicle/1", t) == expected, t
