"""One case to judge and what its stages found of it: plain frozen values the pipeline hands on.

A case is a potential violation at its time t: a recorded monitor.potential_violation, or the
observations (an episode, reasoner/episodes.py) it was re-derived from, or both; with the state
of the run at t (store.state_of) that the scenarios are read from.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property
from typing import Any

from store import EventRef, State

from ..engine import Answer
from ..episodes import Episode
from ..le.sentences import constant
from ..model import Control, Finding, Liability, Penalty, RulebookChoice, StageProof
from ..stages import RuleSet

SECOND = 1_000_000_000

# What the measurements weigh of a case (measuring.weighing_of): the claims they contradict
# (sentence, what they show, what they derive), why a margin proves nothing (by rule), and the
# act's moment.
Contested = tuple[tuple[str, str, tuple[str, ...]], ...]
Weighing = tuple[Contested, tuple[tuple[str | None, str], ...], int | None]
NO_WEIGHING: Weighing = ((), (), None)


@dataclass(frozen=True)
class Case:
    """One potential violation to judge, and the state of the run at its time."""

    run: str
    rs: RuleSet
    state: State
    t: int
    monitor: str
    pv: dict | None               # the recorded monitor.potential_violation, if any
    episode: Episode | None       # the observations it was re-derived from, if any
    vehicle: str
    action: str

    @property
    def anchor(self) -> dict:
        """The event the case is named by: its recorded potential violation, else its first observation."""
        return anchor_of(self.pv, self.episode)

    @cached_property
    def me(self) -> Any:
        """The vehicle as a constant; read once (a case's facts ask it of every argument)."""
        return constant([self.vehicle])

    @cached_property
    def act(self) -> Any:
        return constant(self.action.split())


@dataclass(frozen=True)
class Validation:
    """What the validator stage found: the verdict, why, and what it rests on."""

    verdict: str
    why: str
    rulebook: RulebookChoice | None = None
    scenario: tuple[tuple[Any, EventRef], ...] = ()
    proof: StageProof | None = None
    rule: Any = None                          # the rule of the verdict's proof, where it holds
    dispute: Finding | None = None
    set_aside: tuple[tuple[Any, EventRef], ...] = ()   # contested claims the verdict was taken without


@dataclass(frozen=True)
class Judged:
    """What the stages answered of a case: all a regression compares of it, before its findings."""

    pv_answer: Answer | None
    rederived: bool
    judged_on: str
    validation: Validation
    control: Control
    rule: Any
    penalty: Penalty | None
    liability: Liability | None


def anchor_of(pv: dict | None, episode: Episode | None) -> dict:
    """The recorded potential violation, else the episode's first observation (a case has one)."""
    if pv:
        return pv
    assert episode is not None, "a case is a recorded potential violation or an episode"
    return episode.first


def anchor_key(pv: dict | None, episode: Episode | None) -> str:
    """The case's anchor as a sortable name (its src and zero-padded seq)."""
    anchor = anchor_of(pv, episode)
    return f"{anchor['src']}:{anchor['seq']:020d}"


def incident_id(case: Case) -> str:
    return f"{case.anchor['src']}:{case.anchor['seq']}"


def incident_name(incident: Any) -> tuple:
    """What tells an incident from the run's others (two acts of one observation share its id)."""
    return (incident.run, incident.id, incident.vehicle, incident.action, incident.t)


__all__ = ["Case", "Validation", "Judged", "Weighing", "Contested", "NO_WEIGHING", "SECOND", "anchor_of",
           "anchor_key", "incident_id", "incident_name"]
