"""The plain judge: one case in, its incident out (pipeline.py says the steps).

    court = Court(store, engine, reader, problems)
    incident = judge(court, case_of(court, run, rs, todo), court.gaps(run))

Every speed-up (reasoner/speedups/) wraps this from outside and gives the same answer.
"""
from __future__ import annotations

from .case import Case
from .cases import Todo, case_of, find
from .court import Court
from .pipeline import judge

__all__ = ["Case", "Court", "Todo", "case_of", "find", "judge"]
