"""A red-light runner a camera vendor's simulator recorded as measurements only (entity.state at
2 Hz, the signal's changes, the map's stop lines; no sentence at all): what a user sees of its
history from the command line and in the report. The law: TSRGD 2016 Sch 14 Pt 1 para 5(3),
"vehicular traffic must not proceed beyond the stop line" while red shows (HC 176). The car
keeps 13.4 m/s from 100 m before the centre; the line is 12 m before it, so it crosses 88 / 13.4
= 6.567 s in, 0.567 s after red came at 6 s: punishable, margin 0.567 s after red."""
from __future__ import annotations

import json

import pytest

from reasoner import Case
from explain.report import build_report, render_report
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.foreign import Foreign, Motion, rate

LAG_S = 88 / 13.4 - 6.0


@pytest.fixture(scope="module")
def runner_db(tmp_path_factory):
    run = Foreign(run="measured-runner")
    run.spawn("9")
    run.lights("J1", "west", [(0, "green"), (3, "amber"), (6, "red")])
    run.drive("9", Motion(-100, 13.4), "west", rate(2, 0, 10))
    path = tmp_path_factory.mktemp("margins") / "runner.db"
    with Store(path) as store:
        assert not store.append(run.events).rejected
    return path


def test_incidents_json_gives_the_margin_and_the_line_shows_it(runner_db):
    (inc,) = json.loads(gaps("incidents", "--run", "measured-runner", "--json", db=runner_db).stdout)
    assert (inc["verdict"], inc["rule"], inc["recorded"]) == ("punishable", "HC 176", False)
    margin = inc["margin"]
    assert margin["quantity"] == "seconds after red the stop line was crossed" and margin["unit"] == "s"
    assert margin["value"] == pytest.approx(LAG_S, abs=0.01)
    assert {r["kind"] for r in margin["evidence"]} == {"entity.state", "signal.state"}
    assert 0 < margin["uncertainty"] < margin["value"], margin          # proved: beyond its uncertainty
    line = gaps("incidents", "--run", "measured-runner", db=runner_db).stdout
    assert f"crossed {margin['value']:g} s after red (± {margin['uncertainty']:g} s)" in line


def test_the_explanation_marks_measured_facts_and_gives_their_method(runner_db):
    text = gaps("explain", "--run", "measured-runner", "1", db=runner_db).stdout
    assert "9 crossed the stop line on red light (measured)" in text
    assert "linear interpolation between entity.state" in text
    assert "Margin of the act: seconds after red the stop line was crossed" in " ".join(text.split())
    doc = json.loads(gaps("explain", "--run", "measured-runner", "1", "--json", db=runner_db).stdout)
    measured = doc["measured"] if "measured" in doc else doc["explanation"]["measured"]
    assert any(f["fact"] == "9 crossed the stop line on red light" for f in measured["facts"])


def test_the_report_timeline_marks_the_crossing_on_the_light_bands(runner_db):
    with Store.open_read_only(runner_db) as store:
        report = build_report(Case(store), "measured-runner")
    tl = report.incidents[0].timeline
    crossing = next(m for m in tl.moments if m.what == "crossed the stop line")
    west = next(a for a in tl.window.signals if a.approach == "west")
    red = next(c for c in west.phases if c.colour == "red")
    assert (crossing.t - red.t) / 1e9 == pytest.approx(LAG_S, abs=0.01)
    html = render_report(report, "html")
    assert 'class="moment"' in html and "crossed the stop line" in html
