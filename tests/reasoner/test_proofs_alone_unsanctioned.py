"""A summarised incident's proofs are worked out alone (the monitor stage's and the verdict's):
the penalty and who is liable are no part of them, so working them out asks neither."""
from __future__ import annotations

from reasoner.judge import sanctions as sanctions_module
from store import Store

from tests.reasoner import regress_runs as R
from tests.reasoner.regress_runs import db, new_rules  # noqa: F401 (fixtures)


def test_proving_a_summarised_incident_asks_no_sanctions(db, new_rules, monkeypatch):
    with Store.open_read_only(db) as store:
        full, found, _ = R.summarised(store, new_rules)
        assert any(i.penalty is not None for i in found)
        asked: list = []
        sanctions = sanctions_module.sanctions
        monkeypatch.setattr(sanctions_module, "sanctions", lambda *a: asked.append(a) or sanctions(*a))
        assert [i.proofs for i in found] == [i.proofs for i in full]
        assert asked == []
        assert [i.whole() for i in found] == full
