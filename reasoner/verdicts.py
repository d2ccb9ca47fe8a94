"""The verdict words and the rule ids the code names, in one place, in the rulebooks' words.

A verdict is one of three words. Two are the validator stage's questions: validators.le asks
`query punishable` ("which vehicle punishably violates which action") and `query mitigated`
("... mitigately violates ..."); the third, dismissed, is the reasoner's own: neither is
established, or the act is not proven. `Verdict` is a StrEnum, so a verdict is its word wherever
it is printed, compared or written as JSON: `gaps incidents --json` reads as it always has.

A rule id is the label a rulebook gives a rule in the comment above it ("% HC 176: <law>"): the
Highway Code rule it models. An incident's `rule` is whatever label its proof's rule carries, so a
rulebook of one's own may name any; the constants below are only those the code itself picks
something by (the margin's quantity, the featured incidents of a report).

tests/reasoner/test_verdicts.py reads reasoner/rules/*.le and fails when a rulebook renames or
drops a verdict's question or a rule id named here, so a rename in LE breaks the build, not a
verdict.
"""
from __future__ import annotations

from enum import StrEnum
from typing import Final, Mapping, NewType

from .vocabulary import MITIGATELY_VIOLATES, PUNISHABLY_VIOLATES, Sentence

# What other rooms take from here (tests/architecture/test_walls.py): the verdict words, how a
# dismissal for want of proof begins (explain/explanation_doc.py), the rules a report features
# (explain/featured.py) and a label's rule number (explain/phrases.py); the reasoner's own modules use the rest
__all__ = ["HC_171", "HC_176", "NOT_PROVEN", "Verdict", "rule_number"]


class Verdict(StrEnum):
    """What the validator stage (or, failing it, the reasoner) found of a potential violation."""

    PUNISHABLE = "punishable"
    MITIGATED = "mitigated"
    DISMISSED = "dismissed"


ASKED: Final = (Verdict.PUNISHABLE, Verdict.MITIGATED)  # the validator's questions, in the order asked
QUESTION: Final[Mapping[Verdict, Sentence]] = {Verdict.PUNISHABLE: PUNISHABLY_VIOLATES,   # what each is asked as
                                               Verdict.MITIGATED: MITIGATELY_VIOLATES}
NOT_PROVEN: Final = "not proven"          # how a dismissal's `why` begins where the act is not proven

RuleId = NewType("RuleId", str)           # a rulebook's label of a rule: "HC 176"
RULE_PREFIX: Final = "HC "                # the Highway Code's rules are labelled "HC <number>"

HC_171: Final = RuleId("HC 171")          # Stop sign and line
HC_172: Final = RuleId("HC 172")          # Give Way line
HC_174: Final = RuleId("HC 174")          # box junction
HC_175: Final = RuleId("HC 175")          # amber
HC_176: Final = RuleId("HC 176")          # red, and the emergency exception of para 5
NAMED_RULES: Final = (HC_171, HC_172, HC_174, HC_175, HC_176)


def rule_number(label: str) -> str | None:
    """"HC 176" -> "176": the Highway Code rule a label names; None for any other label."""
    return label[len(RULE_PREFIX):] if label.startswith(RULE_PREFIX) else None
