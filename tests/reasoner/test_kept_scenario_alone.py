"""A changed decision is asked on its kept Vehicle Scenario: that one scenario is parsed, not
every scenario kept in its chunk (on the hour a chunk holds 2,000, and parsing one whole for a
changed decision was half of asking it)."""
from __future__ import annotations

import json

from reasoner import case_memo
from reasoner.regress import decisions as regress_decisions
from store import Store
from tests.reasoner import regress_runs as R
from tests.reasoner.regress_runs import db, new_rules  # noqa: F401 (fixtures)


def test_reading_one_kept_decisions_scenario_parses_it_alone(db, new_rules, monkeypatch):
    R.regressed(db, new_rules)
    with Store.open_read_only(db) as store:
        kept = regress_decisions.kept_decisions(case_memo.CaseMemo(store, R.RUN))
        recorded = list(regress_decisions.recorded_decisions(store, R.RUN))
    assert kept is not None and len(kept) > 1
    parsed: list = []

    def parse(text: str):
        parsed.append(json.loads(text))
        return parsed[-1]
    monkeypatch.setattr(regress_decisions, "parse_json", parse)
    assert tuple(kept[1].decision.facts) == recorded[1].facts
    scenarios = [p for p in parsed if not all(isinstance(item, str) for item in p)]
    assert scenarios == [regress_decisions._kept_facts(recorded[1].facts)[1]]
