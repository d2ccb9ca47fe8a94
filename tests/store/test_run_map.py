"""The run map read once (store/run_map.py): every part typed, what cannot be read None, lists
bounded; and the reasoner's map, the report's picture and the MCAP export all read it so."""
import math

import pytest

from explain.report_data import run_map
from reasoner.history import read_map
from store.run_map import read_run_map
from store import run_map as rm


def start(the_map, **more):
    return {"v": 1, "run": "r", "src": "sim/world", "seq": 0, "t": 0, "kind": "run.start",
            "body": {"map": the_map, **more}}


@pytest.mark.parametrize("junk", [float("nan"), float("inf"), -float("inf"), True, "3", None, [1], {"a": 1}, 10 ** 400])
def test_what_is_not_a_finite_number_is_none(junk):
    assert rm.number(junk) is None
    assert rm.pair([junk, 1]) == (None, 1.0) and rm.whole(rm.pair([junk, 1])) is None


def test_numbers_ids_and_labels():
    assert rm.number(2) == 2.0 and isinstance(rm.number(2), float) and rm.number(-1.5) == -1.5
    assert (rm.ident(5), rm.label(5), rm.ident("J1"), rm.label(None)) == (None, "5", "J1", None)
    assert rm.polyline("a box") is None and rm.whole_line(rm.polyline([[0, 0], ["x", 1]])) == ()


def test_no_map_and_no_run_start():
    assert not read_run_map(None).recorded and read_run_map(None).ref is None
    unmapped = read_run_map(start("not a map"))
    assert not unmapped.recorded and unmapped.ref.src == "sim/world"


def test_a_hostile_map_is_typed_not_trusted():
    given = read_run_map(start({
        "roads": [1, {"id": 2, "from": "x", "to": [1]}, {"id": "R", "from": [0, 0], "to": [10 ** 400, 0]}],
        "junctions": [{"x": "?"}, {"id": "J", "x": 1, "y": 2.5, "control": 7, "box": True, "major": [3, "R"],
                                   "stop_lines": [{"approach": "west", "from": [0, 0], "to": [0, 1]}, "junk"]}],
        "monitors": "none", "network": {"lefthand": False}}))
    assert given.recorded and given.roads_listed == 2 and len(given.roads) == 2     # 1 is not an entry
    assert given.roads[0].ident is None and given.roads[0].label == "2" and given.roads[0].a is None
    assert given.roads[1].b == (None, 0.0)
    nowhere, j = given.junctions
    assert nowhere.x is None and nowhere.label is None
    assert (j.ident, j.x, j.y, j.control, j.control_label, j.box_whole, j.major) == ("J", 1.0, 2.5, None, "7", True, ("R",))
    assert len(j.stop_lines) == 1 and j.stop_lines_listed == 1 and j.stop_lines[0].approach == "west"
    assert given.monitors == () and given.lefthand is False
    with pytest.raises(AttributeError):
        j.x = 0.0                                                     # frozen


def test_lists_and_polylines_are_bounded(monkeypatch):
    monkeypatch.setattr(rm, "MAX_ENTRIES", 5)
    monkeypatch.setattr(rm, "MAX_POINTS", 3)
    given = read_run_map(start({"roads": [{"id": str(n)} for n in range(50)],
                                "lanes": [{"id": "l", "width_m": 3, "shape": [[n, 0] for n in range(10)]}]}))
    assert len(given.roads) == 5 and given.roads_listed == 50     # how many it gave, for a reader to say
    assert len(given.lanes[0].shape) == 3


def test_the_reasoner_and_the_picture_read_the_same_map():
    raw = {"roads": [{"id": "R", "from": [-50, 0], "to": [50, 0], "speed_limit_mph": 30}],
           "junctions": [{"id": "J", "x": 0, "y": 0, "control": "lights", "stop_line_m": 8},
                         {"id": 5, "x": 1e8, "y": 0}],
           "monitors": [{"id": "m", "junction": "J", "x": 0, "y": -10, "heading_deg": 90, "range_m": 40, "fov_deg": 120}]}
    reasoned, drawn = read_map(start(raw)), run_map(start(raw)["body"])
    assert [j.id for j in reasoned.junctions] == ["J"]                        # an id and a place within 10,000 km
    assert [j.id for j in drawn.junctions] == ["J", "5"]               # what has finite coordinates
    assert reasoned.junctions[0].monitors == ("monitor/m",) and reasoned.roads[0].limit_mph == 30.0


def test_an_integer_too_big_for_a_float_is_not_drawn_and_does_not_crash():
    """Before the one reader, explain's float() of 10**400 raised OverflowError out of a report."""
    drawn = run_map({"map": {"junctions": [{"id": "J", "x": 10 ** 400, "y": 0}],
                             "lanes": [{"id": "l", "width_m": 10 ** 400, "shape": [[0, 0], [1, 1]]}]}})
    assert drawn.junctions == () and drawn.lanes == ()
    assert not math.isnan(rm.number(1e308))


def test_a_reader_reads_only_the_parts_it_asks_for():
    raw = {"roads": [{"id": "R", "from": [0, 0], "to": [1, 0]}], "monitors": [{"id": "m"}],
           "lanes": [{"id": "l", "width_m": 3, "shape": [[0, 0], [1, 0]]}]}
    only = read_run_map(start(raw), frozenset({"monitors"}))
    assert only.recorded and only.roads == () and only.lanes == () and [m.ident for m in only.monitors] == ["m"]
    assert len(read_run_map(start(raw)).lanes) == 1
