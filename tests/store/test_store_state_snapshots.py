"""Snapshots of state: the same answer as folding from the start, whatever arrives late and however
the snapshots were made, and a bounded fold per read."""

import random
import sqlite3
import tempfile
from pathlib import Path

import pytest

from tests.store.conftest import reseal_snapshots
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from tests.helpers.store_testkit import T0, event

from store import Store, state
from store.cache import snapshots
from store.state import build_snapshots, state_at

SOURCES = {
    "vehicle/1": ("entity.state", {"x": 0.0, "y": 0.0, "speed_mps": 1.0}),
    "vehicle/2": ("vehicle.perception", {"facts": ["2 has red light"]}),
    "vehicle/3": ("ads.event", {"event": "activated"}),
    "signal/J1": ("signal.state", {"junction": "J1", "approach": "north", "colour": "red"}),
    "monitor/m1": ("monitor.observation", {"vehicle": "1", "facts": ["1 has red light"]}),
}
ADS = ["activated", "deactivated", "transition_demand", "driver_override", "minimal_risk_manoeuvre", "failure"]


def body_for(kind: str, base: dict, n: int) -> dict:
    if kind == "signal.state":
        return {**base, "colour": ["red", "green", "amber"][n % 3]}
    if kind == "ads.event":
        return {"event": ADS[n % len(ADS)]}
    return {**base, "n": n}


def run_events(picks: list[tuple[str, int, int]]) -> list[dict]:
    """Events from (source index, t in ms, body variant) picks; seq counts up per source."""
    seqs: dict[str, int] = {}
    events = []
    names = sorted(SOURCES)
    for index, ms, variant in picks:
        src = names[index % len(names)]
        kind, base = SOURCES[src]
        seq = seqs[src] = seqs.get(src, -1) + 1
        events.append(event(seq, src=src, t=T0 + ms * 1_000_000, kind=kind, body=body_for(kind, base, variant)))
    return events


def times(events: list[dict]) -> list[int]:
    stamps = sorted({e["t"] for e in events})
    return [T0 - 1, *stamps, *(t + 1 for t in stamps[::3])]


def assert_snapshots_agree(store: Store, ts: list[int]) -> None:
    for t in ts:
        assert state_at(store, "r1", t) == state_at(store, "r1", t, use_snapshots=False), t


@pytest.fixture
def small_snapshots(monkeypatch):
    """A snapshot every 3 events and 2 held per pass, so that short runs have many of both."""
    monkeypatch.setattr(state, "SNAPSHOT_EVERY", 3)
    monkeypatch.setattr(state, "_HELD", 2)


picks = st.lists(st.tuples(st.integers(0, 4), st.integers(0, 60), st.integers(0, 5)), min_size=1, max_size=80)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(picks=picks, late=picks, every=st.integers(1, 7), split=st.integers(1, 20), hooked=st.booleans(),
       shuffle_seed=st.integers(0, 1000))
def test_snapshots_give_the_same_state_as_folding_from_the_start(
    small_snapshots, picks, late, every, split, hooked, shuffle_seed
):
    events = run_events(picks + late)
    first, then = events[: len(picks)], events[len(picks):]
    random.Random(shuffle_seed).shuffle(then)
    with tempfile.TemporaryDirectory() as tmp, Store(Path(tmp) / "s.db", durable=False) as store:
        if hooked:
            snapshots.enable_snapshots(store)
        store.append(first)
        build_snapshots(store, "r1", every=every)
        assert_snapshots_agree(store, times(first))
        for i in range(0, len(then), split):  # late and out of order, in batches
            store.append(then[i:i + split])
            t = random.Random(i).choice(times(events))
            assert state_at(store, "r1", t) == state_at(store, "r1", t, use_snapshots=False)
        assert_snapshots_agree(store, times(events))


def long_run(n: int) -> list[dict]:
    rng = random.Random(5)
    return run_events([(rng.randrange(5), i // 3, rng.randrange(6)) for i in range(n)])


def test_build_writes_a_snapshot_every_so_many_events(store):
    store.append(long_run(100))
    assert build_snapshots(store, "r1", every=10) == 10
    assert build_snapshots(store, "r1", every=10) == 10  # nothing more to do


def test_a_read_folds_fewer_events_than_the_snapshot_spacing(store, monkeypatch):
    store.append(long_run(3000))
    build_snapshots(store, "r1", every=100)
    folded = []
    fold_rows = state.fold_rows
    monkeypatch.setattr(state, "fold_rows", lambda s, rows: (folded.append(len(rows)), fold_rows(s, rows)))
    for t in times(long_run(3000))[::50]:
        folded.clear()
        state_at(store, "r1", t)
        assert sum(folded) < 100


def test_reads_write_the_snapshots_they_pass(store, small_snapshots):
    events = long_run(40)
    store.append(events)
    last = events[-1]["t"]
    assert state_at(store, "r1", last) == state_at(store, "r1", last, use_snapshots=False)
    assert snapshots.count(store, "r1") == 40 // 3  # written in passes of two


def test_a_late_event_from_a_writer_without_the_hook_is_seen(db_path, small_snapshots):
    events = long_run(60)
    late = event(999, src="vehicle/9", t=events[5]["t"], kind="entity.state", body={"x": 9, "y": 9, "speed_mps": 0})
    with Store(db_path) as reader, Store(db_path) as writer:
        snapshots.enable_snapshots(reader)
        writer.append(events)
        build_snapshots(reader, "r1")
        writer.append([late])  # the writer knows nothing of snapshots
        end = events[-1]["t"]
        assert state_at(reader, "r1", end).entities["vehicle/9"]["state"]["seq"] == 999
        assert_snapshots_agree(reader, times(events))


def test_the_hook_drops_the_snapshots_a_late_event_makes_stale(store):
    events = long_run(100)
    snapshots.enable_snapshots(store)
    store.append(events)
    build_snapshots(store, "r1", every=10)
    middle = sorted(e["t"] for e in events)[50]
    store.append([event(0, src="vehicle/9", t=middle, kind="entity.state", body={"x": 0, "y": 0, "speed_mps": 0})])
    kept = store.cache.connection.execute("SELECT max(t) FROM state_snapshots WHERE run = 'r1'").fetchone()[0]
    assert kept < middle
    watermark = store.cache.connection.execute("SELECT chain_len FROM state_watermarks WHERE run = 'r1'").fetchone()
    assert watermark == (101,)


def test_snapshots_of_one_run_ignore_another(store):
    store.append(long_run(50))
    build_snapshots(store, "r1", every=5)
    other = [dict(e, run="r2") for e in long_run(50)]
    store.append(other)
    assert snapshots.count(store, "r1") == 10
    assert state_at(store, "r2", other[-1]["t"]) == state_at(store, "r2", other[-1]["t"], use_snapshots=False)


def test_a_damaged_snapshot_is_passed_over(store):
    events = long_run(50)
    store.append(events)
    build_snapshots(store, "r1", every=5)
    store.cache.connection.execute("UPDATE state_snapshots SET state = x'00ff'")
    assert_snapshots_agree(store, times(events)[::7])


def test_snapshots_of_another_fold_version_are_ignored(store, monkeypatch):
    events = long_run(30)
    store.append(events)
    build_snapshots(store, "r1", every=5)
    monkeypatch.setattr(snapshots, "FOLD_VERSION", snapshots.FOLD_VERSION + 1)
    store.cache.connection.execute("UPDATE state_snapshots SET state = ?", (snapshots.encode({"junk": 1}),))
    assert_snapshots_agree(store, times(events)[::5])


def test_the_cache_can_be_cleared_and_rebuilt(store):
    events = long_run(30)
    store.append(events)
    build_snapshots(store, "r1", every=5)
    snapshots.clear(store)
    assert snapshots.count(store, "r1") == 0
    assert_snapshots_agree(store, times(events)[::5])


def test_a_locked_cache_still_answers_without_writing_snapshots(db_path, small_snapshots):
    events = long_run(30)
    with Store(db_path) as reader:
        reader.append(events)
        snapshots.ensure_tables(reader)
        reader.cache.connection.execute("PRAGMA busy_timeout = 10")
        other = sqlite3.connect(reader.cache.path, isolation_level=None)  # the cache, locked
        other.execute("BEGIN IMMEDIATE")
        try:
            end = events[-1]["t"]
            assert state_at(reader, "r1", end) == state_at(reader, "r1", end, use_snapshots=False)
            assert snapshots.count(reader, "r1") == 0
        finally:
            other.execute("ROLLBACK")
            other.close()


def test_snapshots_folded_before_a_concurrent_late_append_are_not_written(db_path, monkeypatch):
    events = long_run(60)
    late = event(0, src="vehicle/9", t=events[10]["t"], kind="entity.state", body={"x": 9, "y": 9, "speed_mps": 0})
    save = snapshots.save

    def save_after_a_late_append(*args):
        with Store(db_path) as writer:  # another process, between this reader's read and its write
            writer.append([late])
        monkeypatch.setattr(snapshots, "save", save)
        return save(*args)

    with Store(db_path) as reader:
        reader.append(events)
        monkeypatch.setattr(snapshots, "save", save_after_a_late_append)
        build_snapshots(reader, "r1", every=5)
        assert_snapshots_agree(reader, times(events))


def test_check_finds_a_snapshot_altered_behind_the_stores_back(store):
    events = long_run(60)
    store.append(events)
    build_snapshots(store, "r1", every=7)
    assert state.check_snapshots(store, "r1") == []
    conn = store.cache.connection
    t, seq, src, blob = conn.execute("SELECT t, seq, src, state FROM state_snapshots ORDER BY t LIMIT 1 OFFSET 3").fetchone()
    forged = snapshots.decode(blob)
    forged["signals"]["J1"]["north"]["colour"] = "off"  # no event of the run says so
    conn.execute("UPDATE state_snapshots SET state = ? WHERE t = ? AND seq = ? AND src = ?",
                 (snapshots.encode(forged), t, seq, src))
    assert state.check_snapshots(store, "r1") == []  # its seal no longer opens: never used, a tamper
    assert snapshots.tampered_snapshots(store, "r1") == [(t, seq, src)]
    reseal_snapshots(store)  # by whoever holds the cache key: the re-fold still finds it
    assert state.check_snapshots(store, "r1") == [(t, seq, src)]


# --- the encoding: orjson where it is exact, json where an integer is too long for it -----------

import gc  # noqa: E402
import struct  # noqa: E402
import zlib  # noqa: E402


def test_a_snapshot_is_written_by_orjson_and_read_back_equal(store):
    events = long_run(40)
    store.append(events)
    build_snapshots(store, "r1", every=10)
    blobs = [blob for (blob,) in store.cache.connection.execute("SELECT state FROM state_snapshots")]
    assert blobs and all(blob[4] == 1 for blob in blobs)  # the writer byte: orjson
    assert_snapshots_agree(store, times(events)[::4])


def test_an_integer_beyond_64_bits_in_a_body_survives_a_snapshot_exactly(store):
    huge = 2**70 + 1  # orjson would read it as a float: 1.1805916207174113e+21
    events = long_run(20)
    events.append(event(0, src="vehicle/8", t=events[-1]["t"] + 1, kind="entity.state",
                        body={"x": 0.0, "y": 0.0, "speed_mps": 0.0, "odometer": huge}))
    events += [dict(e, seq=e["seq"] + 100, t=e["t"] + 10**9) for e in long_run(20)]
    store.append(events)
    build_snapshots(store, "r1", every=5)
    writers = {blob[4] for (blob,) in store.cache.connection.execute("SELECT state FROM state_snapshots")}
    assert writers == {0, 1}  # json once the state holds the long integer, orjson before
    got = state_at(store, "r1", events[-1]["t"]).entities["vehicle/8"]["state"]["body"]["odometer"]
    assert type(got) is int and got == huge
    assert_snapshots_agree(store, times(events)[::3])


def test_a_blob_altered_to_hold_a_long_integer_is_found_by_the_check(store):
    """A forger who writes a long integer into an orjson snapshot gets orjson's float back on
    reads; check_snapshots reads exactly, so it sees the integer and the difference."""
    events = long_run(30)
    store.append(events)
    build_snapshots(store, "r1", every=10)
    conn = store.cache.connection
    t, seq, src, blob = conn.execute("SELECT t, seq, src, state FROM state_snapshots ORDER BY t LIMIT 1").fetchone()
    state_now = snapshots.decode(blob)
    events_folded = state_now["events"]
    text = zlib.decompress(blob[5:]).replace(f'"events":{events_folded},'.encode(),
                                             f'"events":{2**64 * 4 + events_folded},'.encode())
    forged = struct.pack("<IB", len(text), 1) + zlib.compress(text)
    conn.execute("UPDATE state_snapshots SET state = ? WHERE t = ? AND seq = ? AND src = ?", (forged, t, seq, src))
    reseal_snapshots(store)
    assert snapshots.decode(forged, exact=True)["events"] == 2**64 * 4 + events_folded
    assert state.check_snapshots(store, "r1") == [(t, seq, src)]


@pytest.mark.parametrize("blob", [b"", b"\x05\x00\x00\x00", struct.pack("<IB", 2, 7) + zlib.compress(b"{}"),
                                  struct.pack("<IB", 2, 1) + zlib.compress(b"[]")])
def test_blobs_that_are_not_snapshots_decode_to_none(blob):
    assert snapshots.decode(blob) is None


@pytest.mark.parametrize("enabled", [True, False])
def test_reads_leave_the_garbage_collector_as_they_found_it(store, enabled):
    events = long_run(30)
    store.append(events)
    was = gc.isenabled()
    try:
        gc.enable() if enabled else gc.disable()
        state_at(store, "r1", events[-1]["t"])
        build_snapshots(store, "r1", every=5)
        state.check_snapshots(store, "r1")
        assert gc.isenabled() is enabled
        with pytest.raises(sqlite3.ProgrammingError):
            closed = Store(store.path)
            closed.close()
            state_at(closed, "r1", events[-1]["t"])
        assert gc.isenabled() is enabled
    finally:
        gc.enable() if was else gc.disable()
