"""Each decision's form (its shape under a rulebook, reasoner/regress_decisions.py `Shapes`) kept
in the run's sealed cache under the shaper's identity: a later regression asks each kept shape
of its own rulebook without parsing or shaping a sentence, and gives what the plain path gives;
a forged form is not believed; a rulebook whose rules differ but whose templates and named
constants do not shares the forms and still answers with its own rules."""
from __future__ import annotations

import json
import sqlite3

import pytest

from reasoner.regress import regression as regress_module
from reasoner.regress import decisions as regress_decisions
from reasoner.engine import get_engine
from reasoner.shapes import Shaper
from store import Store
from store.cache import cache_tampering

from tests.reasoner import regress_runs as R
from tests.reasoner.regress_runs import db, new_rules  # noqa: F401 (fixtures)


def _masked(result: dict, *paths) -> str:
    text = json.dumps(result, sort_keys=True)
    for n, path in enumerate(paths):
        text = text.replace(str(path), f"RULES{n}")
    return text


def test_a_later_regression_shapes_no_decision_and_gives_the_plain_paths_result(db, new_rules, monkeypatch):
    first = R.regressed(db, new_rules)
    assert first["changed"] and first["counts"]["decisions"] == 4
    calls = R.shaping(monkeypatch)
    again = R.regressed(db, new_rules)
    assert again == first == R.plain(db, new_rules)
    assert calls == []                  # every decision's form read from the cache


def test_a_forged_kept_form_is_not_believed(db, new_rules):
    """The kept forms altered (every decision pointed at the first shape): the seal does not
    open, `gaps verify`'s check names the entry, and the decisions are shaped again."""
    first = R.regressed(db, new_rules)
    with sqlite3.connect(f"{db}.cache") as cache:
        rows = cache.execute("SELECT key, payload FROM derived WHERE kind = 'shapes'").fetchall()
        assert rows
        for key, payload in rows:
            data = json.loads(payload)
            data["of"] = {ident: 0 for ident in data["of"]}
            cache.execute("UPDATE derived SET payload = ? WHERE kind = 'shapes' AND key = ?", (json.dumps(data), key))
    with Store.open_read_only(db) as store:
        assert any(key.startswith("shapes ") for key in cache_tampering(store, [R.RUN]).derived[R.RUN])
    assert R.regressed(db, new_rules) == first


def test_a_rulebook_shaping_alike_reads_the_forms_and_answers_with_its_own_rules(db, new_rules, tmp_path,
                                                                                   monkeypatch):
    """validators.le as it is and without its amber exception have the same templates and name the
    same constants: the second regression reads the forms the first kept, and its answers are its
    own rulebook's (the amber decision permitted again, as the plain path finds)."""
    engine = get_engine()
    cut = regress_module.load_given(engine, [str(new_rules)]).books[0]
    whole_path = R.edited(tmp_path / "whole", "validators.le")
    whole = regress_module.load_given(engine, [str(whole_path)]).books[0]
    assert cut.sha256 != whole.sha256 and Shaper(cut).identity == Shaper(whole).identity
    first = R.regressed(db, new_rules)
    calls = R.shaping(monkeypatch)
    second = R.regressed(db, whole_path)
    assert calls == []
    assert _masked(second, whole_path) == _masked(R.plain(db, whole_path), whole_path)
    assert first["counts"].get("decision") and not second["counts"].get("decision")


def test_the_shapers_identity_follows_its_templates_and_named_constants(tmp_path):
    engine = get_engine()
    base = regress_module.load_given(engine, [str(R.edited(tmp_path / "a", "validators.le"))]).books[0]
    more = regress_module.load_given(engine, [str(R.edited(tmp_path / "b", "validators.le", add=R.GREEN_RULE.replace(
        "the vehicle has green light", "the vehicle has green light\n    and the vehicle is of type tram")))]).books[0]
    assert Shaper(base).identity != Shaper(more).identity       # "tram" now named by a rule: never renamed


def test_a_kept_scenario_is_made_only_for_a_decision_that_needs_its_sentences(db, new_rules, monkeypatch):
    """With the forms kept, only a changed decision (whose two proofs are searched) reads its
    Vehicle Scenario; the others' are never made into sentences and events."""
    first = R.regressed(db, new_rules)
    made: list = []
    unkept = regress_decisions._unkept_facts
    monkeypatch.setattr(regress_decisions, "_unkept_facts", lambda *a: made.append(a[0]) or unkept(*a))
    assert R.regressed(db, new_rules) == first
    assert len(made) == first["counts"]["decision"] == 1
