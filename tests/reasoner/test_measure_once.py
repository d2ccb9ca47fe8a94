"""One measurement of an act works each question about its passage out once (reasoner/measurement.py,
reasoner/derived.py): the facts the passage shows at the act, whatever the number of perceived facts
checked against them, and whether something else explains each road user's braking, however often
the facts and the margins ask it. A run's first judgement measures every case, so these repeats
were most of its cost; the answers are the ones asked afresh."""
from reasoner import derived, history, measurement
from reasoner.history import own_cause
from store import EventRef
from tests.helpers.foreign import Motion
from tests.reasoner.test_foreign_scenarios import _SET_OFF, stop_then_go_run

SECOND = 1_000_000_000


def _pulling_out():
    """7 stops at its Stop line, then pulls out; c2 on the main road brakes hard to a stop just after
    (tests/reasoner/test_foreign_scenarios.py: punishable, HC 171); the passage of 7's crossing."""
    c2 = Motion(-164.0, 13.4, [(_SET_OFF + 0.9 + 0.71, 0.0), (13.4 / 5.0, -5.0), (4.0, 0.0), (8.0, 2.0)])
    run = stop_then_go_run(("c2", c2, "north"))
    crossing = next(p for p in history.from_events(run.events, "7") if p.crossing is not None)
    return crossing, run.run


def _perceived(run: str, n: int) -> list[tuple[str, EventRef]]:
    return [("7 has a stop sign", EventRef(run, "vehicle/7", 100 + i, 0, "vehicle.perception")) for i in range(n)]


def _counting(monkeypatch, name: str) -> list[int]:
    calls: list[int] = []
    real = getattr(derived, name)

    def counted(*args):
        calls.append(1)
        return real(*args)
    monkeypatch.setattr(derived, name, counted)
    return calls


def test_the_facts_of_a_passage_are_derived_once_per_measurement_however_many_perceived_facts(monkeypatch):
    p, run = _pulling_out()
    first, *rest = derived._DERIVERS
    calls: list[int] = []

    def counted(*args):
        calls.append(1)
        return first(*args)
    monkeypatch.setattr(derived, "_DERIVERS", (counted, *rest))
    found = measurement.measure(p, p.crossing.t, "enter the junction", [], [], _perceived(run, 3))
    assert found.present and len(found.beliefs) == 3
    assert len(calls) == 1


def test_whether_a_road_users_braking_is_explained_is_worked_out_once_per_measurement(monkeypatch):
    p, run = _pulling_out()
    calls = _counting(monkeypatch, "paths_within")       # asked once by each working out of `explained`
    braked = [o for o in derived.reacting(p) if not own_cause(o) and (o.braking or o.stopped)]
    assert braked, "the run has a road user whose braking the vehicle may explain"
    found = measurement.measure(p, p.crossing.t, "enter the junction", [], [], _perceived(run, 2))
    assert "7 would force c2 to change speed or course" in {f.sentence for f in found.derived}
    assert len(calls) == len(braked)

