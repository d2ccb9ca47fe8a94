"""For any store and any single-row tampering of its log, verify fails; for an event row it names a
chain position at or before the one tampered with, so nothing after the first reported problem
is trusted by mistake.

Tampering here is what an attacker with write access to the file can do in one step: change one
column of one row, delete one row, insert one row, or swap two rows' places in the chain.
"""

import hashlib
import sqlite3
import tempfile
from pathlib import Path

from hypothesis import HealthCheck, assume, given, settings, strategies as st
from tests.helpers.store_testkit import T0, event, rows, tamper

from store import Store, canonical_json

EVENT_COLUMNS = ("event", "hash", "t", "seq", "src", "kind", "chain_pos", "run")
CHECKPOINT_COLUMNS = ("count", "head", "merkle_root", "frontier", "prev_count", "run")


@st.composite
def stores(draw):
    """(checkpoint interval, list of append calls): up to two runs of up to 20 events from up
    to three sources, offered in any order and split into calls at random."""
    evs = []
    for run in ("r0", "r1")[: draw(st.integers(1, 2))]:
        next_seq = [0] * draw(st.integers(1, 3))
        for _ in range(draw(st.integers(1, 20))):
            source = draw(st.integers(0, len(next_seq) - 1))
            kind = draw(st.sampled_from(["vehicle.perception", "entity.state"]))
            t = T0 + draw(st.integers(0, 10**9))
            evs.append(event(next_seq[source], run=run, src=f"vehicle/{source}", t=t, kind=kind))
            next_seq[source] += 1
    evs = draw(st.permutations(evs))
    calls, start = [], 0
    while start < len(evs):
        size = draw(st.integers(1, len(evs) - start))
        calls.append(evs[start:start + size])
        start += size
    return draw(st.integers(1, 6)), calls


def build(db_path: Path, every: int, calls: list) -> None:
    with Store(db_path, checkpoint_every=every, durable=False) as store:
        for call in calls:
            store.append(call)
        assert store.verify().ok


def event_rows(db_path):
    return rows(db_path, "SELECT rowid, run, chain_pos, src, seq, t, kind, event, hash FROM events ORDER BY rowid")


def changed(column, row, draw):
    """A different value for one column of an event row, as an attacker would write it."""
    _, run, pos, src, seq, t, kind, text, digest = row
    if column == "event":
        i = draw(st.integers(0, len(text) - 1))
        new = draw(st.sampled_from("abcxyz019 {}\":,"))
        assume(new != text[i])
        return text[:i] + new + text[i + 1:]
    choices = {
        "hash": lambda: draw(st.sampled_from(["0" * 64, hashlib.sha256(b"forged").hexdigest(), digest.upper(), ""])),
        "t": lambda: t + draw(st.sampled_from([1, -1, 10**9])),
        "seq": lambda: seq + 10**6,
        "src": lambda: "vehicle/forged",
        "kind": lambda: draw(st.sampled_from(["entity.state", "vehicle.decision", "collision"])),
        "chain_pos": lambda: draw(st.sampled_from([-1, 10**6, pos + 1000])),
        "run": lambda: draw(st.sampled_from(["r0", "r1", "forged"])),
    }
    return choices[column]()


def apply(db_path, *statements) -> bool:
    """Tamper; False if the database itself refused (a UNIQUE constraint), so nothing changed."""
    try:
        tamper(db_path, *statements)
    except sqlite3.IntegrityError:
        return False
    return True


def tamper_an_event(db_path, draw):
    """Tamper with one event row; return (runs it could show in, chain position tampered)."""
    evs = event_rows(db_path)
    row = draw(st.sampled_from(evs))
    rowid, run, pos = row[0], row[1], row[2]
    how = draw(st.sampled_from(["update", "update", "update", "delete", "append", "swap"]))
    if how == "update":
        column = draw(st.sampled_from(EVENT_COLUMNS))
        value = changed(column, row, draw)
        assume(value != row[1 + ("run", "chain_pos", "src", "seq", "t", "kind", "event", "hash").index(column)])
        assume(apply(db_path, (f"UPDATE events SET {column} = ? WHERE rowid = ?", (value, rowid))))
        return {run, value} if column == "run" else {run}, pos
    if how == "delete":
        assume(apply(db_path, ("DELETE FROM events WHERE rowid = ?", (rowid,))))
        return {run}, pos
    if how == "append":  # a well-formed next event, correctly chained onto the run's head
        count = sum(1 for r in evs if r[1] == run)
        [(head,)] = rows(db_path, "SELECT hash FROM events WHERE run = ? AND chain_pos = ?", (run, count - 1))
        forged = event(10**6, run=run, src="vehicle/0", body={"facts": ["0 has green light"]})
        text = canonical_json(forged)
        digest = hashlib.sha256(bytes.fromhex(head) + text).hexdigest()
        assume(apply(db_path, ("INSERT INTO events (run, chain_pos, src, seq, t, kind, event, hash) "
                               "VALUES (?,?,?,?,?,?,?,?)",
                               (run, count, "vehicle/0", 10**6, forged["t"], forged["kind"], text.decode(), digest))))
        return {run}, count
    others = [r for r in evs if r[1] == run and r[2] != pos]
    assume(others)
    other = draw(st.sampled_from(others))
    move = "UPDATE events SET chain_pos = ? WHERE rowid = ?"
    assume(apply(db_path, (move, (-99, rowid)), (move, (pos, other[0])), (move, (other[2], rowid))))
    return {run}, min(pos, other[2])


def tamper_a_checkpoint(db_path, draw):
    checkpoints = rows(db_path, "SELECT id, run, count, head, merkle_root, frontier, prev_count FROM checkpoints")
    row = draw(st.sampled_from(checkpoints))
    how = draw(st.sampled_from(["update", "delete", "replay"]))
    if how == "delete":
        assume(apply(db_path, ("DELETE FROM checkpoints WHERE id = ?", (row[0],))))
    elif how == "replay":
        assume(apply(db_path, ("INSERT INTO checkpoints (run, count, head, created_at, merkle_root, frontier, prev_count) "
                        "VALUES (?, ?, ?, 0, ?, ?, ?)", row[1:])))
    else:
        column = draw(st.sampled_from(CHECKPOINT_COLUMNS))
        old = row[1 + ("run", "count", "head", "merkle_root", "frontier", "prev_count").index(column)]
        value = draw(st.sampled_from([0, 1, 5, -1, None, "r0", "r1", "ab" * 32, ""]))
        assume(value != old)
        assume(apply(db_path, (f"UPDATE checkpoints SET {column} = ? WHERE id = ?", (value, row[0]))))


@settings(deadline=None, max_examples=150, suppress_health_check=[HealthCheck.too_slow])
@given(stores(), st.data())
def test_any_single_row_tampering_is_caught_at_or_before_its_position(plan, data):
    every, calls = plan
    with tempfile.TemporaryDirectory() as folder:
        db_path = Path(folder) / "gaps.db"
        build(db_path, every, calls)
        runs, pos = tamper_an_event(db_path, data.draw)
        with Store(db_path) as store:
            report = store.verify()
    assert not report.ok
    assert report.problem.run in runs
    assert report.problem.chain_pos <= pos


@settings(deadline=None, max_examples=75, suppress_health_check=[HealthCheck.too_slow])
@given(stores(), st.data())
def test_any_single_checkpoint_tampering_is_caught(plan, data):
    every, calls = plan
    with tempfile.TemporaryDirectory() as folder:
        db_path = Path(folder) / "gaps.db"
        build(db_path, every, calls)
        tamper_a_checkpoint(db_path, data.draw)
        with Store(db_path) as store:
            assert not store.verify().ok
