"""scripts/margin_check.py, the independent oracle for issue 36's margins, checked on a run a
foreign producer wrote (tests/helpers/foreign.py), whose margins the test knows by construction:
a vehicle at steady speed crossing its stop line a known time after red, with amber a known
distance before it, and driving a known speed over its road's limit. No reasoner is used here:
the script's own measuring is what is tested."""
from __future__ import annotations

from pathlib import Path

import pytest

from store import Store
from tests.helpers.foreign import LINE_M, Foreign, Motion, crossroads, ns, rate, roads_through
from tests.helpers.script_module import load_script

MPH_PER_MPS = 2.2369362920544
SCRIPT = Path(__file__).resolve().parents[2] / "scripts" / "margin_check.py"
START = 5.0
SPEED = 20.0                    # m/s (44.7 mph) on a 30 mph road: 14.7 mph over
LAG = 1.3                       # s after red the line is crossed
AMBER_S = 3.0                   # amber before red: amber came SPEED * (LAG + AMBER_S) m before the line


@pytest.fixture(scope="module")
def script():
    return load_script(SCRIPT, "margin_check")


@pytest.fixture(scope="module")
def stored(tmp_path_factory, script):
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "lights")], roads=roads_through(0.0, 0.0, limit_mph=30))
    motion = Motion(-151.0, SPEED)     # the line crossed between two 10 Hz samples, amber too
    crossing = START + motion.when(-LINE_M)
    red_at = crossing - LAG
    run.spawn("7")
    run.lights("J1", "west", [(0.0, "green"), (red_at - AMBER_S, "amber"), (red_at, "red")])
    run.drive("7", motion, "west", rate(10, START, crossing + 4.0), t_start=START)
    run.end(crossing + 6.0)
    db = tmp_path_factory.mktemp("margin") / "foreign.db"
    with Store(db) as store:
        assert not store.append(run.events).rejected
    with Store.open_read_only(db) as store:
        raw = script.read(store, run.run)
    return raw, ns(crossing), run


def incident(quantity: str, value: float, unit: str, at: int, *, u: float = 0.05, bound: str | None = None,
             act: dict | None = None, method: str = "") -> dict:
    margin = {"quantity": quantity, "value": value, "unit": unit, "uncertainty": u, "method": method}
    if bound:
        margin["bound"] = bound
    return {"id": "m1:1", "vehicle": "7", "t": at, "margin": margin, "act": act}


def test_red_margin_is_the_known_lag_and_a_wrong_one_is_outside(script, stored):
    raw, crossing, _ = stored
    passage = {"kind": "junction passage", "where": "J1", "start": crossing - 10**9, "end": crossing + 10**9}
    seconds, first, _ = script.red(raw, incident("seconds after red the stop line was crossed", 0, "s", crossing,
                                                 act=passage), False)
    assert seconds == pytest.approx(LAG, abs=1e-6) and not first
    good = script.check_one(raw, incident("seconds after red the stop line was crossed", LAG + 0.04, "s", crossing,
                                          act=passage))
    bad = script.check_one(raw, incident("seconds after red the stop line was crossed", LAG + 0.3, "s", crossing,
                                         act=passage))
    assert (good.within, bad.within) == (True, False), (good, bad)
    # red's onset is in the record (green and amber were reported first): "at least" is contradicted
    bounded = script.check_one(raw, incident("seconds after red the stop line was crossed", LAG, "s", crossing,
                                             act=passage, bound="at least"))
    assert bounded.within is False and "onset" in bounded.note


def test_amber_margin_is_the_known_distance(script, stored):
    raw, crossing, _ = stored
    metres = SPEED * (LAG + AMBER_S)
    got = script.check_one(raw, incident("metres from the stop line when amber came", metres, "m", crossing,
                                         u=0.1, act={"kind": "junction passage", "where": "J1"}))
    assert got.script == pytest.approx(metres, abs=0.01) and got.within is True, got
    off = script.check_one(raw, incident("metres from the stop line when amber came", metres - 1.0, "m", crossing,
                                         u=0.1, act={"kind": "junction passage", "where": "J1"}))
    assert off.within is False, off


def test_speeding_margin_is_the_known_excess_on_the_named_road(script, stored):
    raw, crossing, _ = stored
    over = SPEED * MPH_PER_MPS - 30
    act = {"kind": "speeding stretch", "where": "EW", "start": crossing - 2 * 10**9, "end": crossing}
    got = script.check_one(raw, incident("mph over the speed limit", round(over, 1), "mph", crossing, u=0.22, act=act))
    assert got.script == pytest.approx(over, abs=1e-6) and got.within is True, got
    high = script.check_one(raw, incident("mph over the speed limit", round(over, 1) + 0.5, "mph", crossing, u=0.22,
                                          act=act))
    assert high.within is False, high
    # a stretch the vehicle's samples do not show (before it set off): nothing to check by, said so
    early = script.check_one(raw, incident("mph over the speed limit", 5.0, "mph", ns(0.0), u=0.22,
                                           act={**act, "start": ns(0.0), "end": ns(1.0)}))
    assert early.within is None and "no entity.state" in early.note, early


def test_stop_give_way_and_box_margins_are_the_known_figures(script, tmp_path):
    """A Stop junction where 7 creeps over its west line at 1.2 m/s (never below), c2 on the
    north arm brakes at 5 m/s² between two samples 1 s apart, and a box junction J2 where 8 stands
    4 s: the script measures each known figure, and an off one is outside."""
    j2 = {**crossroads("J2", 500.0, 0.0, "lights"), "box": [[490.0, -10.0], [510.0, -10.0], [510.0, 10.0],
                                                             [490.0, 10.0]]}
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop_sign"}), j2],
                  roads=roads_through(0.0, 0.0), monitors=[])
    creep = Motion(-60.0, 10.0, [(1.936, 0.0), (4.4, -2.0), (3.5, 0.0), (6.0, 2.0)])
    braking = Motion(-95.0, 13.4, [(4.0, 0.0), (2.0, -5.0), (6.0, 0.0)])
    stands = Motion(-35.0, 8.0, [(2.5, 0.0), (2.5, -3.2), (4.0, 0.0), (6.0, 2.0)])       # stands at s = -5, in the box
    for v in ("7", "c2", "8"):
        run.spawn(v)
    run.drive("7", creep, "west", rate(10, START, START + 20.0), t_start=START)
    states = run.drive("c2", braking, "north", rate(10, START, START + 12.0), t_start=START)
    run.drive("8", stands, "west", rate(10, START, START + 15.0), junction="J2", t_start=START)
    db = tmp_path / "foreign.db"
    with Store(db) as store:
        assert not store.append(run.events).rejected
    with Store.open_read_only(db) as store:
        raw = script.read(store, run.run)
    crossing = ns(START + creep.when(-LINE_M))
    passage = {"kind": "junction passage", "where": "J1"}
    got = script.check_one(raw, incident("slowest measured speed before the Stop line", 1.2 * MPH_PER_MPS, "mph",
                                         crossing, u=0.5, act=passage))
    assert got.script == pytest.approx(1.2 * MPH_PER_MPS, abs=0.01) and got.within is True, got
    off = script.check_one(raw, incident("slowest measured speed before the Stop line", 4.0, "mph", crossing, u=0.5,
                                         act=passage))
    assert off.within is False, off
    a, b = (next(e for e in states if e["t"] == ns(START + at)) for at in (4.5, 5.5))
    cited = [{"src": "vehicle/c2", "seq": e["seq"], "t": e["t"], "kind": "entity.state"} for e in (a, b)]
    gw = incident("deceleration of the other road user", 5.0, "m/s²", crossing, u=0.2, act=passage)
    gw["margin"]["evidence"] = cited
    assert script.check_one(raw, gw).script == pytest.approx(5.0, abs=0.01)
    gw["margin"]["value"] = 4.0
    assert script.check_one(raw, gw).within is False
    boxed = incident("seconds stopped in the box junction", 4.0, "s", ns(START + 7.0), u=0.2, bound="at least",
                     act={"kind": "junction passage", "where": "J2"})
    boxed["vehicle"] = "8"
    got = script.check_one(raw, boxed)
    assert got.script == pytest.approx(4.0, abs=0.11) and got.within is True, got
