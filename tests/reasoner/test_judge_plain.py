"""The plain judge and the sped-up one give the same incidents, to the byte (issue 38).

The plain path is the pipeline alone (reasoner/judge/): the run's cases found afresh, each
judged with the plain court (everything worked out, nothing kept or shared), the cases of one
act merged. The sped-up paths are the investigation with every speed-up of reasoner/speedups/:
measurements, states and cases kept (kept_court.py, kept_cases.py), the judgement in force kept
and read back whole or by its summaries (kept_verdicts.py, summaries.py), and a regression's
two sides reading the run once (shared.py)."""
from __future__ import annotations

import pytest

from reasoner import oneact
from reasoner.investigation import IncidentSummary, Investigation, SharedReading, Speedups, whole
from reasoner.judge import Court, case_of, find, judge
from reasoner.model import Incident
from reasoner.speedups.summaries import SUMMARY
from sim_replay.paper import paper_run
from store import Store

from tests.reasoner import regress_runs as R


def plain(store: Store, run: str) -> list[Incident]:
    """Every incident of the run by the pipeline alone."""
    lookup = Investigation(store, speedups=Speedups.NONE)    # for the run's rulesets alone
    rs = lookup.ruleset(run)
    court = Court(store, lookup.engine, lookup.reader, lookup.problems)
    recorded = list(store.events(run, kinds=["monitor.potential_violation"]))
    found = [judge(court, case_of(court, run, rs, todo), court.gaps(run))
             for todo in find(store, lookup.engine, lookup.reader, court.context(run), run, rs, recorded)]
    judged = [i for i in found if i is not None]
    merged = [group[0] if len(group) == 1 else oneact.merge(group) for group in oneact.groups(judged)]
    return sorted(merged, key=lambda i: i.t)


def summarised(found: list) -> list[list]:
    """What a regression compares of each incident: its summary's fields."""
    return [[getattr(i, name) for name in SUMMARY] for i in found]


@pytest.fixture(params=["regress scenario", "paper"])
def stored(request, tmp_path):
    if request.param == "paper":
        db, events = tmp_path / "p.db", paper_run()
        with Store(db) as store:
            assert not store.append(events).rejected
        return db, events[0]["run"]
    return R.build_store(tmp_path / "gaps.db"), R.RUN


def test_every_speed_up_gives_the_plain_judge_s_incidents(stored):
    db, run = stored
    with Store(db) as store:
        judged = plain(store, run)
        expected = [i.to_json() for i in judged]
        assert expected
        cold = Investigation(store, speedups=Speedups.INCIDENTS).incidents(run)      # measures, keeps
        warm = Investigation(store, speedups=Speedups.INCIDENTS).incidents(run)      # reads the kept incidents
        measured = Investigation(store, speedups=Speedups.MEASUREMENTS).incidents(run)  # from kept measurements
        shared = SharedReading()
        Investigation(store, speedups=Speedups.BASELINE).judgements(run)     # keeps the summaries
        by_summary = Investigation(store, speedups=Speedups.BASELINE, shared=shared).judgements(run)
        lean = Investigation(store, speedups=Speedups.NEW_SIDE, shared=shared)
        lean_found = lean.judgements(run)
        assert [i.to_json() for i in cold] == expected
        assert [i.to_json() for i in warm] == expected
        assert [i.to_json() for i in measured] == expected
        assert all(isinstance(i, IncidentSummary) for i in by_summary)
        assert [whole(i).to_json() for i in by_summary] == expected
        assert summarised(by_summary) == summarised(judged)
        assert all(isinstance(i, IncidentSummary) for i in lean_found)
        assert summarised(lean_found) == summarised(judged)
        assert [whole(i).to_json() for i in lean_found] == expected
        assert [i.proofs for i in lean_found] == [whole(i).proofs for i in lean_found]


def test_no_speed_up_keeps_what_it_judged_by_summary_alone():
    """A member that keeps the judgement in force's incidents judges them whole (the case memo's
    codec keeps no IncidentSummary: a summary kept would be dropped without a word), and only the
    plain judge keeps nothing."""
    for member in Speedups:
        assert not (member.keeps_incidents and member.summarises), member
        assert not member.reads_summaries or member.keeps_incidents, member
        assert member.keeps == (member is not Speedups.NONE), member
