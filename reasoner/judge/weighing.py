"""What a case's measurement weighs against what was stated (DESIGN "Weighing", "Margins").

The claims the measurements contradict beyond their tolerance, why a margin proves nothing, and
the moment of the act itself: a verdict that turns on a contradicted claim, or whose margin
does not exceed its uncertainty, is not proven.
"""
from __future__ import annotations

from dataclasses import replace
from typing import Any

from .. import acts
from ..measurement import Measurement, rule_key
from ..verdicts import Verdict
from .case import NO_WEIGHING, Validation, Weighing


def weighing_of(measured: Measurement, action: str) -> Weighing:
    """The claims the measurement contradicts (sentence, what it shows, what it derives), by rule
    why a margin proves nothing (reasoner/margins.py `unproven`), and the act's moment: for a
    junction act, when the vehicle crossed its line (else entered the junction) by the moment it
    was judged at, the act itself; a speeding or box act is judged when recorded."""
    if not measured.present:
        return NO_WEIGHING
    return measured.contested, measured.unproven(), act_moment(measured, action)


def act_moment(measured: Measurement, action: str) -> int | None:
    at = measured.at
    if at is None or action in (acts.SPEEDING, acts.BOX):
        return at
    for what in ("crossed the stop line", "entered the junction"):
        found = [t for said, t in measured.moments if said == what and t <= at]
        if found:
            return found[-1]
    return at


def proved(validation: Validation, rule: Any, unproven: tuple[tuple[str | None, str], ...],
           summary: bool) -> Validation:
    """A conviction needs the act's margin beyond its uncertainty (DESIGN "Margins"): a
    punishable verdict whose rule's margin does not exceed it is not proven, and dismissed so."""
    if validation.verdict != Verdict.PUNISHABLE or not unproven:
        return validation
    key = rule_key(rule.label if rule is not None else None)
    why = next((w for r, w in unproven if r == key), None)
    if why is None:
        return validation
    return replace(validation, verdict=Verdict.DISMISSED, why="" if summary else f"not proven: {why}")
