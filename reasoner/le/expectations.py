"""`FILE.le.tests`: the expected answers of a document's queries, and comparing with them.

Each line is a Prolog fact `expected(Query, Scenario, Answers).` (the reference
implementation's format): Query and Scenario are atoms, Answers a list of strings.  It is read
here as data by a small reader for exactly that shape, never consulted as Prolog.

Answers are compared as multisets (one sentence per proof; order is not stable).  Two
differences of printing are normalised on both sides before comparing, and each case records
whether it needed that: the reference prints date-times as `2021-10-9T0:0:0.0` where this
project prints ISO 8601 (`2021-10-09`), and it prints punctuation inside a constant with spaces
around it (`not - for - profit`) where this project keeps the constant as written
(`not-for-profit`).
"""
from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass, field

from store import GapsError

from .dates import reference_dates_to_iso


class ExpectationError(GapsError, ValueError):
    """An expectations file (the tests beside a rulebook) that cannot be read."""


@dataclass
class Expectation:
    query: str
    scenario: str
    answers: list[str]
    line: int


@dataclass
class Outcome:
    expectation: Expectation
    got: list[str] | None
    passed: bool
    exact: bool = False
    error: str | None = None

    def as_dict(self) -> dict:
        e = self.expectation
        return {"query": e.query, "scenario": e.scenario, "expected": e.answers, "got": self.got,
                "passed": self.passed, "exact": self.exact, "error": self.error, "line": e.line}


@dataclass
class Report:
    file: str
    outcomes: list[Outcome] = field(default_factory=list)
    error: str | None = None            # the document did not load

    @property
    def passed(self) -> int:
        return sum(o.passed for o in self.outcomes)

    @property
    def failed(self) -> int:
        return len(self.outcomes) - self.passed

    @property
    def normalised(self) -> int:
        return sum(o.passed and not o.exact for o in self.outcomes)

    def as_dict(self) -> dict:
        return {"file": self.file, "passed": self.passed, "failed": self.failed,
                "passed_only_after_normalising": self.normalised, "error": self.error,
                "cases": [o.as_dict() for o in self.outcomes]}


# -- reading ------------------------------------------------------------------------------

_TOKEN = re.compile(r"""\s*(?:
    (?P<quoted>'(?:[^'\\]|''|\\.)*')
  | (?P<string>"(?:[^"\\]|""|\\.)*")
  | (?P<number>-?\d+(?:\.\d+)?)
  | (?P<atom>[a-z][A-Za-z0-9_]*)
  | (?P<punct>[(),\[\].])
)""", re.VERBOSE)


def _unquote(text: str, q: str) -> str:
    body = text[1:-1].replace(q + q, q)
    return re.sub(r"\\(.)", lambda m: {"n": "\n", "t": "\t"}.get(m.group(1), m.group(1)), body)


def _tokens(text: str, line: int):
    pos, out = 0, []
    while pos < len(text):
        if text[pos:].strip() == "":
            break
        m = _TOKEN.match(text, pos)
        if not m or m.end() == pos:
            raise ExpectationError(f"line {line}: cannot read {text[pos:pos + 20]!r}")
        kind = m.lastgroup
        assert kind is not None         # every alternative of _TOKEN is a named group
        value = m.group(kind)
        if kind == "quoted":
            value = _unquote(value, "'")
        elif kind == "string":
            value = _unquote(value, '"')
        out.append((kind, value))
        pos = m.end()
    return out


def _term(toks, i, line):
    kind, value = toks[i]
    if kind == "punct" and value == "[":
        items, i = [], i + 1
        if toks[i] == ("punct", "]"):
            return ("list", items), i + 1
        while True:
            item, i = _term(toks, i, line)
            items.append(item)
            if toks[i] == ("punct", ","):
                i += 1
                continue
            if toks[i] == ("punct", "]"):
                return ("list", items), i + 1
            raise ExpectationError(f"line {line}: expected `,` or `]` in a list")
    if kind in ("quoted", "string", "atom", "number"):
        return (kind, value), i + 1
    raise ExpectationError(f"line {line}: unexpected {value!r}")


def read_expectations(text: str) -> list[Expectation]:
    out = []
    for number, raw in enumerate(text.splitlines(), 1):
        line = raw.split("%", 1)[0].strip() if not raw.lstrip().startswith("expected") else raw.strip()
        if not line:
            continue
        toks = _tokens(line, number)
        if len(toks) < 4 or toks[0] != ("atom", "expected") or toks[1] != ("punct", "("):
            raise ExpectationError(f"line {number}: expected `expected(Query, Scenario, Answers).`")
        try:
            query, i = _term(toks, 2, number)
            if toks[i] != ("punct", ","):
                raise ExpectationError(f"line {number}: expected `,` after the query")
            scenario, i = _term(toks, i + 1, number)
            if toks[i] != ("punct", ","):
                raise ExpectationError(f"line {number}: expected `,` after the scenario")
            answers, i = _term(toks, i + 1, number)
            if toks[i:] != [("punct", ")"), ("punct", ".")]:
                raise ExpectationError(f"line {number}: expected `).` at the end")
        except IndexError:
            raise ExpectationError(f"line {number}: the line ends too early") from None
        if answers[0] != "list" or not all(a[0] == "string" for a in answers[1]):
            raise ExpectationError(f"line {number}: the answers are a list of strings")
        if query[0] == "list" or scenario[0] == "list":
            raise ExpectationError(f"line {number}: the query and the scenario are names")
        out.append(Expectation(str(query[1]), str(scenario[1]), [a[1] for a in answers[1]], number))
    return out


# -- comparing ----------------------------------------------------------------------------

_PUNCT_SPACING = re.compile(r"\s*([-/])\s*")


def normalise(answer: str) -> str:
    text = reference_dates_to_iso(answer)
    text = _PUNCT_SPACING.sub(r"\1", text)
    return " ".join(text.split())


def compare(expected: list[str], got: list[str]) -> tuple[bool, bool]:
    """(passed, exact): equal as multisets, and whether that needed no normalising."""
    if Counter(expected) == Counter(got):
        return True, True
    return Counter(map(normalise, expected)) == Counter(map(normalise, got)), False
