"""What the history keeps from one act to the next (reasoner/history.py: the junction monitors'
observations of the last window read, the other road users' spawns) and its short cuts
(Junction.inside, motion.sample_of) give what reading afresh and the long way give."""
import math

from reasoner.history import read as history  # its MAX_OTHER_EVENTS is patched below
from reasoner.history import read_map
from reasoner.history import sample_of
from store import Store
from tests.helpers.foreign import Foreign, Motion, crossroads, ns, rate


def busy_junction() -> tuple[Foreign, dict[str, float]]:
    """Five vehicles through J1 a few seconds apart, each driving and watched by m1: the windows
    of their passages overlap, each begins and ends somewhere else in the last one read."""
    run = Foreign()
    crossings = {}
    for i, (vehicle, approach) in enumerate([("7", "west"), ("8", "north"), ("9", "east"), ("10", "south"),
                                             ("11", "west")]):
        start = 3.0 * i + (1.5 if i == 3 else 0.0)
        motion = Motion(-100, 12.0)
        run.spawn(vehicle, at=start)
        run.drive(vehicle, motion, approach, rate(5, start, start + 16), t_start=start)
        run.watch(vehicle, motion, approach, rate(5, start, start + 16), t_start=start)
        crossings[vehicle] = start + motion.when(-12.0)
    run.lights("J1", "west", [(0, "green")])
    return run, crossings


def test_passages_read_one_after_another_are_those_read_afresh(tmp_path):
    run, crossings = busy_junction()
    with Store(tmp_path / "gaps.db") as store:
        assert not store.append(run.events).rejected
        shared = history.run_context(store, "foreign-1")
        again = [(vehicle, crossings[vehicle]) for vehicle in ("10", "8", "7")]     # back in time: read before
        for vehicle, at in list(crossings.items()) + again:
            kept = history.passage(store, "foreign-1", vehicle, ns(at), context=shared)
            afresh = history.passage(store, "foreign-1", vehicle, ns(at),
                                     context=history.run_context(store, "foreign-1"))
            assert kept == afresh
            assert kept.others and all(o.type == "car" for o in kept.others)
        assert shared._seen and shared._spawns


def test_a_window_cut_short_is_not_kept(tmp_path, monkeypatch):
    """Beyond MAX_OTHER_EVENTS only the first are read; such a window is not whole, and the next
    act reads its own."""
    run, crossings = busy_junction()
    monkeypatch.setattr(history, "MAX_OTHER_EVENTS", 30)
    with Store(tmp_path / "gaps.db") as store:
        store.append(run.events)
        shared = history.run_context(store, "foreign-1")
        for vehicle in ("7", "8", "9"):
            kept = history.passage(store, "foreign-1", vehicle, ns(crossings[vehicle]), context=shared)
            afresh = history.passage(store, "foreign-1", vehicle, ns(crossings[vehicle]),
                                     context=history.run_context(store, "foreign-1"))
            assert kept == afresh
        assert not shared._seen


def test_inside_turns_away_only_what_the_distance_would():
    for shape in ({}, {"box_m": 12.0}):
        start = {"src": "sim", "seq": 0, "t": 0, "kind": "run.start",
                 "body": {"map": {"junctions": [{**crossroads("J1", 3.0, -2.0, "lights"), **shape}], "roads": []}}}
        j = read_map(start).junctions[0]
        e = j.extent_m
        for x in (3.0 - e, 3.0 + e, math.nextafter(3.0 + e, 99), math.nextafter(3.0 + e, -99), 3.0 + e / 2, 50.0):
            for y in (-2.0, -2.0 + e, math.nextafter(-2.0 - e, -99), -2.0 + e * 0.7, -40.0, float("nan")):
                assert j.inside(x, y) == (j.edge(x, y) <= 0.0), (shape, x, y)


def test_a_sample_of_plain_measurements_is_the_one_checked_the_long_way():
    base = {"v": 1, "run": "r", "src": "vehicle/7", "seq": 4, "t": 10, "kind": "entity.state"}
    plain = {**base, "body": {"x": 1.5, "y": -2.25, "speed_mps": 0.0, "heading_deg": 90.0, "road": "R1"}}
    ints = {**base, "body": {"x": 1, "y": -2, "speed_mps": 3, "heading_deg": 90, "road": "R1"}}
    sample, why = sample_of(plain)
    assert why is None and (sample.x, sample.y, sample.speed_mps, sample.heading_deg, sample.road) == \
        (1.5, -2.25, 0.0, 90.0, "R1")
    assert sample.ref.key == ("vehicle/7", 4)
    converted, why = sample_of(ints)
    assert why is None and (converted.x, converted.y, converted.speed_mps) == (1.0, -2.0, 3.0)
    assert type(converted.x) is float
    for speed in (-0.5, 151.0, float("nan"), True):
        s, why = sample_of({**base, "body": {"x": 1.5, "y": 2.0, "speed_mps": speed}})
        assert s.speed_mps is None and "speed_mps left out" in why
