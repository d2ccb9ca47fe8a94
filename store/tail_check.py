"""Before an append extends a run read from the file, the run's tail is checked against its
last checkpoint (and, with a checkpoint key, its last signed one): otherwise the next ordinary
append would write a checkpoint, signed or not, over events someone put in the file behind the
store's back, and seal them (issue 15, finding 4).

Every append writes a checkpoint at the end of each run it extended, in the same transaction as
its events, so in a file only ever written by appends the latest checkpoint of a run covers its
whole chain, and names the hash of its last event. Events past it, a head that is not the last
event's hash, fewer events than it covers, or (with a key) checkpoints after the last one that
key signed, were not written by an append: the append refuses (TamperedTail, exit 1) and writes
nothing. The latest checkpoint's signature is checked, and its Merkle frontier must give its root;
with the count and head checked against it, no event lies past it to re-hash.

This costs a few queries and one signature check per run, once per connection (the chain is
then kept in memory, store/heads.py), not per append.
"""

from __future__ import annotations

import sqlite3
from typing import Any

from . import merkle
from .chain import RunChain
from .errors import EvidenceError
from .tree_heads import CheckpointKey, TreeHead

_CHECKPOINTS = ("SELECT count, head, merkle_root, frontier, prev_count, created_at, signature, key_id, id, wire "
                "FROM checkpoints WHERE run = ?")


class TamperedTail(EvidenceError):
    """A run's stored tail does not follow from its last (signed) checkpoint: an append refuses to
    extend it, since its next checkpoint would vouch for events no append wrote."""


def anchored_chain(conn: sqlite3.Connection, run: str, key: CheckpointKey | None) -> RunChain:
    """The run's chain as stored (head, Merkle frontier, latest checkpoint's count), after
    checking that its tail is the one its last checkpoint (signed by `key`, if given) vouches for."""
    last = conn.execute("SELECT chain_pos, hash FROM events WHERE run = ? ORDER BY chain_pos DESC LIMIT 1",
                        (run,)).fetchone()
    latest = conn.execute(f"{_CHECKPOINTS} ORDER BY id DESC LIMIT 1", (run,)).fetchone()
    count = 0 if last is None else last[0] + 1
    _check_latest(run, count, None if last is None else last[1], latest)
    if last is None:
        return RunChain()
    _check_signed(conn, run, key, latest)
    frontier = _frontier(run, latest)
    if frontier is None:  # a v1 checkpoint (no frontier): the run's hashes, as before v2
        rows = conn.execute("SELECT hash FROM events WHERE run = ? ORDER BY chain_pos", (run,))
        frontier = merkle.frontier_of(_digest(run, stored) for (stored,) in rows)
    return RunChain(count, _digest(run, last[1]), frontier, latest[0])


def _check_latest(run: str, count: int, last_hash: Any, latest: tuple | None) -> None:
    covered = 0 if latest is None else latest[0]
    if count > covered:
        _refuse(run, f"holds {count} events but its latest checkpoint covers {covered}: events {covered} to "
                     f"{count - 1} were not written by an append (every append checkpoints what it wrote)")
    if count < covered:
        _refuse(run, f"holds {count} events but its latest checkpoint covers {covered}: events were removed")
    if latest is not None and latest[1] != last_hash:
        _refuse(run, f"ends on an event whose hash is not the head its latest checkpoint records "
                     f"(event {count - 1}): the tail was rewritten")


def _check_signed(conn: sqlite3.Connection, run: str, key: CheckpointKey | None, latest: tuple) -> None:
    """With a key that has begun signing (any run's checkpoint before the latest signed by it), the
    latest must be signed by that key, and its signature must hold over what it records."""
    if key is None:
        return
    (first,) = conn.execute("SELECT min(id) FROM checkpoints WHERE key_id = ?", (key.id,)).fetchone()
    if first is None or latest[8] < first:
        return  # the key has signed nothing before: signing starts here
    if latest[7] != key.id:
        _refuse(run, f"has a latest checkpoint (of {latest[0]} events) written after key {key.id} began signing "
                     f"that this key did not sign: it was added behind the ingest's back")
    try:
        problem = _head_of(run, latest).signature_problem(key.public)
    except (TypeError, ValueError) as exc:  # a wire column no append writes
        problem = f"its fields are not those of a checkpoint ({exc})"
    if problem is not None:
        _refuse(run, f"its latest checkpoint (of {latest[0]} events) does not verify: {problem}")


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


def _refuse(run: str, what: str) -> None:
    raise TamperedTail(f"run {run} {what}; the store was altered: nothing was appended to it "
                       f"(gaps verify names what changed)")


def _digest(run: str, stored: Any) -> bytes:
    """A stored hash as bytes; a non-hex value means the file was altered."""
    try:
        return bytes.fromhex(stored)
    except (TypeError, ValueError):
        raise TamperedTail(f"an event hash of run {run} is not a sha256 hex digest: the store was altered; "
                           "run gaps verify") from None

