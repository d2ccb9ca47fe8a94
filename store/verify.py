"""Recomputing every hash chain from the stored event text, to prove the log was not altered.

Nothing stored is trusted: hashes, index columns, chain positions and checkpoints are all
checked against the event text, and the report names the first event that does not match, so
an investigator knows where the record stops being reliable.
"""

from __future__ import annotations

import hashlib
import json
import sqlite3
from typing import Any

from .canonical import canonical_json
from .chain import GENESIS, link
from .reports import VerifyReport

_COLUMNS = ("run", "src", "seq", "t", "kind")


def verify_store(conn: sqlite3.Connection, run: str | None = None) -> VerifyReport:
    """Check one run, or every run and every rulebook."""
    names = [run] if run is not None else _all_runs(conn)
    summaries, problems = [], []
    for name in names:
        summary, problem = _verify_run(conn, name, required=run is not None)
        summaries.append(summary)
        problems.append(problem)
    if run is None:
        problems.append(_verify_rulebooks(conn))
    first = next((problem for problem in problems if problem is not None), None)
    return VerifyReport(ok=first is None, runs=summaries, problem=first)


def _all_runs(conn: sqlite3.Connection) -> list[str]:
    """Runs with events or checkpoints: a run whose events were all deleted still has the latter."""
    rows = conn.execute("SELECT run FROM events UNION SELECT run FROM checkpoints ORDER BY run")
    return [name for (name,) in rows]


def _checkpoints(conn: sqlite3.Connection, run: str) -> dict[int, list[str]]:
    """count -> heads recorded for that count."""
    recorded: dict[int, list[str]] = {}
    for count, head in conn.execute("SELECT count, head FROM checkpoints WHERE run = ? ORDER BY id", (run,)):
        recorded.setdefault(count, []).append(head)
    return recorded


def _verify_run(conn: sqlite3.Connection, run: str, *, required: bool) -> tuple[dict, dict | None]:
    walk = _Walk(run, _checkpoints(conn, run))
    rows = conn.execute(
        "SELECT chain_pos, src, seq, t, kind, event, hash FROM events WHERE run = ? ORDER BY chain_pos",
        (run,),
    )
    for row in rows:
        walk.feed(row)
    walk.finish(required=required)
    ok = walk.problem is None
    summary = {"run": run, "events": walk.rows, "head": walk.head.hex() if ok else None, "ok": ok}
    return summary, walk.problem


class _Walk:
    """State of one run's recomputation, fed its rows in chain order."""

    def __init__(self, run: str, checkpoints: dict[int, list[str]]) -> None:
        self.run = run
        self.checkpoints = checkpoints
        self.covered = max(checkpoints, default=0)  # events covered by the latest checkpoint
        self.count = 0  # events verified so far
        self.trusted = 0  # events covered by the last checkpoint that matched
        self.head = GENESIS
        self.rows = 0
        self.problem: dict[str, Any] | None = None

    def feed(self, row: tuple) -> None:
        self.rows += 1
        if self.problem is None:
            self.problem = self._check(row)

    def finish(self, *, required: bool) -> None:
        if self.problem is not None:
            return
        if self.covered > self.count:
            heads = ", ".join(_short(head) for head in self.checkpoints[self.covered])
            self.problem = self._missing(
                f"chain position {self.count} is missing: the checkpoint of {self.covered} events "
                f"(head {heads}) goes beyond the stored chain, which ends after {self.count} events"
            )
        elif required and self.rows == 0:
            self.problem = self._missing(f"no events or checkpoints are recorded for run {self.run}")

    def _check(self, row: tuple) -> dict[str, Any] | None:
        pos, src, seq = row[0], row[1], row[2]
        if pos != self.count:
            return self._position(pos, src, seq)
        what = self._check_event(row)
        return None if what is None else _problem(self.run, src, seq, pos, what)

    def _position(self, pos: Any, src: Any, seq: Any) -> dict[str, Any]:
        if isinstance(pos, int) and pos > self.count:
            return self._missing(
                f"chain position {self.count} is missing: the next stored event ({src} seq {seq}) "
                f"is at position {pos}"
            )
        what = f"chain position {_show(pos)} is out of order or stored twice"
        return _problem(self.run, src, seq, pos, what)

    def _missing(self, what: str) -> dict[str, Any]:
        return _problem(self.run, None, None, self.count, what)

    def _check_event(self, row: tuple) -> str | None:
        """The first thing wrong with one stored event, or None; advances the chain if fine."""
        text, stored = row[5], row[6]
        if not isinstance(text, str):
            return f"the event column holds {type(text).__name__}, not text"
        data = text.encode("utf-8", "surrogatepass")
        digest = link(self.head, data)
        if digest.hex() != stored:
            return f"hash does not match: stored {_short(stored)}, recomputed {_short(digest.hex())}"
        what = _check_text(self.run, row, data)
        if what is not None:
            return what
        self.count += 1
        self.head = digest
        return self._check_checkpoints(digest.hex())

    def _check_checkpoints(self, head: str) -> str | None:
        if self.count == self.covered + 1:
            latest = f"the latest records {self.covered} events" if self.covered else "the run has none"
            return f"the event is not covered by any checkpoint ({latest})"
        recorded = self.checkpoints.get(self.count, ())
        for expected in recorded:
            if expected != head:
                return (
                    f"the checkpoint of {self.count} events records head {_short(expected)}, "
                    f"but the chain recomputes to {_short(head)} here: an event at chain position "
                    f"{self.trusted} to {self.count - 1} was altered, removed or inserted"
                )
        if recorded:
            self.trusted = self.count
        return None


def _check_text(run: str, row: tuple, data: bytes) -> str | None:
    """Does the event text parse, agree with the index columns and sit in canonical form?"""
    try:
        ev = json.loads(data)
    except ValueError:
        return "the stored event text is not valid JSON"
    if not isinstance(ev, dict):
        return "the stored event text is not a JSON object"
    for column, value in zip(_COLUMNS, (run, *row[1:5])):
        said = ev.get(column)
        if type(value) is not type(said) or value != said:
            return f"column {column} is {_show(value)} but the event says {_show(said)}"
    try:
        canonical = canonical_json(ev)
    except (ValueError, TypeError, RecursionError):
        canonical = None
    if canonical != data:
        return "the stored event text is not in canonical form"
    return None


def _verify_rulebooks(conn: sqlite3.Connection) -> dict[str, Any] | None:
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


def _problem(run: str | None, src: Any, seq: Any, chain_pos: Any, what: str) -> dict[str, Any]:
    return {"run": run, "src": src, "seq": seq, "chain_pos": chain_pos, "what": what}


def _short(digest: Any) -> str:
    return f"{digest[:12]}…" if isinstance(digest, str) and len(digest) > 12 else _show(digest)


def _show(value: Any) -> str:
    if value is None:
        return "null"
    if isinstance(value, str):
        return json.dumps(value if len(value) <= 60 else value[:59] + "…", ensure_ascii=False)
    return repr(value)
