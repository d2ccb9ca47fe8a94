"""An investigation renders each validator fact of text and whole numbers once: a regression's
new side renders the Validator Scenario of every case, and cases share many of its facts (a
vehicle's type, its light). An atom with a float or a bool is rendered each time (1.0 and True
equal 1 but do not render as it)."""
from __future__ import annotations

import sys
from collections import Counter

import pytest

from reasoner.engine import Rulebook
from reasoner.investigation import Investigation, Speedups
from reasoner.le.terms import Atom
from store import Store
from tests.reasoner import regress_runs as R


@pytest.fixture
def db(tmp_path):
    return R.build_store(tmp_path / "gaps.db")


def _counted(monkeypatch) -> Counter:
    rendered: Counter = Counter()
    render = Rulebook.render

    def counted(rb, data):
        text = render(rb, data)
        if type(data) is Atom and _from_validate():
            rendered[(rb.sha256, data)] += 1
        return text
    monkeypatch.setattr(Rulebook, "render", counted)
    return rendered


def _from_validate() -> bool:
    """Whether the render asked is of the Validator Scenario's facts (in reasoner/judge/validator_stage.py `validate`,
    not its why)."""
    frame = sys._getframe(2)
    if frame.f_code.co_name not in ("<genexpr>", "render"):
        return False
    for _ in range(3):
        if frame is None:
            return False
        if frame.f_code.co_name == "validate":
            return True
        frame = frame.f_back
    return False


def test_each_validator_fact_is_rendered_once_and_alike(db, monkeypatch):
    with Store.open_read_only(db) as store:
        plain = [i.to_json() for i in Investigation(store, speedups=Speedups.NONE).incidents(R.RUN)]
        rendered = _counted(monkeypatch)
        inv = Investigation(store, speedups=Speedups.NONE)
        once = [i.to_json() for i in inv.incidents(R.RUN)]
        again = [i.to_json() for i in inv.incidents(R.RUN)]     # the same facts again, already rendered
    assert once == plain and again == plain and rendered
    assert [k for k, n in rendered.items() if n > 1] == []


def test_an_atom_equal_to_another_of_other_types_is_rendered_as_itself(db, monkeypatch):
    with Store.open_read_only(db) as store:
        inv = Investigation(store, speedups=Speedups.NONE)
        rb = inv.ruleset(R.RUN, [])["validator"].rulebook
        whole, real, truth = (inv.court.render(rb, Atom("has_speed_of", ("5", v))) for v in (1, 1.0, True))
    assert whole == rb.render(Atom("has_speed_of", ("5", 1)))
    assert real == rb.render(Atom("has_speed_of", ("5", 1.0)))
    assert truth == rb.render(Atom("has_speed_of", ("5", True)))
