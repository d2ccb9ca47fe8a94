"""What recomputing the chains found (store/verify.py), as typed values: per run, the first
problem, the signatures counted and checked, and SQLite's integrity check of the file.

Each value's `to_json()` is the shape `gaps verify --json` has always printed and the cache keeps
(store/verify_cache.py), key for key; `from_json` reads a kept one back (a value of another shape
is a TypeError, KeyError or ValueError: the cache's reader then recomputes).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any


@dataclass(frozen=True)
class Problem:
    """The first thing that does not match: in a run at a source's seq and a chain position, or
    (run, src, seq, chain_pos None) of the file or a rulebook; src and seq are None when the event
    itself is missing. A value no append writes is shown as its repr (store/verify.py: _show)."""

    run: Any
    src: Any
    seq: Any
    chain_pos: Any
    what: str

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "src": self.src, "seq": self.seq, "chain_pos": self.chain_pos, "what": self.what}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> Problem:
        return cls(data["run"], data["src"], data["seq"], data["chain_pos"], data["what"])


@dataclass(frozen=True)
class RunCheck:
    """One run's chain recomputed: its events, the recomputed head (None when the run failed),
    and how many of its events carry a signature."""

    run: str
    events: int
    head: str | None
    ok: bool
    signed: int
    unsigned: int

    def to_json(self) -> dict[str, Any]:
        return {"run": self.run, "events": self.events, "head": self.head, "ok": self.ok,
                "signed": self.signed, "unsigned": self.unsigned}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> RunCheck:
        return cls(data["run"], data["events"], data["head"], data["ok"], data["signed"], data["unsigned"])


@dataclass(frozen=True)
class SignatureCount:
    """The events signed and unsigned; with keys (`checked`; `keys` the file they came from) how
    many signatures are valid and invalid, and the first invalid one (store/signature_tally.py)."""

    signed: int
    unsigned: int
    checked: bool = False
    keys: str | None = None
    valid: int | None = None
    invalid: int | None = None
    first_invalid: Problem | None = None

    def to_json(self) -> dict[str, Any]:
        return {"signed": self.signed, "unsigned": self.unsigned, "checked": self.checked, "keys": self.keys,
                "valid": self.valid, "invalid": self.invalid,
                "first_invalid": None if self.first_invalid is None else self.first_invalid.to_json()}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> SignatureCount:
        first = data["first_invalid"]
        return cls(data["signed"], data["unsigned"], data["checked"], data["keys"], data["valid"], data["invalid"],
                   None if first is None else Problem.from_json(first))


@dataclass(frozen=True)
class IntegrityResult:
    """SQLite's integrity check of the file (store/integrity.py): ok, or its messages."""

    ok: bool
    messages: tuple[str, ...] = ()

    def to_json(self) -> dict[str, Any]:
        return {"ok": self.ok, "messages": list(self.messages)}

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> IntegrityResult:
        return cls(bool(data["ok"]), tuple(data["messages"]))


@dataclass(frozen=True)
class VerifyReport:
    """Outcome of recomputing the chains: ok is the verdict of the chains and the file's
    integrity (a failing integrity check makes it False and, when no event failed first, is the
    problem); `runs` one RunCheck per run checked; `problem` the first that did not match;
    `signatures` None where not counted (a result kept in the cache before they were)."""

    ok: bool
    runs: tuple[RunCheck, ...] = ()
    problem: Problem | None = None
    signatures: SignatureCount | None = None
    integrity: IntegrityResult | None = None

    def to_json(self) -> dict[str, Any]:
        return {"ok": self.ok, "runs": [r.to_json() for r in self.runs],
                "problem": None if self.problem is None else self.problem.to_json(),
                "signatures": None if self.signatures is None else self.signatures.to_json(),
                "integrity": None if self.integrity is None else self.integrity.to_json()}

    def as_dict(self) -> dict[str, Any]:
        """The same as to_json (the name callers used when the report was a dict)."""
        return self.to_json()

    @classmethod
    def from_json(cls, data: dict[str, Any]) -> VerifyReport:
        problem, signatures, integrity = data["problem"], data.get("signatures"), data.get("integrity")
        return cls(bool(data["ok"]), tuple(RunCheck.from_json(r) for r in data["runs"]),
                   None if problem is None else Problem.from_json(problem),
                   None if signatures is None else SignatureCount.from_json(signatures),
                   None if integrity is None else IntegrityResult.from_json(integrity))
