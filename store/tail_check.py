"""Before an append extends a run read from the file, the run's tail is checked against its
last checkpoint and, with a checkpoint key, against the run's last signed head known outside the
file: otherwise the next ordinary append would write a checkpoint, signed or not, over events
someone put in the file behind the store's back, and seal them (issue 15, finding 4; issue 37).

Every append writes a checkpoint at the end of each run it extended, in the same transaction as
its events, so in a file only ever written by appends the latest checkpoint of a run (the one of
the highest count: ids are the file holder's to choose) covers its whole chain, and names the hash
of its last event. Events past it, a head that is not the last event's hash, or fewer events than
it covers were not written by an append: the append refuses (TamperedTail, exit 1) and writes
nothing. Its Merkle frontier must give its root; with the count and head checked against it, no
event lies past it to re-hash.

With a key, what the run must extend is decided outside the file (store/trust_root.py): the last
head of the run in the ingest's witness file (or the last this writer signed), else its first
signed head recorded in the key's public file. The latest checkpoint must then be signed by the
key, cover at least that head, and a checkpoint signed by the key must record that head (same
size, root and chain head). A run known to neither must end on a signed checkpoint if any of its
checkpoints carries a signature; only a run no checkpoint of which was ever signed may begin to be.

This costs a few queries and one or two signature checks per run, once per connection (the chain
is then kept in memory, store/heads.py), not per append.
"""

from __future__ import annotations

import sqlite3
from typing import Any, NoReturn

from . import merkle
from .chain import RunChain
from .errors import EvidenceError
from .keys.tree_heads import CheckpointKey, TreeHead
from .keys.trust_root import SignedRuns

_CHECKPOINTS = ("SELECT count, head, merkle_root, frontier, prev_count, created_at, signature, key_id, id, wire "
                "FROM checkpoints WHERE run = ?")


class TamperedTail(EvidenceError):
    """A run's stored tail does not follow from its last (signed) checkpoint: an append refuses to
    extend it, since its next checkpoint would vouch for events no append wrote."""


def anchored_chain(conn: sqlite3.Connection, run: str, key: CheckpointKey | None,
                   trust: SignedRuns | None = None, *, empty: bool = False) -> RunChain:
    """The run's chain as stored (head, Merkle frontier, latest checkpoint's count), after
    checking that its tail is the one its last checkpoint vouches for and, with `key`, that it
    extends the run's last signed head known outside the file (`trust`, store/trust_root.py).

    The latest checkpoint is the one of the highest count, never of the highest id: ids are the
    file holder's to choose (issue 37). `empty`: the caller found, in the same state of the file,
    that the run holds no events (store/heads.py's probe of a new run), so they are not looked
    for again; a run with no events is checked only against its signed head known outside the
    file, and its checkpoints are not read (a fleet's every new run cost two queries here, now none)."""
    last = None if empty else conn.execute(
        "SELECT chain_pos, hash FROM events WHERE run = ? ORDER BY chain_pos DESC LIMIT 1", (run,)).fetchone()
    known = None if key is None or trust is None else trust.last.get(run)
    if last is None:
        if known is not None:
            _refuse(run, f"holds no events, but its last signed head, in {known[1]}, covers {known[0].size}: "
                         "the run was deleted")
        return RunChain()
    count = last[0] + 1
    latest = conn.execute(f"{_CHECKPOINTS} ORDER BY count DESC, id DESC LIMIT 1", (run,)).fetchone()
    _check_latest(run, count, last[1], latest)
    (odd,) = conn.execute("SELECT count(*) FROM checkpoints WHERE run = ? AND NOT (id >= 1)", (run,)).fetchone()
    if odd:
        _refuse(run, f"has {odd} checkpoint(s) under an id no append writes (ids start at 1): put into the file "
                     "behind the store's back")
    if key is not None:
        _check_signed(conn, run, key, latest, trust)
    elif latest[6] is not None or latest[7] is not None:
        _refuse(run, f"ends on a checkpoint signed by key {latest[7]}, and an append without the checkpoint key would "
                     "leave it unsigned from here on (once a run is signed, every later checkpoint is): append with "
                     "the key (--checkpoint-key)", altered=False)
    frontier = _frontier(run, latest)
    if frontier is None:  # a v1 checkpoint (no frontier): the run's hashes, as before v2
        rows = conn.execute("SELECT hash FROM events WHERE run = ? ORDER BY chain_pos", (run,))
        frontier = merkle.frontier_of(_digest(run, stored) for (stored,) in rows)
    return RunChain(count, _digest(run, last[1]), frontier, latest[0])


def _check_latest(run: str, count: int, last_hash: Any, latest: tuple | None) -> None:
    covered = 0 if latest is None else latest[0]
    if not isinstance(covered, int):
        _refuse(run, f"has a latest checkpoint recording {covered!r} events, which no append writes")
    if count > covered:
        _refuse(run, f"holds {count} events but its latest checkpoint covers {covered}: events {covered} to "
                     f"{count - 1} were not written by an append (every append checkpoints what it wrote)")
    if count < covered:
        _refuse(run, f"holds {count} events but its latest checkpoint covers {covered}: events were removed")
    if latest is not None and latest[1] != last_hash:
        _refuse(run, f"ends on an event whose hash is not the head its latest checkpoint records "
                     f"(event {count - 1}): the tail was rewritten")


def _check_signed(conn: sqlite3.Connection, run: str, key: CheckpointKey, latest: tuple,
                  trust: SignedRuns | None) -> None:
    """With the key: a run whose last signed head is known outside the file (the witness, this
    writer) must end on a checkpoint signed by the key that extends that head; a run the key file
    records must hold one of the first heads it records, signed, and end on a signed checkpoint; a
    run known to neither must end on a signed checkpoint once any of its checkpoints carries a
    signature (only a run never signed may begin to be)."""
    problem = _signature_problem(run, latest, key)
    recorded = [] if trust is None else trust.first.get(run, [])
    match = next((head for head in recorded if _records(conn, run, key, head)), None)
    if trust is not None and match is not None:
        trust.here.add(run)
    known = None if trust is None else trust.last.get(run)
    if known is not None:
        _check_extends(conn, run, key, latest, problem, *known)
    elif trust is not None and recorded:  # (nothing is recorded without the key file)
        if match is None:
            sizes = ", ".join(str(head.size) for head in recorded)
            _refuse(run, f"holds no checkpoint signed by key {key.id} that records one of the first signed heads "
                         f"{trust.where()} records of it (of {sizes} events): its signatures were stripped or it was "
                         "rewritten (or it is a run of the same name in another store, signed before the key file "
                         "recorded runs)")
        if problem is not None:
            _refuse(run, f"has a latest checkpoint (of {latest[0]} events) that does not verify with key {key.id} "
                         f"({problem}), though the run was signed from {match.size} events on ({trust.where()}): "
                         "its tail was written behind the ingest's back")
    elif problem is not None:
        (marked,) = conn.execute("SELECT count(*) FROM checkpoints WHERE run = ? AND (signature IS NOT NULL OR "
                                 "key_id IS NOT NULL)", (run,)).fetchone()
        if marked:
            _refuse(run, f"has {marked} signed checkpoint(s) but its latest (of {latest[0]} events) does not verify "
                         f"with key {key.id}: {problem}; once a run is signed, every later checkpoint is")
        # never signed by anyone: signing begins here, and the key file records it


def _check_extends(conn: sqlite3.Connection, run: str, key: CheckpointKey, latest: tuple, problem: str | None,
                   head: TreeHead, where: str) -> None:
    if latest[0] < head.size:
        _refuse(run, f"holds {latest[0]} events, but its last signed head, in {where}, covers {head.size}: "
                     f"events {latest[0]} to {head.size - 1} were removed")
    if problem is not None:
        _refuse(run, f"has a latest checkpoint (of {latest[0]} events) that does not verify with key {key.id} "
                     f"({problem}), though the run was signed up to {head.size} events ({where}): its tail was "
                     "written behind the ingest's back")
    if not _records(conn, run, key, head):
        _refuse(run, f"does not extend its last signed head ({head.size} events, Merkle root {head.root[:12]}…, "
                     f"in {where}): no checkpoint signed by key {key.id} records it; the run was rewritten")


def _records(conn: sqlite3.Connection, run: str, key: CheckpointKey, head: TreeHead) -> bool:
    """Does a checkpoint of the run signed by the key record this head (size, root, chain head)?"""
    rows = conn.execute(f"{_CHECKPOINTS} AND count = ?", (run, head.size)).fetchall()
    return any(row[2] == head.root and row[1] == head.head and _signature_problem(run, row, key) is None
               for row in rows)


def _signature_problem(run: str, row: tuple, key: CheckpointKey) -> str | None:
    if row[6] is None:
        return "unsigned"
    if row[7] != key.id:
        return f"signed with key {row[7]}, not {key.id}"
    try:
        return _head_of(run, row).signature_problem(key.public)
    except (TypeError, ValueError) as exc:  # a wire column no append writes
        return f"its fields are not those of a checkpoint ({exc})"


def _head_of(run: str, row: tuple) -> TreeHead:
    count, head, root, _, prev, created_at, sig, kid, _, wire = row
    return TreeHead.of_checkpoint(run, count, root, head, prev, created_at, kid, sig, wire)


def _frontier(run: str, anchor: tuple) -> list[bytes] | None:
    """The anchor's Merkle frontier, which must give its root; None for a v1 checkpoint."""
    count, _, root, packed = anchor[:4]
    if packed is None and root is None:
        return None
    frontier = merkle.unpack(packed, count)
    if frontier is None or merkle.root_of_frontier(frontier).hex() != root:
        _refuse(run, f"its checkpoint of {count} events records a Merkle frontier that does not give its root")
    return frontier


def _refuse(run: str, what: str, *, altered: bool = True) -> NoReturn:
    if not altered:
        raise TamperedTail(f"run {run} {what}; nothing was appended to it")
    raise TamperedTail(f"run {run} {what}; the store was altered: nothing was appended to it "
                       f"(gaps verify names what changed)")


def _digest(run: str, stored: Any) -> bytes:
    """A stored hash as bytes; a non-hex value means the file was altered."""
    try:
        return bytes.fromhex(stored)
    except (TypeError, ValueError):
        raise TamperedTail(f"an event hash of run {run} is not a sha256 hex digest: the store was altered; "
                           "run gaps verify") from None

