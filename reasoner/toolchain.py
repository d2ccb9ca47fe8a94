"""The LE tool chain on one document, as `gaps rules check|query|prolog|verify` asks it: each call
returns what the command prints, as values, so that the command only reads its arguments and
renders (issue 38: one way in). The engine (reasoner/engine.py) compiles and answers; this module
decides which question a `--query` is, gathers a scenario's facts and counts the expectations.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Iterable

from store import GapsError

from .engine import QueryResult, Rulebook, enrich, get_engine
from .le.document import parse_facts, parse_question
from .le.errors import LEError
from .le.expectations import ExpectationError, Report
from .rules_verify import verify_file


class ToolchainError(GapsError, ValueError):
    """A document or expectations file the tool chain cannot start on (none there, unreadable)."""


@dataclass(frozen=True)
class RulebookCheck:
    """A document compiled and loaded: its error (None: it loads), warnings, what it holds, and
    its sha256 (the address a rulebook is stored and cited under)."""

    name: str
    error: LEError | None
    warnings: tuple[Any, ...] = ()
    counts: dict[str, int] = field(default_factory=dict)     # templates, rules, scenarios, queries
    sha256: str | None = None

    @property
    def ok(self) -> bool:
        return self.error is None

    def to_json(self, file: str) -> dict[str, Any]:
        if self.error is not None:
            return {"file": file, "ok": False, "errors": [self.error.as_dict()], "warnings": []}
        return {"file": file, "ok": True, "errors": [], "counts": self.counts,
                "warnings": [w.as_dict() for w in self.warnings], "sha256": self.sha256}


def check_rulebook(text: str, name: str) -> RulebookCheck:
    """The document `text` (named `name` in its messages) compiled and loaded."""
    try:
        rb = get_engine().load(text, name)
    except LEError as exc:
        return RulebookCheck(name, exc)
    doc = rb.document
    counts = {"templates": len(doc.templates), "rules": len(doc.rules),
              "scenarios": len(doc.scenarios), "queries": len(doc.queries)}
    return RulebookCheck(name, None, tuple(doc.warnings), counts, rb.sha256)


@dataclass(frozen=True)
class Answered:
    """A question's answers on a scenario, one LE sentence per proof, with the proofs (and why
    there is none) when they were asked for; `rulebook` words the proof trees."""

    result: QueryResult
    rulebook: Rulebook
    explained: bool

    def to_json(self) -> dict[str, Any]:
        out: dict[str, Any] = {"answers": self.result.answers}
        if self.explained:
            out["proofs"] = [[enrich(t, self.rulebook) for t in trees] for trees in self.result.proofs]
            if self.result.why_not is not None:
                out["why_not"] = [enrich(t, self.rulebook) for t in self.result.why_not]
        return out


def ask_rulebook(text: str, name: str, question: str, *, scenario: str | None = None, facts: Iterable[str] = (),
                 explain: bool = False) -> Answered:
    """`question` (a query of the document by name, else a question in LE) asked on `scenario`
    (by name) and the extra `facts` (LE sentences). LEError for what does not parse,
    QuestionError for what the engine could not answer."""
    engine = get_engine()
    rb = engine.load(text, name)
    doc = rb.document
    if question in doc.queries or question in doc.unreadable_queries:
        body = rb.query(question).body
    else:
        body = parse_question(doc, question)
    given = list(rb.scenario(scenario)) if scenario is not None else []
    for f in facts:
        given += parse_facts(doc, f)
    return Answered(engine.answers(rb, body, given, explain=explain), rb, explain)


def prolog_text(text: str, name: str) -> str:
    """The Prolog clauses the document compiles to, each after its LE source line."""
    engine = get_engine()
    return engine.prolog_text(engine.load(text, name))


@dataclass(frozen=True)
class RulebookTests:
    """The expectations of one document, or of every document of a folder, run."""

    reports: tuple[Report, ...]

    @property
    def passed(self) -> int:
        return sum(r.passed for r in self.reports)

    @property
    def failed(self) -> int:
        return sum(r.failed for r in self.reports)

    @property
    def normalised(self) -> int:
        return sum(r.normalised for r in self.reports)

    @property
    def ok(self) -> bool:
        """Every expectation met, and no document with expectations that did not load."""
        return self.failed == 0 and not any(r.error for r in self.reports if r.outcomes)

    def to_json(self) -> dict[str, Any]:
        return {"passed": self.passed, "failed": self.failed, "passed_only_after_normalising": self.normalised,
                "documents": [r.as_dict() for r in self.reports]}


def verify_rulebooks(path: Path, tests: Path | None = None) -> RulebookTests:
    """The expectations of `path` (its FILE.le.tests, or `tests`) run; a folder: those of every
    .le document in it, each beside its own."""
    files = sorted(path.glob("*.le")) if path.is_dir() else [path]
    if not files or not all(f.is_file() for f in files):
        raise ToolchainError(f"no LE document at {path}")
    try:
        return RulebookTests(tuple(verify_file(f, tests=tests if not path.is_dir() else None) for f in files))
    except ExpectationError as exc:
        raise ToolchainError(f"cannot read the expectations: {exc}") from None
