"""Checkpoint rows fuzzed (issue 37): someone holding a signed, witnessed store but not the key
rewrites an event of a run (re-chaining it and recomputing the run's checkpoints, so that the file
agrees with itself), then edits the run's checkpoint rows at random: ids (0, negative, huge,
another row's), key ids (nulled, another key's, made up), signatures (nulled, another row's, a
thief's over the same statement), counts and previous counts, rows deleted or copied. Whatever the
edits, `gaps verify --key PUB` and `gaps verify --against WITNESS` never pass a store whose events
differ from the ones the key signed; with the events untouched, every check ends in exit 0 or 1."""
from __future__ import annotations

import random
import shutil
import tempfile
from pathlib import Path

from hypothesis import event, given
from hypothesis import strategies as st

from store.keys import CheckpointKey, TreeHead
from tests.fuzz.budget import fuzz
from tests.helpers.trust_attacks import (
    Attacked, chain_rows, honest_store, passes, perception, r1_events, r2_events, rows, spawn, tamper,
)

FOLDER = Path(tempfile.mkdtemp(prefix="gaps-fuzz-checkpoints-"))
HONEST = honest_store(FOLDER / "honest")
THIEF = CheckpointKey.create(FOLDER / "thief.key")
EVENTS = {"r1": r1_events(), "r2": r2_events()}
COLUMNS = ("id", "run", "count", "head", "created_at", "merkle_root", "frontier", "prev_count", "signature",
           "key_id", "wire")

EDITS = st.sampled_from(["id", "key_id", "signature", "count", "prev_count", "delete", "copy", "resign"])


def changed_events(run: str, at: int, how: str) -> list[dict]:
    events = [dict(ev) for ev in EVENTS[run]]
    if how == "body":
        if events[at]["kind"] == "entity.spawn":
            events[at] = spawn(run, "car")
        else:
            events[at] = perception(run, events[at]["seq"], ["173 has green light"])
    elif how == "drop":
        del events[at]
    else:  # a forged event inserted
        events.insert(at, perception(run, 1000 + at, ["173 has no stop line"]))
    return events


def rechained(db: Path, run: str, events: list[dict]) -> None:
    """The run's events replaced and its checkpoints recomputed at the same sizes (unsigned) under
    the same ids, as a holder of the file who wants it to agree with itself would."""
    sizes = sorted({min(c, len(events)) for (c,) in rows(db, "SELECT count FROM checkpoints WHERE run = ?", (run,))}
                   | {len(events)})
    ids = [i for (i,) in rows(db, "SELECT id FROM checkpoints WHERE run = ? ORDER BY id", (run,))]
    ids += [max(ids) + 1000 + k for k in range(len(sizes) - len(ids))]
    wire = rows(db, "SELECT wire FROM checkpoints WHERE run = ? ORDER BY count DESC LIMIT 1", (run,))[0][0]
    new_rows, marks = chain_rows(run, events, sizes)
    statements = [("DELETE FROM events WHERE run = ?", (run,)), ("DELETE FROM checkpoints WHERE run = ?", (run,))]
    statements += [("INSERT INTO events VALUES (?, ?, ?, ?, ?, ?, ?, ?)", row) for row in new_rows]
    statements += [("INSERT INTO checkpoints VALUES (?, ?, ?, ?, ?, ?, ?, ?, NULL, NULL, ?)",
                    (ident, run, m.count, m.head, 0, m.root, m.frontier, m.prev, wire)) for m, ident in zip(marks, ids)]
    tamper(db, statements)


def edit_rows(db: Path, run: str, edits: list[tuple[str, int, int]]) -> None:
    """Each edit: (what, which checkpoint of the run, a number to draw values from)."""
    honest_rows = rows(HONEST.db, "SELECT * FROM checkpoints ORDER BY id")
    for what, pick, draw in edits:
        mine = rows(db, "SELECT * FROM checkpoints WHERE run = ? ORDER BY id", (run,))
        if not mine:
            return
        row = dict(zip(COLUMNS, mine[pick % len(mine)]))
        rng = random.Random(draw)
        other = dict(zip(COLUMNS, rng.choice(honest_rows)))
        where = ("WHERE rowid = ?", (row["id"],))
        if what == "delete":
            tamper(db, [(f"DELETE FROM checkpoints {where[0]}", where[1])])
            continue
        if what == "copy":
            values = {**row, "id": rng.choice([0, -5, 10 ** 6 + draw])}
            tamper(db, [(f"INSERT OR IGNORE INTO checkpoints VALUES ({', '.join('?' * len(COLUMNS))})",
                         tuple(values[c] for c in COLUMNS))])
            continue
        if what == "resign":  # a statement of what the row records, signed by a key the thief holds
            head = TreeHead.of_checkpoint(run, row["count"], row["merkle_root"], row["head"], row["prev_count"] or 0,
                                          row["created_at"], None, None, row["wire"])
            signed = (THIEF if draw % 2 else CheckpointKey(bytes(32))).sign(head)
            value = {"signature": signed.sig, "key_id": signed.key if draw % 3 else other["key_id"]}
        else:
            value = {"id": rng.choice([0, -1, 10 ** 9, other["id"]]),
                     "key_id": rng.choice([None, other["key_id"], THIEF.id, "0123456789abcdef"]),
                     "signature": rng.choice([None, other["signature"]]),
                     "count": rng.choice([row["count"] + 1, row["count"] - 1, other["count"]]),
                     "prev_count": rng.choice([0, other["prev_count"], (row["prev_count"] or 0) + 1])}
            value = {what: value[what]}
        sets = ", ".join(f"{column} = ?" for column in value)
        tamper(db, [(f"UPDATE OR IGNORE checkpoints SET {sets} {where[0]}", (*value.values(), *where[1]))])


@fuzz(15)
@given(run=st.sampled_from(["r1", "r2"]), at=st.integers(0, 30), how=st.sampled_from(["body", "drop", "insert",
                                                                                           "none"]),
       edits=st.lists(st.tuples(EDITS, st.integers(0, 10), st.integers(0, 1 << 20)), max_size=4))
def test_checkpoint_edits_never_pass_key_or_against_over_changed_events(run, at, how, edits):
    with tempfile.TemporaryDirectory(dir=FOLDER) as folder:
        db = Path(folder) / "s.db"
        shutil.copy(HONEST.db, db)
        at %= len(EVENTS[run])
        if how != "none":
            rechained(db, run, changed_events(run, at, how))
        edit_rows(db, run, edits)
        found = passes(Attacked(db, HONEST.witness, how), HONEST.public)
        stored = [text for (text,) in rows(db, "SELECT event FROM events WHERE run = ? ORDER BY chain_pos", (run,))]
        honest = [text for (text,) in rows(HONEST.db, "SELECT event FROM events WHERE run = ? ORDER BY chain_pos",
                                           (run,))]
        plain = "passes" if found["plain"] else "fails"
        event(f"events {'changed' if stored != honest else 'untouched'}, plain verify {plain}")
        if stored != honest:  # what a verdict reads has changed
            assert not found["--key"], (run, at, how, edits)
            assert not found["--against"], (run, at, how, edits)
