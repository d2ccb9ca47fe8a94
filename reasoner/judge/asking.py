"""A stage's question to the court, named by what it is asked on.

A stage question is named by its rulebook's sha256 and everything it is asked on, so that a
court that kept the answer (reasoner/speedups/kept_court.py) can give it back without asking.
"""
from __future__ import annotations

from typing import Any, Callable, Iterable

from store import EventRef

from ..model import Finding
from .case import Case
from .court import Court


def asked_noting(court: Court, case: Case, kind: str, question: list,
                 compute: Callable[[list[Finding]], Any], unknown: list[Finding]) -> Any:
    """The court's answer of a stage that notes findings as it answers: they are kept with the
    answer, and added to `unknown` whether the answer was computed or read."""
    def asked() -> list:
        mine: list[Finding] = []
        return [compute(mine), mine]
    answer, found = court.ask(case, kind, question, asked)
    unknown += found
    return answer


def as_asked(facts: Iterable[tuple[Any, EventRef | None]]) -> list[tuple]:
    """Facts as a stage question names them (case_memo.key_of): each with its event reference's
    fields, or None, in one tuple (a reference's own repr, a Python call each, was half of a
    question's key)."""
    return [(text, None) if ref is None else (text, ref.run, ref.src, ref.seq, ref.t, ref.kind) for text, ref in facts]
