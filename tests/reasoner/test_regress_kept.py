"""A regression from what earlier ones kept (Speedups.BASELINE, reasoner/speedups/kept_verdicts.py;
reasoner/regress/decisions.py): the baseline's incidents and decision answers under the rulebooks in
force are read, not judged or asked again, and the decisions' Vehicle Scenarios are kept with
them, so that no decision or perception is read again; the new rules are judged afresh every time. The
result is the plain path's, to the byte, and a forged kept verdict is dropped and judged again."""
from __future__ import annotations

import json
import sqlite3

import pytest

from reasoner import case_memo
from reasoner.regress import decisions as regress_decisions
from reasoner.regress import regression as regress_module
from reasoner.api import Case
from reasoner.investigation import Investigation, Speedups
from reasoner.regress import regress
from store import EventRef, Store
from store.cache import cache_tampering

from tests.reasoner import regress_runs as R


@pytest.fixture
def db(tmp_path):
    return R.build_store(tmp_path / "gaps.db")


@pytest.fixture
def new_rules(tmp_path):
    return R.edited(tmp_path, "validators.le", cut=(R.AMBER_TOO_CLOSE,))      # answers the vehicle stage too


class _Count:
    """Calls of Investigation._afresh by side, of ask, and the kinds read."""

    def __init__(self, monkeypatch) -> None:
        self.judged = {True: 0, False: 0}
        self.asked = 0
        self.kinds: list[str] = []
        afresh, ask, events = Investigation._afresh, regress_module.ask, Store.events

        def counted_afresh(inv, *args):
            self.judged[inv.speedups.keeps_incidents] += 1
            return afresh(inv, *args)

        def counted_ask(*args, **kwargs):
            self.asked += 1
            return ask(*args, **kwargs)

        def counted_events(store, run, **kwargs):
            self.kinds += list(kwargs.get("kinds") or ["*"])
            return events(store, run, **kwargs)
        monkeypatch.setattr(Investigation, "_afresh", counted_afresh)
        monkeypatch.setattr(regress_module, "ask", counted_ask)
        monkeypatch.setattr(Store, "events", counted_events)


def test_a_second_regression_reads_the_baselines_verdicts_and_answers_and_gives_the_same(db, new_rules, monkeypatch):
    first = R.regressed(db, new_rules)
    assert first["changed"] and first["counts"]["decisions"] == 4
    count = _Count(monkeypatch)
    again = R.regressed(db, new_rules)
    assert again == first
    assert count.judged[True] == 0 and count.judged[False] == 3       # the baseline kept, the new rules judged
    assert count.asked == 4 + 2                                          # the new side's, and the changed one's proofs
    assert not {"vehicle.perception", "vehicle.decision"} & set(count.kinds), count.kinds   # the scenarios kept


def test_the_kept_path_gives_the_plain_paths_regression(db, new_rules):
    plain = R.plain(db, new_rules)
    assert R.regressed(db, new_rules) == plain          # keeps
    assert R.regressed(db, new_rules) == plain          # from what it kept


def test_a_forged_kept_verdict_is_dropped_and_judged_again(db, new_rules):
    """Someone who holds the folder turns the kept punishable verdicts mitigated: the seals no
    longer open, so the baseline is judged again, the result is the untouched one, and the cache
    check names the entries."""
    first = R.regressed(db, new_rules)
    _forge(db, "incident", '"punishable"', '"mitigated"')
    assert R.regressed(db, new_rules) == first


def _forge(db, kind: str, was: str, now: str) -> None:
    """Rewrite `was` as `now` in the kept entries of `kind` that hold it, as someone holding the
    folder could; the cache check must name them."""
    with sqlite3.connect(f"{db}.cache") as cache:
        assert cache.execute("UPDATE derived SET payload = replace(payload, ?, ?) WHERE kind = ? AND "
                             "instr(payload, ?) > 0", (was, now, kind, was)).rowcount
    with Store.open_read_only(db) as store:
        assert any(key.startswith(f"{kind} ") for key in cache_tampering(store, [R.RUN]).derived[R.RUN])


def test_a_forged_kept_decision_answer_is_not_believed(db, new_rules):
    first = R.regressed(db, new_rules)
    with sqlite3.connect(f"{db}.cache") as cache:
        assert cache.execute("UPDATE derived SET payload = replace(payload, 'true', 'false') "
                             "WHERE kind = 'decisions'").rowcount
    assert R.regressed(db, new_rules) == first


def test_gaps_incidents_keeps_the_judgement_in_force_and_not_one_with_given_rules(db, new_rules, monkeypatch):
    with Store.open_read_only(db) as store:
        first = [i.to_json() for i in Case(store).incidents(R.RUN)]
    count = _Count(monkeypatch)
    with Store.open_read_only(db) as store:
        assert [i.to_json() for i in Case(store).incidents(R.RUN)] == first
        assert count.judged[True] == 0
        Case(store, [new_rules]).incidents(R.RUN)
        Case(store, [new_rules]).incidents(R.RUN)
    assert count.judged[True] == 6                   # given rules: judged each time


def test_the_codec_keeps_every_incident_exactly(db):
    with Store.open_read_only(db) as store:
        found = Investigation(store, speedups=Speedups.NONE).incidents(R.RUN)
    assert found
    for incident in found:
        assert case_memo.decode(json.loads(json.dumps(case_memo.encode(incident)))) == incident


def test_the_kept_decisions_are_the_recorded_ones_with_their_scenarios(db, new_rules):
    """What a regression keeps of each decision (its Vehicle Scenario: sentences and the events
    they cite) is what reading the run gives, so asking a new rulebook on it is asking on the run."""
    R.regressed(db, new_rules)
    with Store.open_read_only(db) as store:
        recorded = list(regress_decisions.recorded_decisions(store, R.RUN))
        kept = regress_decisions.kept_decisions(case_memo.CaseMemo(store, R.RUN))
    assert kept is not None and any(len({ref for _, ref in d.facts}) == 2 for d in recorded)
    assert [k.decision for k in kept] == recorded


def test_a_forged_kept_scenario_is_not_asked(db, new_rules):
    """A kept decision's sentence altered (the vehicle now saw green where it saw red): the seal
    does not open, the decisions are read from the run again, and the result is the untouched one."""
    first = R.regressed(db, new_rules)
    _forge(db, "decisions", "red light", "green light")
    assert R.regressed(db, new_rules) == first


def test_decisions_asked_once_per_shape_answer_as_asked_one_by_one(db):
    from reasoner.engine import get_engine
    from reasoner.facts import FactReader
    from reasoner.stages import RuleSet, current_rulebooks
    engine, reader, shapes = get_engine(), FactReader(), regress_decisions.Shapes()
    rs = RuleSet(engine, [], [], current_rulebooks(engine))
    with Store.open_read_only(db) as store:
        decisions = list(regress_decisions.recorded_decisions(store, R.RUN)) * 3
    calls = []
    holds = engine.holds

    class Counting:
        def holds(self, *args):
            calls.append(args)
            return holds(*args)
    one_by_one = [regress_decisions.ask(engine, reader, regress_decisions.vehicle_choice(rs, d), d) for d in decisions]
    shaped = [regress_decisions.ask(Counting(), reader, regress_decisions.vehicle_choice(rs, d), d, shapes=shapes)
              for d in decisions]
    assert shaped == one_by_one and any(a.permitted for a in shaped)
    assert 0 < len(calls) <= len(decisions) // 3          # each shape asked once, the repeats not at all


def test_a_decision_asked_again_in_the_same_words_is_neither_parsed_nor_shaped(db, monkeypatch):
    """The answer remembered by the sentences themselves: a repeat costs a look-up. A sentence
    that is not text (a producer's list) is asked, never remembered. What shaping needs of a
    sentence is worked out once, however many decisions hold it."""
    from dataclasses import replace
    from reasoner.engine import get_engine
    from reasoner.facts import FactReader
    from reasoner.stages import RuleSet, current_rulebooks
    engine, reader, shapes = get_engine(), FactReader(), regress_decisions.Shapes()
    rs = RuleSet(engine, [], [], current_rulebooks(engine))
    with Store.open_read_only(db) as store:
        decisions = list(regress_decisions.recorded_decisions(store, R.RUN))
    odd = replace(decisions[0], facts=(*decisions[0].facts, (["not", "a", "sentence"], decisions[0].facts[0][1])))
    decisions += [odd, odd]
    one_by_one = [regress_decisions.ask(engine, reader, regress_decisions.vehicle_choice(rs, d), d) for d in decisions]
    shaped, planned = [], []
    asked, plan = regress_decisions.Shapes._asked, regress_decisions.Shaper.plan
    monkeypatch.setattr(regress_decisions.Shapes, "_asked",
                        lambda self, *a: shaped.append(1) or asked(self, *a))
    monkeypatch.setattr(regress_decisions.Shaper, "plan", lambda self, atom: planned.append(atom) or plan(self, atom))
    again = [regress_decisions.ask(engine, reader, regress_decisions.vehicle_choice(rs, d), d, shapes=shapes)
             for d in decisions * 3]
    assert again == one_by_one * 3
    distinct = {(d.goal, *(text for text, _ in d.facts)) for d in decisions[:-2]}
    sentences = {text for d in decisions for text in (d.goal, *(t for t, _ in d.facts)) if isinstance(text, str)}
    assert len(planned) == len(set(planned)) <= len(sentences)     # each sentence planned once, whoever says it
    assert len(shaped) == len(distinct) + 2 * 3          # each wording shaped once; the odd one every time


def test_a_regression_collects_once_for_both_sides(db, new_rules, monkeypatch):
    import gc
    full = []
    collect = gc.collect
    monkeypatch.setattr(gc, "collect", lambda generation=2: full.append(generation) if generation == 2 else None
                        or collect(generation))
    R.regressed(db, new_rules)
    assert full.count(2) == 1


def test_the_codec_keeps_plain_data_as_it_is_and_tags_what_json_would_change():
    tree = {"sentence": ["can", 5, "go"], "children": [{"rule": None, "x": 1.5}]}
    assert case_memo.encode(tree) == {"j": tree}
    for value in ({"v": float("nan")}, {"v": (1, 2)}, {1: "a"}, {"r": [EventRef("r", "s", 1, 2, "k")]}):
        encoded = case_memo.encode(value)
        assert "j" not in encoded
        back = case_memo.decode(json.loads(json.dumps(encoded)))
        assert repr(back) == repr(value)


def test_the_new_side_asks_only_the_rulebooks_it_does_not_share_with_the_baseline(db, new_rules, monkeypatch):
    """The monitor, decision fault, penalty and liability stages' answers the judgement in force
    kept are read by the new side, which asks the same rulebooks the same questions on the same
    facts; the new validators.le is asked (its verdicts, and the decisions: it answers the vehicle
    stage), and the others only what no kept answer covers: a changed case's."""
    from reasoner.bundled import CURRENT_SET, bundled
    from reasoner.engine import Engine, sha256_text
    first = R.regressed(db, new_rules)
    asked: list[str] = []
    for name in ("ask", "holds", "ask_first", "first_holding", "answers", "answers_all"):
        original = getattr(Engine, name)

        def counted(self, rb, *args, _original=original, **kwargs):
            asked.append(names.get(rb.sha256, rb.sha256))
            return _original(self, rb, *args, **kwargs)
        monkeypatch.setattr(Engine, name, counted)
    names = {sha256_text(bundled(n)): n for n in CURRENT_SET}      # the engine names a text by its first load
    names[sha256_text(new_rules.read_text(encoding="utf-8"))] = "new"
    assert R.regressed(db, new_rules) == first
    flipped = [case for case in first["runs"][0]["incidents"] if case["changes"]]
    assert len(flipped) == 1 and flipped[0]["after"].startswith("punishable")
    assert "monitors.le" not in asked and "new" in asked
    assert asked.count("liability.le") == 1              # for the one verdict now punishable, never kept
    assert asked.count("highway_code.le") == 1           # the changed decision's baseline proof, never kept


def test_a_regression_names_its_runs_without_summing_them_up(db, new_rules, monkeypatch):
    """The runs are chosen by name: a run's summary counts its events, a scan of the hour's 11
    million index entries for a list of names."""
    def summed(store):
        raise AssertionError("Store.runs counts every event of every run")
    monkeypatch.setattr(Store, "runs", summed)
    with Store.open_read_only(db) as store:
        assert regress(store, [str(new_rules)]).counts()["runs"] == 1
        with pytest.raises(regress_module.NoSuchRun):
            regress(store, [str(new_rules)], runs=["no-such-run"])


def test_the_new_side_searches_a_verdicts_proof_only_where_it_changed(db, new_rules, monkeypatch):
    from reasoner.engine import Engine, sha256_text
    first = R.regressed(db, new_rules)
    new = sha256_text(new_rules.read_text(encoding="utf-8"))
    proofs: list[str] = []
    ask_first = Engine.ask_first

    def counted(self, rb, *args, **kwargs):
        proofs.append(rb.sha256)
        return ask_first(self, rb, *args, **kwargs)
    monkeypatch.setattr(Engine, "ask_first", counted)
    assert R.regressed(db, new_rules) == first
    changed = [case for case in first["runs"][0]["incidents"] if case["changes"]]
    assert len(first["runs"][0]["incidents"]) > len(changed) == proofs.count(new) == 1
