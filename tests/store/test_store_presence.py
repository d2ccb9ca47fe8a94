"""The index of where road users were (store/presence.py): it may name a source that never came
near, never leave out one that did, however the events arrived; it lives in the cache file,
follows the chain as it grows, and a forged box fails `gaps verify`."""

import json
import math
import sqlite3

from hypothesis import given, settings
from hypothesis import strategies as st

from store import Store
from store.cache import check_presence, sources_near
from store.cache import presence
from tests.helpers.cli import gaps
from tests.helpers.store_testkit import T0, rows

SECOND = 1_000_000_000


def state(src: str, seq: int, t: int, x, y) -> dict:
    """An entity.state as a producer writes it (x and y may be anything JSON holds)."""
    return {"v": 1, "run": "r1", "src": src, "seq": seq, "t": t, "kind": "entity.state",
            "body": {"x": x, "y": y, "speed_mps": 5.0}}


def drive(src: str, x0: float, y0: float, dx: float, dy: float, n: int, *, t0: int = T0, every_s: float = 0.1,
          first_seq: int = 0) -> list[dict]:
    return [state(src, first_seq + i, t0 + int(i * every_s * SECOND), x0 + i * dx, y0 + i * dy) for i in range(n)]


def placed_near(events: list[dict], x: float, y: float, radius: float, t_from: int, t_to: int) -> set[str]:
    """The truth the index must cover: sources with a position that is a number within radius."""
    def number(v):
        return type(v) in (int, float) and math.isfinite(v)
    return {e["src"] for e in events if t_from <= e["t"] <= t_to and number(e["body"]["x"])
            and number(e["body"]["y"]) and math.hypot(e["body"]["x"] - x, e["body"]["y"] - y) <= radius}


def test_only_the_road_users_that_came_near_are_named(db_path):
    with Store(db_path) as store:
        store.append(drive("vehicle/near", -200.0, 0.0, 1.5, 0.0, 300)      # crosses (0, 0) at about 13 s
                     + drive("vehicle/far", -200.0, 400.0, 1.5, 0.0, 300)   # 400 m north, parallel
                     + drive("vehicle/late", 0.0, -500.0, 0.0, 1.0, 100, t0=T0 + 60 * SECOND))  # after the window
        found = sources_near(store, "r1", 0.0, 0.0, 50.0, T0, T0 + 30 * SECOND)
    assert found == ["vehicle/near"]


def test_the_index_lives_in_the_cache_file_not_the_store(db_path):
    with Store(db_path) as store:
        store.append(drive("vehicle/1", 0.0, 0.0, 1.0, 0.0, 50))
        sources_near(store, "r1", 0.0, 0.0, 10.0, T0, T0 + SECOND)
        cache = store.cache.path
    tables = {name for (name,) in rows(db_path, "SELECT name FROM sqlite_master WHERE type = 'table'")}
    assert not tables & {"presence", "presence_marks"}
    assert rows(cache, "SELECT count(*) > 0 FROM presence") == [(1,)]


def test_events_appended_after_the_index_was_built_are_found_late_ones_too(db_path):
    with Store(db_path) as store:
        store.append(drive("vehicle/1", 500.0, 500.0, 0.0, 0.0, 20))
        assert sources_near(store, "r1", 0.0, 0.0, 20.0, T0, T0 + 10 * SECOND) == []
    with Store(db_path) as writer:       # another process, no hook: the cache hears nothing of it
        writer.append(drive("vehicle/2", 5.0, 5.0, 0.0, 0.0, 10, t0=T0 + 2 * SECOND))   # earlier than some
    with Store(db_path) as store:
        assert sources_near(store, "r1", 0.0, 0.0, 20.0, T0, T0 + 10 * SECOND) == ["vehicle/2"]
        assert check_presence(store, "r1") == []


def test_a_cache_of_another_chain_is_not_used(tmp_path):
    a, b = tmp_path / "a.db", tmp_path / "b.db"
    with Store(a) as store:
        store.append(drive("vehicle/1", 0.0, 0.0, 0.0, 0.0, 10))
        assert sources_near(store, "r1", 0.0, 0.0, 5.0, T0, T0 + SECOND) == ["vehicle/1"]
    with Store(b) as store:             # the same run id and length, another road user elsewhere
        store.append(drive("vehicle/9", 0.0, 0.0, 0.0, 0.0, 10))
    (tmp_path / "b.db.cache").write_bytes((tmp_path / "a.db.cache").read_bytes())
    with Store(b) as store:
        assert sources_near(store, "r1", 0.0, 0.0, 5.0, T0, T0 + SECOND) == ["vehicle/9"]


def test_positions_that_are_not_numbers_place_nobody_and_booleans_only_widen(db_path):
    events = [state("vehicle/text", 0, T0, "0.0", "0.0"), state("vehicle/null", 0, T0, None, 0.0),
              state("vehicle/bool", 0, T0, True, False), state("vehicle/int", 0, T0, 3, -4)]
    with Store(db_path) as store:
        store.append(events)
        found = sources_near(store, "r1", 0.0, 0.0, 10.0, T0, T0)
    assert "vehicle/int" in found and "vehicle/text" not in found and "vehicle/null" not in found


def test_a_locked_cache_answers_from_memory(db_path):
    with Store(db_path) as store:
        store.append(drive("vehicle/1", 0.0, 0.0, 0.0, 0.0, 10))
        store.cache.connection          # created
        other = sqlite3.connect(store.cache.path, timeout=0)
        other.execute("BEGIN IMMEDIATE")            # another process writing the cache
        try:
            assert sources_near(store, "r1", 0.0, 0.0, 5.0, T0, T0 + SECOND) == ["vehicle/1"]
        finally:
            other.execute("ROLLBACK")
            other.close()


walk = st.lists(st.tuples(st.sampled_from(["vehicle/a", "vehicle/b", "pedestrian/c", "vehicle/d"]),
                          st.integers(0, 40_000),                                         # t: ms from T0
                          st.floats(-300, 300, allow_nan=False), st.floats(-300, 300, allow_nan=False)),
                min_size=1, max_size=60)


@settings(max_examples=40, deadline=None)
@given(walk, st.floats(-100, 100), st.floats(-100, 100), st.floats(1, 150), st.integers(0, 40_000),
       st.integers(0, 20_000), st.integers(1, 3))
def test_no_source_that_came_within_the_radius_is_left_out(tmp_path_factory, points, x, y, radius, start_ms,
                                                           length_ms, batches):
    """Whatever the positions, times and order of arrival (in several appends, late ones included)."""
    seqs: dict[str, int] = {}
    events = []
    for src, ms, px, py in points:
        seqs[src] = seqs.get(src, -1) + 1
        events.append(state(src, seqs[src], T0 + ms * 1_000_000, px, py))
    path = tmp_path_factory.mktemp("p") / "gaps.db"
    t_from, t_to = T0 + start_ms * 1_000_000, T0 + (start_ms + length_ms) * 1_000_000
    with Store(path) as store:
        size = math.ceil(len(events) / batches)
        for i in range(0, len(events), size):
            store.append(events[i:i + size])
            found = set(sources_near(store, "r1", x, y, radius, t_from, t_to))
            assert placed_near(events[:i + size], x, y, radius, t_from, t_to) <= found
        assert check_presence(store, "r1") == []


def test_bucket_agrees_with_sqlite_division():
    conn = sqlite3.connect(":memory:")
    for t in (0, 1, presence._BUCKET_NS - 1, presence._BUCKET_NS, -1, -presence._BUCKET_NS, -presence._BUCKET_NS - 1,
              T0, -T0):
        assert presence.bucket(t) == conn.execute("SELECT ? / ?", (t, presence._BUCKET_NS)).fetchone()[0]


def test_a_forged_box_is_not_believed_and_verify_warns(db_path):
    """Hiding a road user from the reasoner by narrowing its box (issue 15, finding 2): the box no
    longer carries its seal, so the read rebuilds the boxes from the events and still finds it;
    verify names the tampered cache as a warning (the evidence and the verdicts stand: exit 0)."""
    with Store(db_path) as store:
        store.append(drive("vehicle/1", 0.0, 0.0, 1.0, 0.0, 50) + drive("vehicle/2", 100.0, 0.0, 0.0, 0.0, 50))
        sources_near(store, "r1", 0.0, 0.0, 10.0, T0, T0 + SECOND)
    ok = gaps("verify", db=db_path)
    assert ok.exit_code == 0, ok.output
    cache = sqlite3.connect(f"{db_path}.cache")
    cache.execute("UPDATE presence SET x0 = 900.0, x1 = 901.0 WHERE src = 'vehicle/1' AND bucket = ?",
                  (presence.bucket(T0),))
    cache.commit()
    cache.close()
    warned = gaps("verify", db=db_path)
    assert warned.exit_code == 0, warned.output
    assert "WARNING: the cache file" in warned.stdout and "boxes of where road users were are not those sealed" \
        in warned.stdout
    as_json = json.loads(gaps("verify", "--json", db=db_path).stdout)
    assert as_json["ok"] is True and as_json["presence"] == {"r1": []}
    assert as_json["cache"]["presence"] == {"r1": ["the boxes of where road users were are not those sealed "
                                                   "(one altered, added or removed)"]}
    with Store(db_path) as store:
        assert sources_near(store, "r1", 0.0, 0.0, 10.0, T0, T0 + SECOND) == ["vehicle/1"]  # not believed
        assert store.cache.sealer.tampered() == {"presence": 1}
    assert gaps("verify", db=db_path).stdout.count("WARNING") == 0  # rebuilt by that read
