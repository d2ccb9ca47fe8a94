"""`gaps report` without a browser: the demo run's report in HTML, Markdown and JSON holds what it
must (a summary row, a scene and a timeline per incident, the rulebooks' sha256s, the chain),
references nothing outside itself, and shows hostile recorded strings as text."""
from __future__ import annotations

import copy
import json
import re
from datetime import datetime, timezone
from html.parser import HTMLParser
from pathlib import Path

import pytest

from reasoner import Case
from explain.report import ReportError, build_report, format_for, render_report
from explain.picture_parts import JunctionDrawn, MonitorDrawn, Mover, Picture, RoadDrawn, SignalDrawn
from explain.report_data import facing_approach, number
from explain.report_parts import Report
from explain.svg_scene import scene_svg
from explain.svg_timeline import timeline_svg
from explain.timeline_parts import ActTimeline
from reasoner.timelines import Timeline
from sim_replay.paper import RUN, paper_run
from reasoner import NoSuchIncident
from store import NoSuchRun, Store

VOID = {"area", "base", "br", "col", "embed", "hr", "img", "input", "link", "meta", "source", "track", "wbr"}
# SVG elements the renderers write self-closed
SELF_CLOSED = {"rect", "circle", "line", "polyline", "polygon", "path"}
NOW = datetime(2026, 1, 2, 3, 4, 5, tzinfo=timezone.utc)
HOSTILE = '<script>alert("x")</script> & "quoted" \u202e'


class Outline(HTMLParser):
    """Checks tags nest and close, and collects each element's tag and attributes."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[str] = []
        self.elements: list[tuple[str, dict]] = []
        self.problems: list[str] = []
        self.text: list[str] = []

    def handle_starttag(self, tag: str, attrs: list) -> None:
        self.elements.append((tag, dict(attrs)))
        if tag not in VOID:
            self.stack.append(tag)

    def handle_startendtag(self, tag: str, attrs: list) -> None:
        self.elements.append((tag, dict(attrs)))

    def handle_endtag(self, tag: str) -> None:
        if tag in VOID:
            return
        if not self.stack or self.stack[-1] != tag:
            self.problems.append(f"</{tag}> closes {self.stack[-1:] or 'nothing'} at {self.getpos()}")
            return
        self.stack.pop()

    def handle_data(self, data: str) -> None:
        self.text.append(data)


def outline(page: str) -> Outline:
    parser = Outline()
    parser.feed(page)
    parser.close()
    return parser


def with_class(parsed: Outline, tag: str, cls: str) -> list[dict]:
    return [a for t, a in parsed.elements if t == tag and cls in (a.get("class") or "").split()]


@pytest.fixture(scope="module")
def demo_report(tmp_path_factory) -> Report:
    db = tmp_path_factory.mktemp("report") / "demo.db"
    with Store(db) as store:
        store.append(paper_run())
        return build_report(Case(store), RUN, now=NOW)


def hostile_events() -> list[dict]:
    """The demo run with producer-written strings that try to be markup: a fact of the vehicle, a
    road, junction and monitor id on the map, a signal approach."""
    events = copy.deepcopy(paper_run())
    for ev in events:
        if ev["kind"] == "run.start":
            ev["body"]["map"]["roads"].append({"id": HOSTILE, "from": [0, 0], "to": [50, 50]})
            ev["body"]["map"]["junctions"].append({"id": HOSTILE, "x": 30.0, "y": -20.0, "control": "none"})
            ev["body"]["map"]["monitors"].append({"id": HOSTILE, "junction": "j1", "x": 10.0, "y": -10.0,
                                                  "heading_deg": 90.0, "range_m": 20.0, "fov_deg": 60.0})
        if ev["kind"] == "vehicle.perception" and ev["src"] == "vehicle/173":
            ev["body"]["facts"].append(f"173 is near {HOSTILE}")
        if ev["kind"] == "signal.state" and ev["seq"] == 0:
            ev["body"]["approach"] = HOSTILE
    return events


# --- the demo report ------------------------------------------------------------------------------

def test_html_is_well_formed_and_has_a_scene_and_a_timeline_per_incident(demo_report):
    page = render_report(demo_report, "html")
    parsed = outline(page)
    assert parsed.problems == [] and parsed.stack == []
    n = len(demo_report.incidents)
    assert n == 2 and demo_report.incidents_in_run == 2
    assert len(with_class(parsed, "svg", "gaps-scene")) == n
    assert len(with_class(parsed, "svg", "gaps-timeline")) == n
    assert len(with_class(parsed, "tr", "incident-row")) == n
    assert len(with_class(parsed, "section", "gaps-explanation")) == n
    # the clip paths of the pictures do not clash
    ids = [a["id"] for _, a in parsed.elements if "id" in a]
    assert len(ids) == len(set(ids))


def test_html_summary_rows_say_what_the_verdicts_are(demo_report):
    page = render_report(demo_report, "html")
    rows = re.findall(r'<tr class="incident-row">(.*?)</tr>', page)
    cells = [re.findall(r"<td>(.*?)</td>", r) for r in rows]
    assert [c[3] for c in cells] == ["173", "253"]
    assert "punishable" in cells[0][6] and "mitigated" in cells[1][6]
    assert cells[0][7] == "£100, 3 points" and cells[1][7] == "none"
    assert [c[8] for c in cells] == ["driver", "none"]
    assert [c[9] for c in cells] == ["1", "0"]


def test_html_names_every_rulebook_by_sha256_and_shows_the_chain(demo_report):
    page = render_report(demo_report, "html")
    shas = {b.book.sha256 for e in demo_report.incidents for b in e.rulebooks}
    assert len(shas) == 3          # paper.le recorded; penalties and liability current
    for sha in shas:
        assert re.fullmatch(r"[0-9a-f]{64}", sha) and sha in page
    sources = {b.name: b.source for b in demo_report.rulebooks}
    assert sources == {"paper.le": "recorded", "penalties.le": "current", "liability.le": "current"}
    assert "Verified." in page and "its 20 events are as recorded" in page
    assert demo_report.chain.last.head in page


def test_html_is_self_contained(demo_report):
    page = render_report(demo_report, "html")
    parsed = outline(page)
    assert not [t for t, _ in parsed.elements if t in ("script", "link", "img", "iframe", "object", "embed")]
    for tag, attrs in parsed.elements:
        for name, value in attrs.items():
            if name in ("src", "href", "xlink:href"):
                assert value.startswith("#"), (tag, name, value)
    assert "@import" not in page and "@font-face" not in page
    assert set(re.findall(r"url\((.)", page)) <= {"#"}
    assert "@media print" in page


def test_scene_draws_the_map_the_signal_the_vehicle_and_the_monitor(demo_report):
    first = demo_report.incidents[0]
    pic = first.scene
    assert [r.id for r in pic.roads] == ["r1", "r2"] and [j.id for j in pic.junctions] == ["j1"]
    assert [(s.approach, s.colour) for s in pic.signals] == [("west", "red")]
    me = [v for v in pic.vehicles if v.incident]
    assert [(v.id, v.x, v.y, v.heading_deg) for v in me] == [("173", -2.0, 0.0, 0.0)]
    svg = scene_svg(pic, 1)
    assert svg.count('class="road"') == 2 and svg.count('class="fov"') == 1
    assert svg.count('class="vehicle incident"') == 1
    assert '<g class="signal"><title>signal j1 west: red</title>' in svg and "#d62020" in svg
    # the ambulance has spawned but reported no position yet: not drawn, said in the caption
    assert [v.id for v in pic.vehicles if v.x is None] == ["253"]
    assert "Not drawn (no position recorded): 253" in render_report(demo_report, "html")


def test_timeline_holds_the_speed_and_the_signal_changes_around_the_incident(demo_report):
    tl = demo_report.incidents[0].timeline
    second = 1_000_000_000
    assert tl.window.t_to - tl.window.t == 5 * second and tl.window.t - tl.window.t_from == 20 * second
    assert [(p.t - tl.window.t, p.speed_mps) for p in tl.window.speed] == [(-second, 9.0), (0, 9.0)]
    assert [(p.monitor, p.speed_mps) for p in tl.window.observed_speed] == [("monitor/m1", 9.0)]
    (west,) = tl.window.signals
    assert west.approach == "west"
    assert [(c.t - tl.window.t, c.colour) for c in west.phases] == [(-6 * second, "amber"), (-3 * second, "red")]
    # the ambulance 30 s later: the window opens with the light as it was then (red, from the first cycle)
    later = demo_report.incidents[1].timeline
    (west,) = later.window.signals
    assert [c.colour for c in west.phases] == ["red", "amber", "red"]
    assert west.phases[0].t < later.window.t_from
    svg = timeline_svg(tl, 0.0)
    assert svg.count('class="signal-band"') == 2 and "▶ j1 west" in svg and 'class="speed"' in svg


def test_markdown_has_the_same_sections(demo_report):
    text = render_report(demo_report, "md")
    assert text.startswith("# Incident report: run paper-junctions\n")
    assert "| 1 | monitor/m1:1 | 08:00:10.000 UTC | 173 | enter the junction | HC 176 | punishable |" in text
    assert "## Incident 2: vehicle 253, enter the junction, mitigated" in text
    assert "- vehicle 173 (car) (this incident): at (-2, 0) m, heading 0°, speed 20.1 mph (9 m/s)" in text
    assert "| -3 s | signal j1 west | red |" in text
    # the explanation's headings sit under the incident's
    assert "\n### Vehicle 173 committed a punishable violation" in text and "\n#### 7. Evidence" in text
    for b in demo_report.rulebooks:
        assert b.sha256 in text


def test_json_carries_the_explanations_and_the_scene_data(demo_report):
    data = json.loads(render_report(demo_report, "json"))
    assert data["run"] == RUN and data["generated"] == "2026-01-02T03:04:05Z"
    verdicts = [(e["row"]["vehicle"], e["explanation"]["incident"]["verdict"]) for e in data["incidents"]]
    assert verdicts == [("173", "punishable"), ("253", "mitigated")]
    assert data["incidents"][0]["scene"]["monitors"][0]["fov_deg"] == 90.0
    assert data["incidents"][0]["explanation"]["evidence"]["chain"]["verified"] is True


def test_one_incident_by_id_or_number(tmp_path):
    with Store(tmp_path / "d.db") as store:
        store.append(paper_run())
        by_id = build_report(Case(store), RUN, incident="monitor/m1:3", now=NOW)
        by_number = build_report(Case(store), RUN, incident="2", now=NOW)
        with pytest.raises(NoSuchIncident, match="no incident '9'.*1=monitor/m1:1, 2=monitor/m1:3"):
            build_report(Case(store), RUN, incident="9")      # found as reasoner.Case finds it, for every command
        with pytest.raises(NoSuchRun, match="no run 'other'; runs: paper-junctions"):
            build_report(Case(store), "other")
    assert [e.number for e in by_id.incidents] == [2] and by_id.incidents_in_run == 2
    assert render_report(by_id, "json") == render_report(by_number, "json")
    assert "One incident of the 2 the run holds." in render_report(by_id, "html")


# --- hostile strings ------------------------------------------------------------------------------

def test_hostile_recorded_strings_are_shown_not_obeyed(tmp_path):
    with Store(tmp_path / "h.db") as store:
        report = store.append(hostile_events())
        assert not report.rejected, report.rejected
        built = build_report(Case(store), RUN, now=NOW)
    page = render_report(built, "html")
    parsed = outline(page)
    assert parsed.problems == [] and parsed.stack == []
    assert "<script" not in page and "\u202e" not in page
    assert not [t for t, _ in parsed.elements if t == "script"]
    assert "&lt;script&gt;alert(&quot;x&quot;)&lt;/script&gt; &amp; &quot;quoted&quot; \\u202e" in page
    # it reached the parts that draw it: the explanation (an unknown fact), the map and the signal band
    shown = "".join(parsed.text)
    assert shown.count('<script>alert("x")</script>') >= 3
    markdown = render_report(built, "md")
    assert "<script" not in markdown and "&lt;script&gt;" in markdown
    data = json.loads(render_report(built, "json"))      # JSON keeps it as recorded, as data
    assert any(r["id"] == HOSTILE for r in data["incidents"][0]["scene"]["roads"])


def test_pictures_leave_out_what_is_not_a_number():
    pic = Picture(0, "+0s", "1", roads=(RoadDrawn("r", (0.0, 0.0), (10.0, 0.0)),),
                  junctions=(JunctionDrawn("nowhere", 0.0, 0.0, "lights"),),
                  signals=(SignalDrawn("nowhere", "north", "red; fill:url(http://x)", 0),),
                  monitors=(MonitorDrawn("monitor/m", None, None, 1.0, None, None, None),),
                  vehicles=(Mover("1", None, None, None, incident=True),))
    svg = scene_svg(pic)
    assert not re.findall(r'="[^"]*(?:nan|inf)', svg, re.I)
    attributes = [v for _, a in outline(svg).elements for k, v in a.items() if k != "xmlns"]
    assert not [v for v in attributes if "url(http" in (v or "")]     # the colour went into a title, as text
    assert re.search(r'<g class="signal"><title>[^<]*</title><rect [^>]*/><circle [^>]*fill="#ffffff"', svg)
    assert "vehicle 1 has no recorded position at this time" in svg
    assert number(float("nan")) is None and number(True) is None and number("3") is None and number(2) == 2.0
    empty = timeline_svg(ActTimeline(Timeline(10, 0, 15, "1", None, (), (), ())))
    assert "no speed recorded for vehicle 1" in empty and "no signal reported at this junction" in empty


def test_facing_approach_reads_compass_names():
    assert facing_approach(0.0, ["west", "north"]) == "west"        # heading east, from the west
    assert facing_approach(90.0, ["west", "south", "east"]) == "south"
    assert facing_approach(0.0, ["a", "b"]) is None and facing_approach(None, ["west"]) is None


def test_format_from_the_suffix():
    assert [format_for(Path(p)) for p in ("r.html", "R.HTM", "r.md", "r.json")] == ["html", "html", "md", "json"]
    with pytest.raises(ReportError, match=r"\.html, \.md or \.json"):
        format_for(Path("r.pdf"))
