"""Recomputing every hash chain and Merkle tree from the stored event text, to prove the log
was not altered.

Nothing stored is trusted: hashes, index columns, chain positions and checkpoints are all
checked against the event text, and the report names the first event that does not match, so
an investigator knows where the record stops being reliable. Checkpoints are checked as a
sequence too: each names the count of the one before it, so removing, adding or reordering one
shows. The wire tables and the stored rulebooks are chains too, whose ends every checkpoint
records (store/wire_ends.py, store/rulebook_chain.py). (The checkpoints' created_at, the
quarantine, and a rulebook put after the last checkpoint are not covered: docs/store.md.)
"""

from __future__ import annotations

import hashlib
import json
import sqlite3
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any, Callable, Iterator

from . import merkle
from .wire import ends as wire_ends
from .canonical import canonical_json
from .chain import GENESIS, link
from .integrity import integrity_problem, integrity_problems
from .wire.liveliness import wire_problem
from .verify_report import IntegrityResult, Problem, RunCheck, SignatureCount, VerifyReport
from .reading import one_snapshot
from .keys.tally import SignatureTally

_COLUMNS = ("run", "src", "seq", "t", "kind")
_PROGRESS_EVERY = 1 << 14  # events between two progress calls

Progress = Callable[[int, int], None]  # (events checked so far, events to check)
IntegrityCheck = Callable[[sqlite3.Connection], list[str]]  # the file's integrity problems ([] if none)


def verify_store(conn: sqlite3.Connection, run: str | None = None, progress: Progress | None = None,
                 keys: Any = None, integrity: IntegrityCheck = integrity_problems) -> VerifyReport:
    """Check one run, or every run and every rulebook, and the file's own integrity (SQLite's
    check: store/integrity.py); count the signed events, and with `keys` (store.TrustedKeys)
    check each signature against the keys trusted for its source.

    Everything is read in one read transaction: a store being appended to is verified as it was
    at one moment, never as checkpoints from before a commit beside events from after it."""
    with one_snapshot(conn), tolerant_text(conn):
        try:
            return _verify(conn, run, progress, keys, integrity)
        except sqlite3.DatabaseError as exc:  # a page SQLite cannot read: the walk cannot go on
            return _unreadable(exc, keys)


def _unreadable(exc: sqlite3.DatabaseError, keys: Any) -> VerifyReport:
    what = f"SQLite cannot read the store file: {exc}: it is damaged, and nothing in it can be vouched for"
    return VerifyReport(ok=False, runs=(), problem=_problem(None, None, None, None, what),
                        signatures=_counted(SignatureTally(keys)), integrity=IntegrityResult(False, (str(exc),)))


def _counted(tally: SignatureTally) -> SignatureCount:
    return SignatureCount.from_json(tally.to_json())


def _typed(problem: dict[str, Any] | None) -> Problem | None:
    """A problem another module states as its JSON (store/integrity.py, store/liveliness.py)."""
    return None if problem is None else Problem.from_json(problem)


class NotUtf8(bytes):
    """A TEXT value whose bytes are not UTF-8: sqlite3 would raise on it and end the verify with a
    traceback; verify names the event instead (issue 15, finding 6)."""


def _decoded(data: bytes) -> str | NotUtf8:
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError:
        return NotUtf8(data)


@contextmanager
def tolerant_text(conn: sqlite3.Connection) -> Iterator[None]:
    """Read TEXT values that are not UTF-8 as NotUtf8 within the block (a verify, and what its
    caller reads beside it)."""
    before = conn.text_factory
    conn.text_factory = _decoded
    try:
        yield
    finally:
        conn.text_factory = before


def _verify(conn: sqlite3.Connection, run: str | None, progress: Progress | None, keys: Any,
            integrity: IntegrityCheck) -> VerifyReport:
    messages = integrity(conn)
    names = [run] if run is not None else _all_runs(conn)
    ticker = _Ticker(progress, _event_total(conn, run) if progress else 0)
    legacy = _legacy_through(conn)
    tally = SignatureTally(keys)
    summaries: list[RunCheck] = []
    problems: list[Problem | None] = []
    for name in names:
        summary, problem = _verify_run(conn, name, legacy, ticker, tally, required=run is not None)
        summaries.append(summary)
        problems.append(problem)
    if run is None:
        problems.append(_verify_rulebooks(conn))
    problems.append(_verify_wire(conn, run))
    problems.append(_typed(integrity_problem(messages)))
    ticker.done()
    first = next((problem for problem in problems if problem is not None), None)
    return VerifyReport(ok=first is None, runs=tuple(summaries), problem=first, signatures=_counted(tally),
                        integrity=IntegrityResult(not messages, tuple(messages)))


def _all_runs(conn: sqlite3.Connection) -> list[str]:
    """Runs with events or checkpoints: a run whose events were all deleted still has the latter."""
    rows = conn.execute("SELECT run FROM events UNION SELECT run FROM checkpoints ORDER BY run")
    return [name for (name,) in rows]


def _event_total(conn: sqlite3.Connection, run: str | None) -> int:
    if run is None:
        return conn.execute("SELECT count(*) FROM events").fetchone()[0]
    return conn.execute("SELECT count(*) FROM events WHERE run = ?", (run,)).fetchone()[0]


def _legacy_through(conn: sqlite3.Connection) -> int:
    """Checkpoints up to this id were written by v1, without Merkle root, frontier and
    prev_count; a file whose legacy record was deleted is held to v2 throughout."""
    (through,) = conn.execute("SELECT min(through_id) FROM legacy_checkpoints").fetchone()
    return through if isinstance(through, int) else 0


class _Ticker:
    """Calls progress(done, total) every _PROGRESS_EVERY events, and once at the end."""

    def __init__(self, progress: Progress | None, total: int) -> None:
        self.progress = progress
        self.total = total
        self.count = 0

    def tick(self) -> None:
        self.count += 1
        if self.progress is not None and self.count % _PROGRESS_EVERY == 0:
            self.progress(self.count, self.total)

    def done(self) -> None:
        if self.progress is not None:
            self.progress(self.count, max(self.total, self.count))


@dataclass
class _Checkpoint:
    id: int
    count: Any
    head: Any
    merkle_root: Any
    frontier: Any
    fault: str | None  # what is wrong with it as a member of the run's sequence of checkpoints


def _checkpoints(conn: sqlite3.Connection, run: str, legacy: int) -> dict[int, list[_Checkpoint]]:
    """count -> checkpoints recorded for that count, each judged against the one before it."""
    recorded: dict[int, list[_Checkpoint]] = {}
    before = 0  # count of the previous checkpoint, in id order
    rows = conn.execute(
        "SELECT id, count, head, merkle_root, frontier, prev_count, signature FROM checkpoints WHERE run = ? "
        "ORDER BY id", (run,),
    )
    for id_, count, head, root, frontier, prev, signature in rows:
        fault = _sequence_fault(id_ > legacy, count, before, root, frontier, prev, signature is not None)
        if not (isinstance(id_, int) and id_ >= 1):
            fault = (f"the checkpoint of {_show(count)} events is recorded under id {_show(id_)}, which no append "
                     "writes (ids start at 1): it was put into the file behind the store's back")
        at = count if isinstance(count, int) and count > 0 else 1
        recorded.setdefault(at, []).append(_Checkpoint(id_, count, head, root, frontier, fault))
        before = count
    return recorded


def _sequence_fault(modern: bool, count: Any, before: Any, root: Any, frontier: Any, prev: Any,
                    signed: bool = False) -> str | None:
    name = f"the checkpoint of {_show(count)} events"
    if modern and (root is None or frontier is None or prev is None):
        return f"{name} lacks the Merkle root, frontier or previous count every checkpoint since v2 records"
    if not modern and (root is not None or frontier is not None or prev is not None or signed):
        return (f"{name} carries a Merkle root, frontier, previous count or signature, which no v1 checkpoint has, "
                "yet the legacy record excuses it as one: the legacy record was raised")
    if not isinstance(count, int) or count < 1:
        return f"{name} records an impossible event count"
    if isinstance(before, int) and count <= before:
        return f"{name} is recorded after one of {before} events: checkpoints were reordered or added"
    if prev is not None and prev != before:
        return (
            f"{name} follows a checkpoint of {_show(prev)} events, but the one recorded before it "
            f"is of {_show(before)}: a checkpoint was removed, added or changed"
        )
    return None


def _verify_run(
    conn: sqlite3.Connection, run: str, legacy: int, ticker: _Ticker, tally: SignatureTally, *, required: bool
) -> tuple[RunCheck, Problem | None]:
    if not isinstance(run, str) or isinstance(run, NotUtf8):
        return _foreign_run(run)
    walk = _Walk(run, _checkpoints(conn, run, legacy), tally)
    rows = conn.execute(
        "SELECT chain_pos, src, seq, t, kind, event, hash FROM events WHERE run = ? ORDER BY chain_pos",
        (run,),
    )
    for row in rows:
        walk.feed(row)
        ticker.tick()
    walk.finish(required=required)
    ok = walk.problem is None
    return RunCheck(run, walk.rows, walk.head.hex() if ok else None, ok, walk.signed, walk.unsigned), walk.problem


def _foreign_run(run: Any) -> tuple[RunCheck, Problem]:
    """Rows under a run id that is not text (a blob, a number, bytes that are not UTF-8): no
    append writes one, so they were put into the file behind the store's back."""
    shown = _show(run)
    what = (f"rows are recorded under a run id that is not text ({shown}): they were added to the file "
            "behind the store's back")
    return RunCheck(shown, 0, None, False, 0, 0), _problem(shown, None, None, None, what)


class _Walk:
    """State of one run's recomputation, fed its rows in chain order."""

    def __init__(self, run: str, checkpoints: dict[int, list[_Checkpoint]], tally: SignatureTally) -> None:
        self.run = run
        self.tally = tally
        self.signed = self.unsigned = 0  # events of the run with and without a signature
        self.parsed: dict | None = None  # the event of the row being checked, once its text parsed
        self.checkpoints = checkpoints
        self.covered = max(checkpoints, default=0)  # events covered by the latest checkpoint
        self.count = 0  # events verified so far
        self.trusted = 0  # events covered by the last checkpoint that matched
        self.head = GENESIS
        self.frontier: list[bytes] = []  # Merkle frontier of the events verified so far
        self.rows = 0
        self.problem: Problem | None = None

    def feed(self, row: tuple) -> None:
        """Check the row against the chain (until the first problem); count and check its signature
        in any case: a signature proves its event on its own, even past a broken link."""
        self.rows += 1
        self.parsed = None
        if self.problem is None:
            self.problem = self._check(row)
        event = self.parsed if self.parsed is not None else _parse(row[5])
        if event is not None:
            signed = self.tally.see(self.run, row[0], row[1], row[2], event)
            self.signed += signed
            self.unsigned += 1 - signed

    def finish(self, *, required: bool) -> None:
        if self.problem is not None:
            return
        if self.covered > self.count:
            heads = ", ".join(_short(cp.head) for cp in self.checkpoints[self.covered])
            self.problem = self._missing(
                f"chain position {self.count} is missing: the checkpoint of {self.covered} events "
                f"(head {heads}) goes beyond the stored chain, which ends after {self.count} events"
            )
        elif required and self.rows == 0:
            self.problem = self._missing(f"no events or checkpoints are recorded for run {self.run}")

    def _check(self, row: tuple) -> Problem | None:
        pos, src, seq = row[0], row[1], row[2]
        if pos != self.count:
            return self._position(pos, src, seq)
        what = self._check_event(row)
        return None if what is None else _problem(self.run, src, seq, pos, what)

    def _position(self, pos: Any, src: Any, seq: Any) -> Problem:
        if isinstance(pos, int) and pos > self.count:
            return self._missing(
                f"chain position {self.count} is missing: the next stored event ({src} seq {seq}) "
                f"is at position {pos}"
            )
        what = f"chain position {_show(pos)} is out of order or stored twice"
        return _problem(self.run, src, seq, pos, what)

    def _missing(self, what: str) -> Problem:
        return _problem(self.run, None, None, self.count, what)

    def _check_event(self, row: tuple) -> str | None:
        """The first thing wrong with one stored event, or None; advances the chain if fine."""
        text, stored = row[5], row[6]
        if isinstance(text, NotUtf8):
            return "the stored event text is not valid UTF-8"
        if not isinstance(text, str):
            return f"the event column holds {type(text).__name__}, not text"
        data = text.encode("utf-8", "surrogatepass")
        digest = link(self.head, data)
        if digest.hex() != stored:
            return f"hash does not match: stored {_short(stored)}, recomputed {_short(digest.hex())}"
        what, self.parsed = _check_text(self.run, row, data)
        if what is not None:
            return what
        merkle.push(self.frontier, self.count, digest)
        self.count += 1
        self.head = digest
        return self._check_checkpoints(digest.hex())

    def _check_checkpoints(self, head: str) -> str | None:
        if self.count == self.covered + 1:
            latest = f"the latest records {self.covered} events" if self.covered else "the run has none"
            return f"the event is not covered by any checkpoint ({latest})"
        recorded = self.checkpoints.get(self.count, ())
        for checkpoint in recorded:
            what = self._check_checkpoint(checkpoint, head)
            if what is not None:
                return what
        if recorded:
            self.trusted = self.count
        return None

    def _check_checkpoint(self, checkpoint: _Checkpoint, head: str) -> str | None:
        """Does a checkpoint recorded at this count agree with the events before it?"""
        if checkpoint.fault is not None:
            return checkpoint.fault
        if checkpoint.head != head:
            return (
                f"the checkpoint of {self.count} events records head {_short(checkpoint.head)}, "
                f"but the chain recomputes to {_short(head)} here: an event at chain position "
                f"{self.trusted} to {self.count - 1} was altered, removed or inserted"
            )
        if checkpoint.merkle_root is not None:
            root = merkle.root_of_frontier(self.frontier).hex()
            if checkpoint.merkle_root != root:
                return (
                    f"the checkpoint of {self.count} events records Merkle root "
                    f"{_short(checkpoint.merkle_root)}, but the events recompute to {_short(root)}: "
                    f"the checkpoint was altered"
                )
        if checkpoint.frontier is not None and checkpoint.frontier != merkle.pack(self.frontier):
            return (
                f"the checkpoint of {self.count} events records a Merkle frontier that the events "
                f"do not produce: the checkpoint was altered"
            )
        return None


def _check_text(run: str, row: tuple, data: bytes) -> tuple[str | None, dict | None]:
    """Does the event text parse, agree with the index columns and sit in canonical form?
    Returns what is wrong (or None) and the parsed event (None if it is not a JSON object)."""
    try:
        ev = json.loads(data)
    except ValueError:
        return "the stored event text is not valid JSON", None
    if not isinstance(ev, dict):
        return "the stored event text is not a JSON object", None
    for column, value in zip(_COLUMNS, (run, *row[1:5])):
        said = ev.get(column)
        if type(value) is not type(said) or value != said:
            return f"column {column} is {_show(value)} but the event says {_show(said)}", ev
    try:
        canonical = canonical_json(ev)
    except (ValueError, TypeError, RecursionError):
        canonical = None
    if canonical != data:
        return "the stored event text is not in canonical form", ev
    return None, ev


def _parse(text: Any) -> dict | None:
    """A stored event's text as an object, or None (for rows past the first problem)."""
    try:
        ev = json.loads(text)
    except (ValueError, TypeError, RecursionError):
        return None
    return ev if isinstance(ev, dict) else None


def _verify_rulebooks(conn: sqlite3.Connection) -> Problem | None:
    """Rulebooks are addressed by the hash of their text: each must still hash to its address."""
    for address, name, version, text in conn.execute("SELECT sha256, name, version, text FROM rulebooks"):
        actual = hashlib.sha256(str(text).encode("utf-8", "surrogatepass")).hexdigest()
        if actual != address:
            what = (
                f"rulebook {name} {version} is stored under {_short(address)} "
                f"but its text hashes to {_short(actual)}"
            )
            return _problem(None, None, None, None, what)
    return None


def _verify_wire(conn: sqlite3.Connection, run: str | None) -> Problem | None:
    """The liveliness and wire-miss chains (store/liveliness.py), which the missing-evidence
    finding reads, and the ends of them and of the rulebooks' chain the checkpoints (of the run)
    record (store/wire_ends.py);
    a value no append writes (bytes, not UTF-8) is a problem too, not a crash."""
    try:
        found = wire_problem(conn)
    except (ValueError, TypeError) as exc:
        return _problem(None, None, None, None, f"a liveliness or wire-miss row holds a value no append writes: {exc}")
    if found is not None:
        return _typed(found)
    recorded = wire_ends.checkpoint_problem(conn, run)
    return None if recorded is None else _problem(run, None, None, None, recorded)


def _problem(run: str | None, src: Any, seq: Any, chain_pos: Any, what: str) -> Problem:
    """The report's account of a problem; a value no append writes (bytes, text that is not
    UTF-8) is shown as its repr, so that the report stays plain JSON."""
    src, seq, chain_pos = (_show(v) if isinstance(v, bytes) else v for v in (src, seq, chain_pos))
    return Problem(run, src, seq, chain_pos, what)


def _short(digest: Any) -> str:
    return f"{digest[:12]}…" if isinstance(digest, str) and len(digest) > 12 else _show(digest)


def _show(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, str):
        return json.dumps(value if len(value) <= 60 else value[:59] + "…", ensure_ascii=False)
    return repr(value)
