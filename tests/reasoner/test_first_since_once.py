"""Whether a constant of a case's facts names another road user on record by the act's time is
asked of every constant of every case: when its sources became entities is worked out once per
run and constant (reasoner/judge/court.py `first_since`), with the answers it gave before."""
from __future__ import annotations

from types import SimpleNamespace

from reasoner.engine import get_engine
from reasoner.facts import FactReader
from reasoner.judge import Court
from reasoner.le.terms import Atom
from store import Store


def test_each_constant_s_sources_are_looked_up_once_per_run(tmp_path, monkeypatch):
    with Store(tmp_path / "g.db") as store:
        court = Court(store, get_engine(), FactReader(), {})
        since = {"vehicle/288": 5.0, "pedestrian/288": 2.0, "vehicle/12": float("inf")}
        asked: list[str] = []
        monkeypatch.setattr(court, "named", lambda run: {288: ["vehicle/288", "pedestrian/288"], 12: ["vehicle/12"]})
        monkeypatch.setattr(court, "since_once", lambda run, src: asked.append(src) or since[src])
        pairs = [(Atom("is_approaching", (288, 1340)), None), (Atom("is_behind", (12, 1340)), None),
                 (Atom("has_speed", (1340, 7)), None)]
        found = [court.others(SimpleNamespace(run="r", me=1340, t=t), pairs) for t in (1, 2, 3, 6, 1)]
        assert found == [set(), {288}, {288}, {288}, set()]
        assert sorted(asked) == sorted(since)          # each source once, however many cases ask
