"""reasoner/case_memo.key_of names a kept entry by what it was asked on: two questions that differ
in any value must never share a key (a kept answer would be taken for another question's)."""
from __future__ import annotations

import itertools

from reasoner.case_memo import key_of
from store import EventRef

REF = EventRef("r", "monitor/m1", 12, 1_000, "monitor.observation")


def _apart(*values) -> None:
    keys = [key_of("q", v) for v in values]
    for (a, ka), (b, kb) in itertools.combinations(zip(values, keys), 2):
        assert ka != kb, (a, b)


def test_values_that_differ_get_different_keys():
    _apart((1, 2), [1, 2], [[1, 2]], [(1, 2)], ((1, 2),))
    _apart(1, 1.0, True, "1", None, 0, False, 0.0, -0.0, [], (), "", {})
    _apart(float("nan"), float("inf"), float("-inf"), "NaN", "nan", None, "Infinity")
    _apart(2 ** 70, float(2 ** 70), 2 ** 70 + 1, -(2 ** 70), str(2 ** 70))
    _apart(REF, ("@ref", "r", "monitor/m1", 12, 1_000, "monitor.observation"),
           ["@ref", "r", "monitor/m1", 12, 1_000, "monitor.observation"], repr(REF),
           EventRef("r", "monitor/m1", 12, 1_000, None), EventRef("r", "monitor/m1", 13, 1_000, "monitor.observation"))
    _apart(["a", "b"], ["a,b"], ['a", "b'], ["a", "b", None])
    _apart({"a": 1}, {"a": 1.0}, [["a", 1]], {"a": (1,)})


def test_equal_values_get_one_key():
    assert key_of("q", [["7 has red light", REF]], (1, 2)) == \
        key_of("q", [["7 has red light", EventRef("r", "monitor/m1", 12, 1_000, "monitor.observation")]], (1, 2))
    assert key_of(float("nan")) == key_of(float("nan"))
    assert key_of("q", 1) != key_of("q", [1]) != key_of(["q", 1])


def test_a_warm_regression_names_its_questions_without_an_event_reference_s_repr(tmp_path, monkeypatch):
    """A stage question names each fact's event by the reference's fields (judge/asking.py
    `as_asked`): the reference's own repr, a Python call each, was half of a question's key."""
    from tests.reasoner import regress_runs as R
    db = R.build_store(tmp_path / "gaps.db")
    rules = R.edited(tmp_path / "new", "validators.le", cut=(R.AMBER_TOO_CLOSE,))
    first = R.regressed(db, rules)
    shown: list[EventRef] = []
    monkeypatch.setattr(EventRef, "__repr__", lambda ref: shown.append(ref) or "EventRef(...)")
    assert R.regressed(db, rules) == first
    assert not shown
