"""The JSON report is the contract the typed report keeps (issue 38, "Types where values cross"):
explain/ builds the report as frozen values (picture_parts, timeline_parts, report_parts) and
their `to_json` is, to the byte, what the code that built it as dicts wrote
(data/report_before_typed.json, written by tests/helpers/report_shapes.py with main's explain/
at commit db5f254): lanes, stop lines, crossings and box, road users present and stale, a
monitor's cone, the distance to the Stop line and the speed of the road user forced, key for key
and in order."""
from __future__ import annotations

import json
from pathlib import Path

import pytest

from explain.picture_parts import Mover, Picture
from explain.report_parts import Report
from explain.timeline_parts import ActTimeline
from tests.helpers.report_shapes import NOW, crowded_lanes_run, report_json

BEFORE = json.loads((Path(__file__).parent / "data" / "report_before_typed.json").read_text(encoding="utf-8"))


@pytest.fixture(scope="module")
def now_json(tmp_path_factory):
    return report_json(tmp_path_factory.mktemp("report-json"))


@pytest.mark.parametrize("name", sorted(BEFORE))
def test_the_json_report_is_what_it_was_to_the_byte(now_json, name):
    assert json.dumps(now_json[name], indent=1) == json.dumps(BEFORE[name], indent=1)


def test_the_report_is_values_all_the_way_to_the_pictures(tmp_path):
    from explain import build_report
    from reasoner import Case
    from sim_replay.paper import RUN
    from store import Store
    with Store(tmp_path / "r.db") as store:
        store.append(crowded_lanes_run())
        report = build_report(Case(store), RUN, now=NOW)
    assert isinstance(report, Report)
    entry = report.incidents[1]
    assert isinstance(entry.scene, Picture) and isinstance(entry.timeline, ActTimeline)
    assert all(isinstance(m, Mover) for m in entry.scene.movers)
    assert {u.id: u.present for u in entry.scene.road_users} == {"pedestrian/p1": False, "pedestrian/p2": True}
    assert entry.timeline.to_line is not None and entry.timeline.to_line.approach == "west"
    with pytest.raises(AttributeError):
        entry.scene.vehicle = "someone else"        # type: ignore[misc]   # frozen: built once, then only read
