"""Attacks on a signed, witnessed store by someone who holds the store file but not the checkpoint
key (issue 37): rewrites whose checkpoints keep, zero or raise their ids, null a key id, or are
signed by another key; forged tails under an unsigned checkpoint at id 0 or 100, then extended by
an honest append; a run deleted or cut back. Each works on a copy of an honest store through raw
SQL (the append-only triggers dropped, as tests/helpers/store_testkit.tamper does), and each
changes what a verdict reads: an event's body, or events that no source sent.

Used by tests/store/test_store_trust_root.py, tests/fuzz/test_fuzz_checkpoints.py and the figures
script tests/helpers/trust_figures.py; it needs only what every version of the store offers (Store,
CheckpointKey, WitnessFile, canonical_json, the chain and Merkle functions), so that the script
can count what an older checkout catches too.
"""
from __future__ import annotations

import json
import random
import shutil
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Callable

from store import Store, canonical_json
from store.keys import CheckpointKey, TreeHead, WitnessFile, public_path_of
from store import merkle
from store.chain import GENESIS, link
from tests.helpers import store_testkit
from tests.helpers.store_testkit import rows

T0 = 1_732_184_100_000_000_000
SPAWN_SRC = "vehicle/253"


def perception(run: str, seq: int, facts: list[str] | None = None) -> dict[str, Any]:
    return {"v": 1, "run": run, "src": "vehicle/173", "seq": seq, "t": T0 + seq * 100_000_000,
            "kind": "vehicle.perception", "body": {"facts": facts or ["173 has red light"]}}


def spawn(run: str, vehicle_type: str) -> dict[str, Any]:
    return {"v": 1, "run": run, "src": SPAWN_SRC, "seq": 0, "t": T0, "kind": "entity.spawn",
            "body": {"type": vehicle_type, "driver": "human"}}


def r1_events() -> list[dict]:
    """Run r1: an ambulance spawns (what decides mitigated or punishable), then 25 perceptions."""
    return [spawn("r1", "ambulance")] + [perception("r1", i) for i in range(25)]


def r2_events() -> list[dict]:
    return [perception("r2", i) for i in range(4)]


@dataclass(frozen=True)
class Honest:
    """An honest store written by the key's holder in several appends, every checkpoint signed and
    witnessed: r1 (26 events, checkpoints every 8 and at each append's end), then r2 (4 events, one
    checkpoint). `public` is the investigator's copy of the key's public file, taken now."""

    db: Path
    witness: Path
    key_path: Path
    public: Path

    def key(self) -> CheckpointKey:
        return CheckpointKey.load(self.key_path)


def honest_store(folder: Path) -> Honest:
    folder.mkdir(parents=True, exist_ok=True)
    key_path = folder / "ckpt.key"
    CheckpointKey.create(key_path)
    key = CheckpointKey.load(key_path)
    db, witness_path = folder / "honest.db", folder / "witness.jsonl"
    witness = WitnessFile(witness_path)
    events = r1_events()
    with Store(db, checkpoint_key=key, checkpoint_every=8) as store:
        store.add_checkpoint_hook(witness.append)
        for lo, hi in ((0, 11), (11, 21), (21, 26)):
            store.append(events[lo:hi])
        store.append(r2_events())
    witness.close()
    public = folder / "investigator.pub"
    shutil.copy(public_path_of(key_path), public)
    return Honest(db, witness_path, key_path, public)


# --- raw access ----------------------------------------------------------------------------------


def tamper(db: Path, statements: list[tuple[str, tuple]]) -> None:
    """The statements run behind the store's back (store_testkit.tamper)."""
    store_testkit.tamper(db, *statements)


def stored_events(db: Path, run: str) -> list[dict]:
    return [json.loads(text) for (text,) in rows(db, "SELECT event FROM events WHERE run = ? ORDER BY chain_pos",
                                                 (run,))]


@dataclass(frozen=True)
class Checkpoint:
    """A checkpoint row as an honest append computes it (unsigned)."""

    count: int
    head: str
    root: str
    frontier: str
    prev: int


def chain_rows(run: str, events: list[dict], sizes: list[int]) -> tuple[list[tuple], list[Checkpoint]]:
    """The events rows of `events` and the honest checkpoints at `sizes` (sorted, the last the whole run)."""
    out, marks = [], []
    head, frontier, prev = GENESIS, [], 0
    for pos, ev in enumerate(events):
        text = canonical_json(ev)
        head = link(head, text)
        merkle.push(frontier, pos, head)
        out.append((run, pos, ev["src"], ev["seq"], ev["t"], ev["kind"], text.decode(), head.hex()))
        if pos + 1 in sizes:
            marks.append(Checkpoint(pos + 1, head.hex(), merkle.root_of_frontier(frontier).hex(),
                                    merkle.pack(frontier), prev))
            prev = pos + 1
    return out, marks


def wire_of(db: Path, run: str) -> str | None:
    found = rows(db, "SELECT wire FROM checkpoints WHERE run = ? ORDER BY count DESC LIMIT 1", (run,))
    return found[0][0] if found else None


def checkpoint_row(db: Path, run: str, mark: Checkpoint, ident: int, *, v1: bool = False,
                   key: CheckpointKey | None = None) -> tuple[str, tuple]:
    """An INSERT of `mark` under id `ident`: in v1 form (no root, frontier, previous count, wire:
    what a checkpoint at an id <= 0 was taken for), or modern, signed by `key` if given."""
    if v1:
        return ("INSERT INTO checkpoints (id, run, count, head, created_at) VALUES (?, ?, ?, ?, ?)",
                (ident, run, mark.count, mark.head, T0))
    wire = wire_of(db, run)
    sig = kid = None
    if key is not None:
        head = TreeHead.of_checkpoint(run, mark.count, mark.root, mark.head, mark.prev, T0, None, None, wire)
        signed = key.sign(head)
        sig, kid = signed.sig, signed.key
    return ("INSERT INTO checkpoints (id, run, count, head, created_at, merkle_root, frontier, prev_count, signature, "
            "key_id, wire) VALUES (?, ?, ?, ?, ?, ?, ?, ?, ?, ?, ?)",
            (ident, run, mark.count, mark.head, T0, mark.root, mark.frontier, mark.prev, sig, kid, wire))


def replace_run(db: Path, run: str, events: list[dict], sizes: list[int], ids: list[int], *, v1: bool = False,
                key: CheckpointKey | None = None, keep_below: int = 0) -> None:
    """The run's events from `keep_below` on and its checkpoints above `keep_below` replaced by
    `events` and honest checkpoints at `sizes` (under `ids`)."""
    new_rows, marks = chain_rows(run, events, sizes)
    marks = [m for m in marks if m.count > keep_below]
    if keep_below:
        last_kept = rows(db, "SELECT max(count) FROM checkpoints WHERE run = ? AND count <= ?", (run, keep_below))
        marks = [Checkpoint(m.count, m.head, m.root, m.frontier, last_kept[0][0] if i == 0 else m.prev)
                 for i, m in enumerate(marks)]
    statements = [("DELETE FROM events WHERE run = ? AND chain_pos >= ?", (run, keep_below)),
                  ("DELETE FROM checkpoints WHERE run = ? AND count > ?", (run, keep_below))]
    statements += [("INSERT INTO events VALUES (?, ?, ?, ?, ?, ?, ?, ?)", row) for row in new_rows[keep_below:]]
    statements += [checkpoint_row(db, run, mark, ident, v1=v1, key=key) for mark, ident in zip(marks, ids)]
    tamper(db, statements)


def checkpoint_ids(db: Path, run: str, above: int = 0) -> list[int]:
    return [i for (i,) in rows(db, "SELECT id FROM checkpoints WHERE run = ? AND count > ? ORDER BY id", (run, above))]


# --- the attacks ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class Attacked:
    """A store after an attack: `changed` says what a verdict now reads differently; `appended`:
    for a forged tail, whether the honest append on top of it was stored (True), refused (False),
    or not tried (None)."""

    db: Path
    witness: Path
    changed: str
    appended: bool | None = None


def rewrite_keep_ids(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """r1's ambulance made a car, the run re-chained and re-checkpointed (unsigned) under the ids
    of the checkpoints it replaces: below every id of r2, where signing 'began' by the ids."""
    ids = checkpoint_ids(copy, "r1")
    events = [spawn("r1", "car")] + r1_events()[1:]
    every = rng.choice([8, 13, 26])
    sizes = sorted({*range(every, 26, every), 26})[:len(ids)]
    sizes[-1] = 26
    replace_run(copy, "r1", events, sizes, ids)
    return Attacked(copy, honest.witness, "r1's ambulance is a car")


def rewrite_zero_id(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """r2 rewritten (a perception changed), its one checkpoint at an id <= 0 in the form a v1
    checkpoint has (no root, frontier, previous count), as if written before signing."""
    events = r2_events()
    at = rng.randrange(len(events))
    events[at] = perception("r2", at, ["173 has green light"])
    replace_run(copy, "r2", events, [len(events)], [rng.choice([0, -1, -7])], v1=True)
    return Attacked(copy, honest.witness, f"r2's event {at} sees a green light")


def rewrite_tail_null_key_id(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """r1 rewritten after one of its checkpoints, the tail re-checkpointed (unsigned) under a freed
    id; the key id of the untouched checkpoints before it nulled, so that the first id carrying
    the key's id is r2's."""
    kept = rng.choice([c for (c,) in rows(copy, "SELECT count FROM checkpoints WHERE run = 'r1' AND count < 26")])
    ids = checkpoint_ids(copy, "r1", kept)
    events = r1_events()
    at = rng.randrange(kept, 26)
    events[at] = perception("r1", events[at]["seq"], ["173 has green light"]) if at else spawn("r1", "car")
    replace_run(copy, "r1", events, [26], ids[:1], keep_below=kept)
    tamper(copy, [("UPDATE checkpoints SET key_id = NULL WHERE run = 'r1'", ())])
    return Attacked(copy, honest.witness, f"r1's event {at} sees a green light")


def rewrite_thief_key(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """r1's ambulance made a car, re-checkpointed and signed by a key the thief made."""
    thief = CheckpointKey.create(copy.with_suffix(f".thief{rng.randrange(1 << 30)}"))
    replace_run(copy, "r1", [spawn("r1", "car")] + r1_events()[1:], [8, 16, 24, 26], checkpoint_ids(copy, "r1"),
                key=thief)
    return Attacked(copy, honest.witness, "r1's ambulance is a car")


def rewrite_tail_high_id(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """r1's signed checkpoints after one of them deleted, its tail rewritten under one unsigned
    checkpoint at an id above every other."""
    kept = rng.choice([c for (c,) in rows(copy, "SELECT count FROM checkpoints WHERE run = 'r1' AND count < 26")])
    events = r1_events()
    at = rng.randrange(max(kept, 1), 26)
    events[at] = perception("r1", events[at]["seq"], ["173 has green light"])
    replace_run(copy, "r1", events, [26], [rng.choice([100, 1000, 2 ** 40])], keep_below=kept)
    return Attacked(copy, honest.witness, f"r1's event {at} sees a green light")


def delete_run(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    run = rng.choice(["r1", "r2"])
    tamper(copy, [("DELETE FROM events WHERE run = ?", (run,)), ("DELETE FROM checkpoints WHERE run = ?", (run,))])
    return Attacked(copy, honest.witness, f"run {run} is gone")


def truncate(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """r1 cut back to one of its own (signed) checkpoints."""
    cut = rng.choice([c for (c,) in rows(copy, "SELECT count FROM checkpoints WHERE run = 'r1' AND count < 26")])
    tamper(copy, [("DELETE FROM events WHERE run = 'r1' AND chain_pos >= ?", (cut,)),
                  ("DELETE FROM checkpoints WHERE run = 'r1' AND count > ?", (cut,))])
    return Attacked(copy, honest.witness, f"r1 ends after {cut} events")


def forge_tail(copy: Path, rng: random.Random, ident: int) -> int:
    """r2 given 1-5 forged events (a stop line ignored), its signed checkpoint replaced by an
    unsigned one over them at `ident` (in v1 form at an id <= 0); returns the run's length."""
    forged = rng.randint(1, 5)
    events = r2_events() + [perception("r2", seq, ["173 has no stop line"]) for seq in range(4, 4 + forged)]
    replace_run(copy, "r2", events, [len(events)], [ident], v1=ident <= 0)
    return len(events)


def honest_append(honest: Honest, copy: Path, key: CheckpointKey | None = None, witness: bool = True) -> bool:
    """The ingest, as `gaps serve --checkpoint-key KEY --witness W` runs it, stores one honest
    event of r2 on top: True if it was stored."""
    key = honest.key() if key is None else key
    sink = WitnessFile(honest.witness)
    try:
        kwargs = {"witness": honest.witness} if witness else {}
        try:
            with Store(copy, checkpoint_key=key, **kwargs) as store:
                store.add_checkpoint_hook(sink.append)
                seq = rows(copy, "SELECT max(seq) FROM events WHERE run = 'r2'")[0][0] + 1
                return store.append([perception("r2", seq, ["173 stopped"])]).stored == 1
        except TypeError:  # a store without the witness argument (before issue 37)
            with Store(copy, checkpoint_key=key) as store:
                store.add_checkpoint_hook(sink.append)
                seq = rows(copy, "SELECT max(seq) FROM events WHERE run = 'r2'")[0][0] + 1
                return store.append([perception("r2", seq, ["173 stopped"])]).stored == 1
    except Exception as exc:  # TamperedTail: refused
        if type(exc).__name__ != "TamperedTail":
            raise
        return False
    finally:
        sink.close()


def forged_tail_id0(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    forge_tail(copy, rng, rng.choice([0, -1]))
    return Attacked(copy, honest.witness, "r2 holds events no source sent", honest_append(honest, copy))


def forged_tail_id100(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    forge_tail(copy, rng, rng.choice([100, 5000]))
    return Attacked(copy, honest.witness, "r2 holds events no source sent", honest_append(honest, copy))


def forged_tail_sealed(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """The forged tail under an unsigned checkpoint at id 0 or 100, then sealed as the ingest did
    before issue 37: one honest event stored on top, its checkpoint signed by the real key over the
    forgery and its head appended to the witness (written here by hand, as that ingest wrote them)."""
    count = forge_tail(copy, rng, rng.choice([0, 100]))
    events = stored_events(copy, "r2") + [perception("r2", count, ["173 stopped"])]
    new_rows, marks = chain_rows("r2", events, [count + 1])
    mark = Checkpoint(count + 1, marks[0].head, marks[0].root, marks[0].frontier, count)
    top = rows(copy, "SELECT max(id) FROM checkpoints")[0][0]
    key = honest.key()
    insert = checkpoint_row(copy, "r2", mark, top + 1, key=key)
    tamper(copy, [("INSERT INTO events VALUES (?, ?, ?, ?, ?, ?, ?, ?)", new_rows[-1]), insert])
    sig, kid, wire = insert[1][8], insert[1][9], insert[1][10]
    head = TreeHead.of_checkpoint("r2", mark.count, mark.root, mark.head, mark.prev, T0, kid, sig, wire)
    sink = WitnessFile(honest.witness)
    sink.append([head])
    sink.close()
    return Attacked(copy, honest.witness, "r2 holds events no source sent, sealed by the key")


def _seed(key_path: Path) -> bytes:
    from store.keys.files import seed_of
    return seed_of(key_path.read_text("ascii"), str(key_path))


def untouched(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """No attack: every check must pass."""
    return Attacked(copy, honest.witness, "nothing")


def honest_after_witness_copy(honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """No attack either: the ingest goes on storing r2 after the investigator copied the witness
    (the copy's last head of r2 is older than the store's tail, which the key signed)."""
    stale = copy.with_suffix(".stale.jsonl")
    shutil.copy(honest.witness, stale)
    for _ in range(rng.randint(1, 3)):
        honest_append(honest, copy)
    return Attacked(copy, stale, "nothing (r2 grew after the witness was copied)", None)


ATTACKS: dict[str, Callable[[Honest, Path, random.Random], Attacked]] = {
    "none (untouched)": untouched,
    "none (witness copied before the last appends)": honest_after_witness_copy,
    "rewrite, ids kept": rewrite_keep_ids,
    "rewrite, id <= 0": rewrite_zero_id,
    "rewrite tail, key_id nulled": rewrite_tail_null_key_id,
    "rewrite, thief's key": rewrite_thief_key,
    "rewrite tail, high id": rewrite_tail_high_id,
    "run deleted": delete_run,
    "truncation": truncate,
    "forged tail, unsigned id <= 0": forged_tail_id0,
    "forged tail, unsigned id 100": forged_tail_id100,
    "forged tail sealed (pre-fix ingest)": forged_tail_sealed,
}


def attack(name: str, honest: Honest, copy: Path, rng: random.Random) -> Attacked:
    """A copy of the honest store (and of its witness, which the append may extend), attacked."""
    shutil.copy(honest.db, copy)
    witness = copy.with_suffix(".witness.jsonl")
    shutil.copy(honest.witness, witness)
    attacked_honest = Honest(honest.db, witness, honest.key_path, honest.public)
    return ATTACKS[name](attacked_honest, copy, rng)


CHECKS = {"plain": (), "--key": ("key",), "--against": ("against",), "--key --against": ("key", "against")}


def passes(attacked: Attacked, public: Path) -> dict[str, bool]:
    """Which of `gaps verify`, `--key PUB`, `--against WITNESS` and both pass (exit 0) on the store."""
    from tests.helpers.cli import gaps

    found = {}
    for name, parts in CHECKS.items():
        args = ["verify", "--no-snapshots", "--json"]
        args += ["--key", public] if "key" in parts else []
        args += ["--against", attacked.witness] if "against" in parts else []
        result = gaps(*args, db=attacked.db)
        assert result.exit_code in (0, 1), result.output
        found[name] = result.exit_code == 0
    return found
