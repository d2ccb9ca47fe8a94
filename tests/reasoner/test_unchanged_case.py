"""A decision answered alike on both sides makes its case without CaseResult's __init__ (tens of
thousands a regression): the very case the dataclass makes, every field set, in its order."""
from __future__ import annotations

from dataclasses import fields

from reasoner.regress.regression import CaseResult, _unchanged_case
from reasoner.regress.decisions import RecordedDecision


def test_an_unchanged_decisions_case_is_the_dataclasses_own() -> None:
    d = RecordedDecision("run", "vehicle/5", 7, 1_000, "5", "enter the junction", "go", True, True, None, (), "vehicle/5:7")
    made = _unchanged_case(d, "permitted")
    plain = CaseResult("run", "decision", "vehicle/5:7", "5", "enter the junction", 1_000, "permitted", "permitted")
    assert made == plain and list(vars(made)) == [f.name for f in fields(CaseResult)]
    assert vars(made) == vars(plain) and made.to_json() == plain.to_json()
