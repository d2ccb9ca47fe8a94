"""What one investigation measured is what the next one judges from (reasoner/case_memo.py).

The second investigation of an unchanged run reads the cases, the states at the acts and the
measurements of the passages from the cache file, and re-runs the rulebooks only: its incidents
are the first one's, to the byte, without one history rebuilt. An entry whose seal does not
open, a run whose chain has grown, and a value of a type the codec does not keep are measured
afresh, and the seal failure is reported by `gaps verify`'s cache check."""
from __future__ import annotations

import json
import sqlite3
import sys
from pathlib import Path

import pytest

from reasoner import case_memo, history
from reasoner import investigation as investigation_module
from reasoner.judge import cases as cases_module
from reasoner.judge import court as court_module
from reasoner.derived import Contradiction
from reasoner.investigation import Investigation
from reasoner.measurement import Measurement
from reasoner.model import DerivedFact, Margin
from sim_replay.paper import paper_run
from store import EventRef, Store
from store.cache import cache_tampering

sys.path.insert(0, str(Path(__file__).parent))
from test_foreign_scenarios import FORCED, LAWFUL_STOP, ROLLING, give_way_run, mps, runner_run, stop_run  # noqa: E402
from test_verdict_paths import mixed_run  # noqa: E402


def _events(name: str) -> tuple[list[dict], str]:
    if name == "paper":
        events = paper_run()
        return events, events[0]["run"]
    if name == "mixed":
        events = mixed_run()
        return events, events[0]["run"]
    run = {"red runner": lambda: runner_run("7", mps(30), 1.5, "2 Hz", "camera")[0],
           "give way forced": lambda: give_way_run(FORCED, "5 Hz", "measured"),
           "stop rolled": lambda: stop_run(ROLLING, "2 Hz"),
           "lawful stop": lambda: stop_run(LAWFUL_STOP, "2 Hz")}[name]()
    run.end((max(e["t"] for e in run.events) - run.events[0]["t"]) / 1e9 + 1)
    return run.events, run.run


def _judged(db: Path, run: str) -> tuple[list[dict], Investigation]:
    with Store(db) as store:
        inv = Investigation(store)
        return [i.to_json() for i in inv.incidents(run)], inv


def _stored(tmp_path: Path, name: str) -> tuple[Path, str]:
    events, run = _events(name)
    db = tmp_path / "g.db"
    with Store(db) as store:
        assert not store.append(events).rejected
    return db, run


def _forbid(*args, **kwargs):
    raise AssertionError("measured again")


@pytest.mark.parametrize("name", ["paper", "mixed", "red runner", "give way forced", "stop rolled"])
def test_the_second_investigation_judges_what_the_first_measured_without_measuring(tmp_path, monkeypatch, name):
    db, run = _stored(tmp_path, name)
    cold, first = _judged(db, run)
    assert cold and first.memo(run).hits == 0
    monkeypatch.setattr(history, "passage", _forbid)
    monkeypatch.setattr(court_module, "state_of", _forbid)
    monkeypatch.setattr(cases_module, "episodes", _forbid)
    warm, second = _judged(db, run)
    assert warm == cold
    # nothing measured again; what the first measured of a case that came to nothing (an entry
    # the sweep of the vehicles' own record named, that no rule raises) is not even read: the
    # kept list of unraised cases skips it
    assert second.memo(run).misses == 0 and 0 < second.memo(run).hits <= first.memo(run).misses


def test_a_forged_measurement_is_dropped_measured_again_and_reported(tmp_path):
    """Someone who holds the folder rewrites the kept measurements (the red runner's passage made
    to say nothing: no margin, no derived fact): their seals no longer open, so it is measured again, the
    incidents are the untouched ones, and the cache check names the entry."""
    db, run = _stored(tmp_path, "red runner")
    cold, _ = _judged(db, run)
    assert any(i["margin"] for i in cold)
    nothing = json.dumps(case_memo.encode(Measurement(False)), separators=(",", ":"))   # "no passage here"
    with sqlite3.connect(f"{db}.cache") as cache:
        assert cache.execute("UPDATE derived SET payload = ? WHERE kind = 'measurement'", (nothing,)).rowcount
    with Store(db) as store:
        assert cache_tampering(store, [run]).derived[run]
        inv = Investigation(store)
        again = [i.to_json() for i in inv.incidents(run)]
        assert store.cache.sealer.tampered().get("derived")
    assert again == cold and inv.memo(run).misses >= 1


def test_a_run_that_has_grown_is_measured_afresh(tmp_path):
    """Kept entries belong to the chain they were derived from: one event more and none is used."""
    events, run = _events("red runner")
    db = tmp_path / "g.db"
    with Store(db) as store:
        store.append(events[:-1])
    _judged(db, run)
    with Store(db) as store:
        store.append(events[-1:])
    _, inv = _judged(db, run)
    assert inv.memo(run).hits == 0 and inv.memo(run).misses > 0


def test_the_codec_keeps_measurements_exactly_and_names_no_other_type():
    ref = EventRef("r", "vehicle/7", 12, 1_000, "vehicle.perception")
    contradiction = Contradiction("7 is too close to the stop line to stop safely", ref, "35.0 m out", "rule 126",
                                  (ref,))
    value = Measurement(True, 5, (DerivedFact("7 has speed of 30", "m/s", (ref,), None),), (contradiction,),
                        (("crossed the stop line", 5),), ("signal/j1",),
                        ((None, None), ("HC 176", Margin("s", 1.5, "s", (ref,), "", (("speed", 13.4, "m/s"),)))),
                        (("7 has amber light", "vehicle/7", 12, (contradiction,)),))
    text = json.dumps(case_memo.encode(value))
    assert case_memo.decode(json.loads(text)) == value
    with pytest.raises(KeyError):
        case_memo.decode({"@": "Path", "f": ["/etc/passwd"]})
    with pytest.raises(case_memo.Uncacheable):
        case_memo.encode(Path("/"))


def test_a_measurement_answers_for_every_rule_and_every_belief_it_measured():
    """The margin under a rule that picks none is the one without a rule; a belief it did not
    measure is not answered (the passage is asked instead)."""
    ref = EventRef("r", "vehicle/7", 12, 1_000, "vehicle.perception")
    red = Margin("seconds after red the stop line was crossed", 1.5, "s")
    amber = Margin("metres from the stop line when amber came", 20.0, "m")
    m = Measurement(True, 5, margins=((None, red), ("HC 175", amber), ("HC 176", red)),
                    beliefs=(("7 has amber light", "vehicle/7", 12, ()),))
    assert m.margin(" hc 175 ") == amber and m.margin("HC 999") == red and m.margin(None) == red
    assert m.contradicted([("7 has amber light.", ref)]) == ()
    assert m.contradicted([("7 is stopped", ref)]) is None


def test_values_no_fast_parser_reads_come_back_exactly(tmp_path):
    """Kept entries are read with orjson where it gives what `json` gives: an integer wider than
    64 bits, NaN and infinities (which orjson refuses or rounds) come back as they were kept."""
    db, run = _stored(tmp_path, "paper")
    ref = EventRef(run, "vehicle/7", 12, 2**70, "vehicle.perception")
    kept = Measurement(True, 2**70, (DerivedFact("7 has speed of 30", "m/s", (ref,), None),), (),
                       (("crossed the stop line", float("inf")),), (), ((None, Margin("s", -1e308, "s", (ref,), "", ())),), ())
    plain = {"big": 2**64 + 1, "neg": -(2**63) - 1, "inf": float("-inf"), "x": [1.5, "a", None, True]}
    with Store(db) as store:
        memo = case_memo.CaseMemo(store, run)
        memo.put("measurement", "k", kept)
        memo.put("state", "k", plain, plain=True)
        memo.save()
    with Store(db) as store:
        memo = case_memo.CaseMemo(store, run)
        assert memo.get("measurement", "k") == kept
        back = memo.get("state", "k", plain=True)
        assert back == plain and type(back["big"]) is int and back["inf"] == float("-inf")
        memo.put("state", "n", {"v": float("nan")}, plain=True)     # NaN != NaN: not plain, not kept
        memo.put("state", "m", {"v": 1.0}, plain=True)
        memo.save()
    with Store(db) as store:
        memo = case_memo.CaseMemo(store, run)
        assert memo.get("state", "n", plain=True) is None and memo.get("state", "m", plain=True) == {"v": 1.0}


def test_cases_are_judged_with_the_collector_paused_and_young_cycles_collected(tmp_path, monkeypatch):
    """A third of a judgement from kept measurements was the cyclic collector's full passes over
    everything judged so far; judging pauses it (after one full pass for what earlier
    judgements left: reasoner/collector.py), collects the young generations every YOUNG_EVERY
    cases, and leaves it on as it found it."""
    import gc
    db, run = _stored(tmp_path, "paper")
    seen, young = [], []
    judge = investigation_module.judge
    monkeypatch.setattr(investigation_module, "judge", lambda *a: seen.append(gc.isenabled()) or judge(*a))
    monkeypatch.setattr(investigation_module, "YOUNG_EVERY", 1)
    monkeypatch.setattr(investigation_module.gc, "collect", lambda generation=2: young.append(generation) or 0)
    assert gc.isenabled()
    found, _ = _judged(db, run)
    assert found and seen and not any(seen)
    assert young == [2] + [1] * len(seen)
    assert gc.isenabled()


def test_cases_the_monitor_rulebook_does_not_raise_are_not_judged_again_under_it(tmp_path, monkeypatch):
    """A swept case the monitor rules do not raise is no incident; the next investigation under the
    same monitor rulebook skips it (same incidents), one under another monitor rulebook judges it."""
    from reasoner.bundled import bundled
    db, run = _stored(tmp_path, "lawful stop")   # stationary at the line, then away: swept, not raised
    judged = []
    judge = investigation_module.judge
    monkeypatch.setattr(investigation_module, "judge",
                        lambda court, case, gaps, *proofs: judged.append(case.t) or judge(court, case, gaps, *proofs))
    first, _ = _judged(db, run)
    assert len(judged) > len(first)               # some swept cases were judged and raised nothing
    judged.clear()
    again, _ = _judged(db, run)
    assert again == first and len(judged) == len(first)
    judged.clear()
    other = tmp_path / "monitors.le"
    other.write_text(bundled("monitors.le") + "\n% another text, another sha256\n", encoding="utf-8")
    with Store(db) as store:
        Investigation(store, rules=[str(other)]).incidents(run)
    assert len(judged) > len(first)
