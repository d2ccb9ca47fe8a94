"""The baseline's kept incidents read by their summaries (reasoner/speedups/summaries.py
`IncidentSummary`): a regression decodes whole only the incidents whose change shows their proofs,
gives what the plain path gives, and a forged summary is not believed."""
from __future__ import annotations

import sqlite3

import pytest

from reasoner.case_memo import CaseMemo
from store import Store
from store.cache import cache_tampering

from tests.reasoner import regress_runs as R


@pytest.fixture
def db(tmp_path):
    return R.build_store(tmp_path / "gaps.db")


@pytest.fixture
def new_rules(tmp_path):
    return R.edited(tmp_path, "validators.le", cut=(R.AMBER_TOO_CLOSE,))


def _read(monkeypatch) -> list[str]:
    """The kinds of the kept values read (decoded), one per read."""
    kinds: list[str] = []
    value = CaseMemo._value
    monkeypatch.setattr(CaseMemo, "_value", lambda memo, kind, *a: kinds.append(kind) or value(memo, kind, *a))
    return kinds


def test_only_the_changed_incidents_are_decoded_whole(db, new_rules, monkeypatch):
    first = R.regressed(db, new_rules)
    incidents = first["runs"][0]["incidents"]
    changed = [i for i in incidents if i["changes"] and i["before"] is not None]
    assert changed and len(changed) < len(incidents)
    kinds = _read(monkeypatch)
    assert R.regressed(db, new_rules) == first == R.plain(db, new_rules)
    assert kinds.count("incident summary") == len([i for i in incidents if i["before"] is not None])
    assert kinds.count("incident") == len(changed)


def test_a_forged_summary_is_not_believed(db, new_rules, monkeypatch):
    """The kept summaries' verdicts turned: their seals do not open, the cache check names them,
    and the incidents are read whole, to the same result."""
    first = R.regressed(db, new_rules)
    with sqlite3.connect(f"{db}.cache") as cache:
        assert cache.execute("UPDATE derived SET payload = replace(replace(replace(payload, '\"punishable\"', '\"x\"'), "
                             "'\"mitigated\"', '\"punishable\"'), '\"x\"', '\"mitigated\"') "
                             "WHERE kind = 'incident summary'").rowcount
    with Store.open_read_only(db) as store:
        assert any(key.startswith("incident summary ") for key in cache_tampering(store, [R.RUN]).derived[R.RUN])
    kinds = _read(monkeypatch)
    assert R.regressed(db, new_rules) == first
    assert kinds.count("incident") == len([i for i in first["runs"][0]["incidents"] if i["before"] is not None])
