"""The incidents of the judgement in force, kept beside the store.

A run judged by the rulebooks in force (its own, else the current ones: what `gaps incidents`
shows) keeps each incident in the case memo, under the rulebooks of its stages, the problems
reading the run's own, the chain and the code; the next such investigation reads it instead of
judging it. With summaries, each incident's summary is kept beside it and read first
(summaries.py): a regression's baseline decodes whole only the incidents whose change it shows.
A judgement with a rulebook given for any stage is worked out each time.
"""
from __future__ import annotations

from functools import partial
from typing import Callable

from ..case_memo import CaseMemo, key_of
from ..judge.case import anchor_key
from ..judge.cases import Todo
from ..stages import RuleSet
from . import summaries
from .summaries import Judgement


def in_force(rs: RuleSet) -> bool:
    """Whether the rulebooks are the run's own or the current ones (none given for any stage)."""
    return all(choice.source != "given" for choice in rs.stages.values())


def judged_by(rs: RuleSet, problems: list[str] | None) -> str:
    """What names a run's judgement in force in each of its incidents' keys: the rulebooks of its
    stages and the problems reading the run's own (digested once per run, not with every case:
    they were most of an incident's key)."""
    return key_of(rs.describe(), problems)


def incident(memo: CaseMemo, judgement: str, todo: Todo, judge: Callable[[], Judgement | None], *,
             by_summary: bool) -> Judgement | None:
    """The case's kept incident (`by_summary`: its kept summary, whole when asked for), else
    `judge()`'s, kept (with its summary). `judge` judges the case whole (a Speedups member that
    keeps incidents never judges by summary; a summary would not be kept: case_memo's codec
    keeps no IncidentSummary)."""
    key = _key(judgement, todo)
    whole = partial(memo.remember, "incident", key, judge)
    if not by_summary:
        return whole()
    summary = memo.get("incident summary", key)
    if summary is not None:
        return summaries.kept(summary, whole)
    found = whole()
    if found is not None:
        memo.put("incident summary", key, summaries.summary_of(found))
    return found


def _key(judgement: str, todo: Todo) -> str:
    t, src, pv, ep = todo
    if pv:
        acted = [pv["body"].get("vehicle"), pv["body"].get("action")]
    else:
        assert ep is not None, "a case is a recorded potential violation or an episode"
        acted = [ep.vehicle, ep.action]
    return key_of("incident", judgement, t, src, anchor_key(pv, ep), acted)
