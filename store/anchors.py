"""A store checked against what is kept outside it: signed tree heads (`gaps verify --against`)
and the checkpoint key (`gaps verify --key`).

`gaps verify` proves a store agrees with itself; someone holding the file can make a rewritten
or shortened store agree with itself too. A tree head kept elsewhere says "run r had `size`
events with Merkle root R": the store must still hold at least that many events of the run, the
first `size` of them, re-hashed from their text, must give R, and the run's latest head is shown
to be a prefix of the whole stored run by an RFC 6962 consistency proof (store/consistency.py).
That catches a run cut back (truncation, even to one of its own checkpoints), events forged at
its tail and sealed by a later append, a consistent rewrite of the whole run, and a deleted run.
A head written since schema v8 also records where the wire tables' chains (liveliness changes,
wire misses) stood (store/wire_ends.py): each table, re-hashed from its rows, must still have that
hash at that row, which catches rows cut off the end with their wire checkpoints, a table
rewritten or emptied. A head without that part (written before v8) checks the events only, and
its outcome says so (`wire`: "not covered"). A part that also records the stored rulebooks' end
(store/rulebook_chain.py) has that checked the same way, which catches a rulebook removed or its
name, version or text changed (`rulebooks`: "checked"; "not covered" for a part without it).

With the checkpoint key's public half, every checkpoint of a run from the first one that key
signed on must be signed by it, and its signature must hold over what the checkpoint records
(which verify checks against the events), and the wire tables' and rulebooks' ends it records
must hold in the store: a checkpoint added, a run rewritten, or a wire table or the rulebooks cut
back or rewritten, by someone without the key fails.
"""

from __future__ import annotations

import sqlite3
from dataclasses import asdict, dataclass, replace
from typing import Any, Sequence

from . import merkle, wire_ends
from .chain import GENESIS, link
from .consistency import RangeRoots, proof_ranges, verify_consistency
from .signatures import key_id
from .tree_heads import TreeHead


@dataclass(frozen=True)
class HeadOutcome:
    """What the store says to one tree head: ok, or what is wrong (`what`)."""

    run: str
    size: int
    root: str
    ok: bool
    stored: int                 # events of the run in the store
    outcome: str                # "matches", "consistent" (a proof from size to stored), or the failure's name
    what: str | None = None
    proof_nodes: int | None = None
    wire: str = "not covered"   # the wire tables' ends: "checked", "not covered" (a head before v8), "not checked"
    rulebooks: str = "not covered"  # the rulebooks' end: the same ("not covered": a head whose part lacks it)

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


def check_heads(conn: sqlite3.Connection, heads: Sequence[TreeHead], public: bytes | None) -> list[HeadOutcome]:
    """Each head checked against the store, in the order given; one pass over each run named."""
    by_run: dict[str, list[TreeHead]] = {}
    for head in heads:
        by_run.setdefault(head.run, []).append(head)
    found: dict[tuple[str, int, str], HeadOutcome] = {}
    for run, its_heads in by_run.items():
        for outcome in _check_run(conn, run, its_heads, public):
            found[(outcome.run, outcome.size, outcome.root)] = outcome
    outcomes = [found[(h.run, h.size, h.root)] for h in heads]
    return _with_wire(conn, heads, outcomes)


def _with_wire(conn: sqlite3.Connection, heads: Sequence[TreeHead], outcomes: list[HeadOutcome]) -> list[HeadOutcome]:
    """Each head whose events hold, and which records the wire tables' ends (and the rulebooks'),
    checked for those too (one pass over each table for all heads)."""
    ends = [end for head, o in zip(heads, outcomes) if o.ok and head.wire for end in head.wire]
    problems = wire_ends.problems(conn, ends)
    judged = []
    for head, outcome in zip(heads, outcomes):
        if head.wire is None:
            judged.append(outcome)
            continue
        books = "checked" if wire_ends.covers_rulebooks(head.wire) else "not covered"
        if not outcome.ok:
            judged.append(replace(outcome, wire="not checked",
                                  rulebooks="not checked" if books == "checked" else books))
            continue
        checked = replace(outcome, wire="checked", rulebooks=books)
        problem = wire_ends.first_problem(problems, head.wire)
        judged.append(checked if problem is None else replace(checked, ok=False, outcome=problem[0], what=problem[1]))
    return judged


def _check_run(conn: sqlite3.Connection, run: str, heads: list[TreeHead], public: bytes | None) -> list[HeadOutcome]:
    sizes = sorted({h.size for h in heads})
    latest = sizes[-1]
    roots, stored, proof = _walk(conn, run, sizes, latest)
    outcomes = []
    for head in heads:
        outcomes.append(_judge(head, roots, stored, proof if head.size == latest else None, public))
    return outcomes


def _walk(conn: sqlite3.Connection, run: str, sizes: list[int], latest: int
          ) -> tuple[dict[int, bytes], int, tuple[list[bytes], bytes] | None]:
    """Re-hash the run's events from their text, in one pass: the Merkle root at each size asked,
    the number of events, and the consistency proof from the latest size to the whole run, with
    its root (None if the run is shorter than that size)."""
    (last,) = conn.execute("SELECT max(chain_pos) FROM events WHERE run = ?", (run,)).fetchone()
    length = last + 1 if isinstance(last, int) else 0
    ranges = proof_ranges(latest, length) if length >= latest else []
    streamed = RangeRoots(ranges)
    wanted = set(sizes)
    roots: dict[int, bytes] = {}
    frontier: list[bytes] = []
    head, count = GENESIS, 0
    for (text,) in conn.execute("SELECT event FROM events WHERE run = ? ORDER BY chain_pos", (run,)):
        head = link(head, _bytes(text))
        merkle.push(frontier, count, head)
        streamed.feed(count, head)
        count += 1
        if count in wanted:
            roots[count] = merkle.root_of_frontier(frontier)
    if count < latest:
        return roots, count, None
    proof = streamed.proof(ranges)
    if count != length or proof is None:  # positions missing: the proof is not of the stored run
        return roots, count, ([], bytes(32))
    return roots, count, (proof, merkle.root_of_frontier(frontier))


def _bytes(text: Any) -> bytes:
    """A stored event's text as the bytes it was hashed as (anything else hashes as itself, and fails)."""
    if isinstance(text, bytes):
        return bytes(text)
    return str(text).encode("utf-8", "surrogatepass")


def _judge(head: TreeHead, roots: dict[int, bytes], stored: int,
           proof: tuple[list[bytes], bytes] | None, public: bytes | None) -> HeadOutcome:
    def failed(outcome: str, what: str) -> HeadOutcome:
        return HeadOutcome(head.run, head.size, head.root, False, stored, outcome, what)

    if public is not None:
        problem = head.signature_problem(public)
        if problem is not None:
            return failed("bad signature", f"the head is not signed by key {key_id(public)}: {problem}")
    if stored == 0:
        return failed("run missing", f"the store holds no events of run {head.run}, which had {head.size}: "
                                     "the run was deleted")
    if stored < head.size:
        return failed("truncated", f"the store holds {stored} events of run {head.run}, the head {head.size}: "
                                   f"events {stored} to {head.size - 1} were removed")
    root = roots[head.size].hex()
    if root != head.root:
        return failed("rewritten", f"the first {head.size} events of run {head.run} recompute to Merkle root "
                                   f"{root[:12]}…, the head records {head.root[:12]}…: they were rewritten")
    if proof is None:
        return HeadOutcome(head.run, head.size, head.root, True, stored, "matches")
    nodes, whole = proof
    if not verify_consistency(head.size, stored, bytes.fromhex(head.root), whole, nodes):
        return failed("inconsistent", f"no consistency proof from {head.size} to {stored} events holds")
    outcome = "matches" if stored == head.size else "consistent"
    return HeadOutcome(head.run, head.size, head.root, True, stored, outcome, None, len(nodes))


@dataclass(frozen=True)
class KeyCheck:
    """What `--key` found: signed checkpoints, and the first that should have been signed and is not."""

    key: str
    signed: int
    unsigned_before: int        # checkpoints before the key's first signature (not demanded)
    ok: bool
    problem: dict[str, Any] | None

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


def check_checkpoint_key(conn: sqlite3.Connection, public: bytes, run: str | None) -> KeyCheck:
    """From the first checkpoint `public` signed on (in the order written, any run), every
    checkpoint must be signed by it: a run rewritten, or a checkpoint added, after signing began
    shows as unsigned or signed by another key, even under the ids of the checkpoints it replaced.
    The wire tables' (and rulebooks') ends the signed checkpoints record (v8 on) must then hold in
    the store."""
    kid = key_id(public)
    (first,) = conn.execute("SELECT min(id) FROM checkpoints WHERE key_id = ?", (kid,)).fetchone()
    first = first if isinstance(first, int) else None
    where = "" if run is None else "WHERE run = ? "
    signed = unsigned_before = 0
    wired: list[TreeHead] = []
    sql = ("SELECT id, run, count, head, merkle_root, prev_count, created_at, signature, key_id, wire "
           f"FROM checkpoints {where}ORDER BY id")
    for row in conn.execute(sql, () if run is None else (run,)):
        if first is None or row[0] < first:
            unsigned_before += 1
            continue
        head, problem = _signed_head(row[1:], public)
        if problem is not None:
            name = row[1] if isinstance(row[1], str) else repr(row[1])
            return KeyCheck(kid, signed, unsigned_before, False, {"run": name, "count": row[2], "what": problem})
        if head is not None and head.wire:
            wired.append(head)
        signed += 1
    if not signed:
        what = f"no checkpoint{'' if run is None else ' of run ' + run} is signed by key {kid}"
        return KeyCheck(kid, 0, unsigned_before, False, {"run": run, "count": None, "what": what})
    wrong = _wire_problem(conn, wired, kid)
    return KeyCheck(kid, signed, unsigned_before, wrong is None, wrong)


def _wire_problem(conn: sqlite3.Connection, heads: list[TreeHead], kid: str) -> dict[str, Any] | None:
    """The first signed checkpoint (in the order written) whose wire tables' or rulebooks' ends the
    store no longer holds, as a KeyCheck problem; None if every one holds."""
    problems = wire_ends.problems(conn, [end for head in heads for end in head.wire or ()])
    for head in heads:
        problem = wire_ends.first_problem(problems, head.wire or ())
        if problem is not None:
            return {"run": head.run, "count": head.size,
                    "what": f"the checkpoint of {head.size} events of run {head.run}, signed by key {kid}, records "
                            f"{wire_ends.recorded_as(problem[0])}, and {problem[1]} ({problem[0]})"}
    return None


def _signed_head(row: tuple, public: bytes) -> tuple[TreeHead | None, str | None]:
    """The checkpoint row's tree head and, if its signature by `public` does not hold, why not."""
    name, count, head, root, prev, created_at, sig, kid, wire = row
    if sig is None:
        return None, (f"the checkpoint of {count} events is unsigned, after the run's checkpoints were signed by "
                      f"key {key_id(public)}: it was added behind the ingest's back")
    try:
        statement = TreeHead.of_checkpoint(name, count, root, head, prev, created_at, kid, sig, wire)
        problem = statement.signature_problem(public)
    except (TypeError, ValueError):
        return None, f"the checkpoint of {count} events: its fields are not those of a checkpoint"
    return statement, None if problem is None else f"the checkpoint of {count} events: {problem}"
