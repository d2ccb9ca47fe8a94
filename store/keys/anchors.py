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

With the checkpoint key's public file (store/trust_root.py), nothing in the store decides what
must be signed: every run checked must end on a checkpoint signed by the key, every checkpoint
from the run's first signed head on (the one the key file records, else its first checkpoint the
key signed, in the order of counts, never of ids) must be signed by it, its signature must hold
over what the checkpoint records (which verify checks against the events), and the wire tables'
and rulebooks' ends it records must hold in the store: a checkpoint added, a run rewritten under
any ids, signatures stripped, a run the key file records deleted, or a wire table or the rulebooks
cut back or rewritten, by someone without the key fails. The heads of a witness must follow one
another (prev_size), so a head signed over a tail the witness never saw shows. Then, per run, what
the witness and the key prove of its stored events (RunProof): a run is proven only when every
stored event is (docs/guarantees.md).
"""

from __future__ import annotations

import sqlite3
from dataclasses import asdict, dataclass, field, replace
from typing import Any, Sequence, cast

from .. import merkle
from ..wire import ends as wire_ends
from ..chain import GENESIS, link
from ..consistency import RangeRoots, proof_ranges, verify_consistency
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
    return _linked(conn, heads, outcomes, public)


def _linked(conn: sqlite3.Connection, heads: list[TreeHead], outcomes: list[HeadOutcome],
            public: bytes | None) -> list[HeadOutcome]:
    """The run's heads, in the witness's order, must follow one another: each signed checkpoint
    names the size of the one before it (prev_size), and the ingest witnesses every one it signs.
    A head that follows a checkpoint the witness does not hold was signed over events no witnessed
    head covered (a tail forged and then sealed by an append); with the key, a run of checkpoints
    signed by it in the store that leads back to the witnessed head accounts for the gap (a witness
    write that failed)."""
    judged = list(outcomes)
    before: TreeHead | None = None
    for i, head in enumerate(heads):
        if before is not None and head.size > before.size and head.prev_size != before.size \
                and not _signed_between(conn, head, before.size, public):
            what = (f"the head of {head.size} events follows a checkpoint of {head.prev_size} events, but the "
                    f"witness's previous head of run {head.run} is of {before.size}: events {before.size} to "
                    f"{head.prev_size - 1} were sealed without a witnessed head (forged, or a witness write "
                    "failed: with --key, checkpoints signed by the key over them account for the latter)")
            judged[i] = replace(judged[i], ok=False, outcome="unwitnessed link", what=what)
        if before is None or head.size > before.size:
            before = head
    return judged


def _signed_between(conn: sqlite3.Connection, head: TreeHead, bottom: int, public: bytes | None) -> bool:
    """Do checkpoints signed by `public` lead from `head`'s previous size back to `bottom`?"""
    if public is None:
        return False
    at = head.prev_size
    while at > bottom:
        rows = conn.execute("SELECT count, head, merkle_root, prev_count, created_at, signature, key_id, wire "
                            "FROM checkpoints WHERE run = ? AND count = ?", (head.run, at)).fetchall()
        found = next((signed for signed, problem in (_signed_head((head.run, *row), public) for row in rows)
                      if problem is None), None)
        if found is None or found.prev_size >= at:
            return False
        at = found.prev_size
    return at == bottom


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
class KeyProblem:
    """The first thing wrong under the key: the run (None: the store holds none), the checkpoint's
    count where there is one, and what is wrong."""

    run: str | None
    count: Any                  # as stored: an int, unless the file holds something else there
    what: str

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "count": self.count, "what": self.what}


@dataclass(frozen=True)
class KeyedRun:
    """What the key proves of one run: of its `events`, those its latest signed checkpoint covers
    (`signed_through`), from which size every checkpoint must be signed (`since`) and whether the
    key file said so (`recorded`), the checkpoints signed and those before the first signed one;
    ok, or `what` is wrong."""

    run: str
    events: int
    signed_through: int
    since: Any                  # a checkpoint's count as stored (an int), or None
    recorded: bool
    signed: int
    unsigned_before: int
    ok: bool
    what: str | None

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "events": self.events, "signed_through": self.signed_through, "since": self.since,
                "recorded": self.recorded, "signed": self.signed, "unsigned_before": self.unsigned_before,
                "ok": self.ok, "what": self.what}


@dataclass(frozen=True)
class KeyCheck:
    """What `--key` found: signed checkpoints, and the first that should have been signed and is not.

    `runs` says, per run, what the key proves: `events` stored, `signed_through` (the events its
    latest signed checkpoint covers: all of them when ok), `since` (the size from which every
    checkpoint must be signed) and whether that came from the key file (`recorded`) or from the
    run's first checkpoint the key signed. `absent`: runs the key file records that the store does
    not hold (deleted, or signed into another store: the key file does not say which)."""

    key: str
    signed: int
    unsigned_before: int        # checkpoints before a run's first signed one (not demanded)
    ok: bool
    problem: KeyProblem | None
    runs: tuple[KeyedRun, ...] = ()
    absent: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {"key": self.key, "signed": self.signed, "unsigned_before": self.unsigned_before, "ok": self.ok,
                "problem": None if self.problem is None else self.problem.to_json(),
                "runs": [run.to_json() for run in self.runs], "absent": list(self.absent)}


_KEY_ROWS = ("SELECT count, head, merkle_root, prev_count, created_at, signature, key_id, wire FROM checkpoints "
             "WHERE run = ? ORDER BY count, id")


def check_checkpoint_key(conn: sqlite3.Connection, public: bytes, run: str | None,
                         recorded: Sequence[TreeHead] = ()) -> KeyCheck:
    """Every run checked (the one asked, else every run of the store) must be signed by `public`
    through its end, and, once signed, at every later checkpoint (in the order of their counts,
    which verify checks against the events, never of their ids, which the file's holder chooses).
    Where a run's signing began is read from the key file (`recorded`: the runs' first signed heads,
    store/trust_root.py): the run must hold one of the heads it records of it, signed; for a run it
    does not record, from its first checkpoint the key signed, which decides nothing the latest
    signed one does not prove. A checkpoint that carries a signature or key id must verify,
    wherever it is. The wire tables' (and rulebooks') ends the signed checkpoints record must then
    hold in the store."""
    kid = key_id(public)
    first: dict[str, list[TreeHead]] = {}
    for head in recorded:
        first.setdefault(head.run, []).append(head)
    stored = _runs(conn)
    names = [run] if run is not None else stored
    absent = tuple(sorted(name for name in first if name not in set(stored) and (run is None or name == run)))
    signed = unsigned_before = 0
    wired: list[TreeHead] = []
    runs = []
    problem = None
    for name in names:  # every run, so that the report says what the key proves of each
        found = _key_run(conn, name, public, first.get(name, []))
        signed += found.signed
        unsigned_before += found.unsigned_before
        runs.append(found.summary())
        problem = problem or found.problem
        if found.problem is None:
            wired += [head for head in found.heads if head.wire]
    if not names:
        what = f"no checkpoint is signed by key {kid}: the store holds no run"
        return KeyCheck(kid, 0, 0, False, KeyProblem(None, None, what), (), absent)
    problem = problem or _wire_problem(conn, wired, kid)
    return KeyCheck(kid, signed, unsigned_before, problem is None, problem, tuple(runs), absent)


def _runs(conn: sqlite3.Connection) -> list[Any]:
    rows = conn.execute("SELECT run FROM events UNION SELECT run FROM checkpoints")
    return sorted({name for (name,) in rows}, key=repr)


@dataclass
class _KeyRun:
    """One run under the key: its signed heads, what is proven and the first thing wrong."""

    run: Any
    events: int
    since: int | None = None
    recorded: bool = False
    signed: int = 0
    unsigned_before: int = 0
    signed_through: int = 0
    heads: list[TreeHead] = field(default_factory=list)
    problem: KeyProblem | None = None

    def fail(self, count: Any, what: str) -> _KeyRun:
        name = self.run if isinstance(self.run, str) else repr(self.run)
        self.problem = KeyProblem(name, count, f"run {name}: {what}")
        return self

    def summary(self) -> KeyedRun:
        return KeyedRun(self.run if isinstance(self.run, str) else repr(self.run), self.events, self.signed_through,
                        self.since, self.recorded, self.signed, self.unsigned_before, self.problem is None,
                        None if self.problem is None else self.problem.what)


def _key_run(conn: sqlite3.Connection, run: Any, public: bytes, recorded: list[TreeHead]) -> _KeyRun:
    kid = key_id(public)
    (last,) = conn.execute("SELECT max(chain_pos) FROM events WHERE run = ?", (run,)).fetchone()
    found = _KeyRun(run, last + 1 if isinstance(last, int) else 0)
    rows = conn.execute(_KEY_ROWS, (run,)).fetchall()
    if recorded:
        found.since = _recorded_size(run, rows, public, recorded)
        if found.since is None:
            sizes = ", ".join(str(head.size) for head in recorded)
            at = [row for row in rows if row[0] in {head.size for head in recorded}]
            problem = next((p for p in (_signed_head((run, *row), public)[1] for row in at) if p), None)
            if problem is not None:
                return found.fail(at[0][0], f"{problem}; the key file records the run's first signed head there")
            return found.fail(None, f"the key file records its first signed head (of {sizes} events), and no "
                                    f"checkpoint signed by key {kid} in the store records it: the run was rewritten "
                                    "or its signatures stripped (or it is another store's run of that name)")
        found.recorded = True
    for row in rows:
        count, sig, row_kid = row[0], row[5], row[6]
        must = found.since is not None and isinstance(count, int) and count >= found.since
        if sig is None and row_kid is None and not must:
            found.unsigned_before += 1
            continue
        head, problem = _signed_head((run, *row), public)
        if problem is not None:
            after = (f"; the run was signed from {found.since} events on, and once a run is signed every later "
                     "checkpoint is: it was written behind the ingest's back") if must else ""
            return found.fail(count, f"{problem}{after}")
        if found.since is None:
            found.since = count
        found.signed += 1
        found.heads.append(cast(TreeHead, head))  # its signature holds: a head
    if not rows:
        return found.fail(None, "it has no checkpoint")
    if not found.signed:
        return found.fail(rows[-1][0], f"no checkpoint is signed by key {kid}: nothing outside the file vouches "
                                       f"for its {found.events} events")
    found.signed_through = found.heads[-1].size
    if found.signed_through < found.events:
        return found.fail(found.signed_through, f"its latest signed checkpoint covers {found.signed_through} events "
                                                f"of {found.events}: events {found.signed_through} to "
                                                f"{found.events - 1} are vouched for by no signature")
    return found


def _recorded_size(run: Any, rows: list[tuple], public: bytes, recorded: list[TreeHead]) -> int | None:
    """The size of the first of the key file's heads of the run that a checkpoint signed by the
    key records (same size, root and chain head), or None."""
    wanted = {(head.size, head.root, head.head) for head in recorded}
    for row in rows:
        if (row[0], row[2], row[1]) in wanted and _signed_head((run, *row), public)[1] is None:
            return row[0]
    return None


def _wire_problem(conn: sqlite3.Connection, heads: list[TreeHead], kid: str) -> KeyProblem | None:
    """The first signed checkpoint (in the order written) whose wire tables' or rulebooks' ends the
    store no longer holds, as a KeyCheck problem; None if every one holds."""
    problems = wire_ends.problems(conn, [end for head in heads for end in head.wire or ()])
    for head in heads:
        problem = wire_ends.first_problem(problems, head.wire or ())
        if problem is not None:
            return KeyProblem(head.run, head.size,
                              f"the checkpoint of {head.size} events of run {head.run}, signed by key {kid}, records "
                              f"{wire_ends.recorded_as(problem[0])}, and {problem[1]} ({problem[0]})")
    return None


def _signed_head(row: tuple, public: bytes) -> tuple[TreeHead | None, str | None]:
    """The checkpoint row's tree head and, if its signature by `public` does not hold, why not."""
    name, count, head, root, prev, created_at, sig, kid, wire = row
    if sig is None:
        return None, f"the checkpoint of {count} events is unsigned"
    try:
        statement = TreeHead.of_checkpoint(name, count, root, head, prev, created_at, kid, sig, wire)
        problem = statement.signature_problem(public)
    except (TypeError, ValueError):
        return None, f"the checkpoint of {count} events: its fields are not those of a checkpoint"
    return statement, None if problem is None else f"the checkpoint of {count} events: {problem}"


@dataclass(frozen=True)
class RunProof:
    """What was proven of one run by what is kept outside the store: of its `events`, the first
    `witnessed` by the witness's heads that held (None: no witness given), the first `signed` by
    checkpoints the key signed (None: no key given); `proven` is the larger, and the run is ok only
    when every stored event is proven and nothing checked failed (`what` says what did)."""

    run: str
    events: int
    witnessed: int | None
    signed: int | None
    proven: int
    ok: bool
    what: str | None = None

    def to_json(self) -> dict[str, Any]:
        return asdict(self)


def prove_runs(conn: sqlite3.Connection, run: str | None, heads: Sequence[TreeHead], outcomes: Sequence[HeadOutcome],
               keyed: KeyCheck | None, witness: bool = True) -> list[RunProof]:
    """Per run (the one asked, else every run of the store and of the witness), how many of its
    stored events the witness and the key prove: a run the witness names that the store lacks
    fails, and so does a run the witness or the key failed on, or a run, or a tail, that neither
    covers."""
    witnessed: dict[str, int] = {}
    failed: dict[str, str] = {}
    for head, outcome in zip(heads, outcomes):
        if outcome.ok:
            witnessed[head.run] = max(witnessed.get(head.run, 0), head.size)
        else:
            failed.setdefault(head.run, f"the witness's head of {head.size} events: {outcome.what}")
    by_key = {entry.run: entry for entry in (keyed.runs if keyed is not None else ())}
    for entry in by_key.values():
        if not entry.ok:
            failed.setdefault(entry.run, cast(str, entry.what))   # a run not ok says what is wrong
    if run is not None:
        names = [run]
    else:
        rows = conn.execute("SELECT run FROM events UNION SELECT run FROM checkpoints")
        names = sorted({name for (name,) in rows if isinstance(name, str)} | {h.run for h in heads})
    proofs = []
    for name in names:
        (last,) = conn.execute("SELECT max(chain_pos) FROM events WHERE run = ?", (name,)).fetchone()
        events = last + 1 if isinstance(last, int) else 0
        seen = witnessed.get(name, 0) if witness else None
        keyed_run = by_key.get(name)
        signed = None if keyed is None else (keyed_run.signed_through if keyed_run and keyed_run.ok else 0)
        proven = max(seen or 0, signed or 0)
        what = failed.get(name)
        if what is None and proven < events:
            what = _unproven(proven, events, witness, keyed)
        proofs.append(RunProof(name, events, seen, signed, proven, what is None, what))
    return proofs


def _unproven(proven: int, events: int, witness: bool, keyed: KeyCheck | None) -> str:
    by = " nor ".join(by for by, given in (("no witnessed head", witness), ("no signed checkpoint", keyed)) if given)
    if keyed is None:
        by += " (give --key to prove what the ingest signed since the witness's last head)"
    which = (f"event {proven} of {events} is" if proven == events - 1
             else f"events {proven} to {events - 1} of {events} are")
    return f"{which} covered by {by}: nothing outside the file vouches for them"


@dataclass(frozen=True)
class AnchorReport:
    """The store against everything kept outside it: each witness head, the key, and per run what
    they prove together (`runs`); ok only if every part is."""

    heads: list[HeadOutcome]
    key: KeyCheck | None
    runs: list[RunProof]

    @property
    def ok(self) -> bool:
        return all(o.ok for o in self.heads) and (self.key is None or self.key.ok) and all(r.ok for r in self.runs)
