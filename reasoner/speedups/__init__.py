"""What makes judging many cases fast, each beside the plain judge (reasoner/judge/) and each
giving its answer: the court that reads what the case memo kept (kept_court.py), the run's
cases kept (kept_cases.py), the incidents of the judgement in force kept whole and by their
summaries (kept_verdicts.py, summaries.py), and what two investigations read of a run alike
(shared.py). The tests compare each with the plain judge to the byte.

An investigation judges through one of `Speedups`' members, each the set of these modules one
caller uses: a set nobody uses cannot be asked for.
"""
from __future__ import annotations

from enum import Enum

__all__ = ["Speedups"]


class Speedups(Enum):
    """The speed-ups an investigation judges through, named for who uses them."""

    NONE = "none"
    """The plain judge alone (reasoner/judge/): every case found, measured and judged with its
    proofs, nothing read from or written to the case memo (the path the others must agree with)."""

    MEASUREMENTS = "measurements"
    """kept_court.py, kept_cases.py: the cases, measurements and states kept in the case memo for
    the next investigation of the chain, and read from it (the default: explanations, scenes)."""

    INCIDENTS = "incidents"
    """MEASUREMENTS and kept_verdicts.py: the incidents of the judgement in force kept whole and read
    back (`gaps incidents`, reasoner.api.Case)."""

    BASELINE = "baseline"
    """INCIDENTS with summaries.py: the kept incidents read by their summaries, whole when asked
    for (a regression's baseline)."""

    NEW_SIDE = "new side"
    """MEASUREMENTS with summaries.py: each case judged only as far as its summary goes, its
    stage answers remembered so that its proofs or the whole incident, worked out when asked
    for, ask nothing twice (a regression's new side)."""

    @property
    def keeps(self) -> bool:
        """Whether the case memo is read and written (kept_court.py, kept_cases.py)."""
        return self is not Speedups.NONE

    @property
    def keeps_incidents(self) -> bool:
        """Whether the judgement in force's incidents are kept whole (kept_verdicts.py)."""
        return self in (Speedups.INCIDENTS, Speedups.BASELINE)

    @property
    def reads_summaries(self) -> bool:
        """Whether kept incidents are handed back by their summaries (summaries.py)."""
        return self is Speedups.BASELINE

    @property
    def summarises(self) -> bool:
        """Whether each case is judged as far as its summary only (summaries.summarised)."""
        return self is Speedups.NEW_SIDE
