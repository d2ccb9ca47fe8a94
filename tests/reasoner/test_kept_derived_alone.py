"""A regression's new side judges a case as far as its summary goes, which reads what the case's
measurement derived and nothing else of it: that is kept in its own entry beside the
measurement, so the summary neither reads nor seals the whole measurement."""
from __future__ import annotations

from reasoner import case_memo
from tests.reasoner import regress_runs as R
from tests.reasoner.regress_runs import db, new_rules  # noqa: F401 (fixtures)


def test_a_summary_reads_the_derived_facts_alone_and_judges_alike(db, new_rules, monkeypatch):
    first = R.regressed(db, new_rules)
    read: list[str] = []
    text = case_memo.CaseMemo.text

    def counted(memo, kind, key):
        found = text(memo, kind, key)
        read.append(kind if found is not None else f"missing {kind}")
        return found
    monkeypatch.setattr(case_memo.CaseMemo, "text", counted)
    assert R.regressed(db, new_rules) == first
    assert read.count("derived") > read.count("measurement")
    assert not [kind for kind in read if kind in ("missing derived", "missing measurement")]
