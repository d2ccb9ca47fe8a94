"""What a printed report must say and show (issue 11): the tool's version and the store file's
sha256 on it, A4 pages numbered "page N of M", speeds in mph, only the road users present at the
incident's moment drawn, and labels that do not cover one another. The PDF itself is checked in
test_report_browser.py (it needs Chromium)."""
from __future__ import annotations

import hashlib
import itertools
import json
import re
from dataclasses import replace
from datetime import datetime, timezone
from importlib.metadata import version
from pathlib import Path

import pytest

from explain.labels import Box, Placer, text_size
from explain.presence import FRESH_NS, presence_at
from reasoner import Case
from explain.report import build_report, render_report
from explain.report_html import css_string
from explain.report_parts import Report
from explain.svg_scene import scene_svg
from explain.svg_timeline import timeline_svg
from explain.timeline_parts import ActTimeline
from explain.units import mph
from tests.helpers.scene_pictures import crowded_picture
from sim_replay.paper import RUN, paper_run
from reasoner.timelines import SpeedSample, Timeline
from store import EventRef, Store

NOW = datetime(2026, 1, 2, 3, 4, 5, tzinfo=timezone.utc)
SECOND = 1_000_000_000
T0 = 1732176000000000000            # the paper run's start; its second incident is at +40 s
INCIDENT_2 = T0 + 40 * SECOND


def closed_store(path: Path, events: list[dict]) -> Path:
    with Store(path) as store:
        report = store.append(events)
        assert not report.rejected, report.rejected
    return path


def built(path: Path) -> Report:
    with Store.open_read_only(path) as store:  # as `gaps report` reads it
        return build_report(Case(store), RUN, now=NOW)


# --- the tool's version and the store file's sha256 -----------------------------------------------

@pytest.fixture(scope="module")
def demo(tmp_path_factory) -> tuple[Path, str, int, Report]:
    """The demo run in a closed store file, its sha256 as hashlib reads it and its size before
    the report, and its report."""
    path = closed_store(tmp_path_factory.mktemp("print") / "demo.db", paper_run())
    data = path.read_bytes()
    return path, hashlib.sha256(data).hexdigest(), len(data), built(path)


def test_the_report_names_the_tool_version_and_the_store_file_by_sha256(demo):
    path, sha, size, report = demo
    p = report.provenance
    assert p.tool == "mind-the-gaps" and p.version == version("mind-the-gaps")
    assert (p.store_path, p.store_sha256, p.store_bytes, p.wal_pending) == (str(path.resolve()), sha, size, False)


def test_html_markdown_and_json_carry_version_and_sha256(demo):
    path, sha, _, report = demo
    page = render_report(report, "html")
    table = re.search(r'<table class="provenance">(.*?)</table>', page, re.S).group(1)
    assert f"<td>mind-the-gaps {version('mind-the-gaps')}</td>" in table
    assert f'<td class="sha">{sha}</td>' in table and f"<td>{path.resolve()}</td>" in table
    # every printed page: in the margins, as CSS strings
    assert f'@bottom-left{{content:"store " "demo.db" " sha256 " "{sha}"' in page
    assert f'@top-right{{content:"mind-the-gaps " "{version("mind-the-gaps")}"' in page
    text = render_report(report, "md")
    assert f"- store sha256: {sha}\n" in text and f"- tool: mind-the-gaps {version('mind-the-gaps')}\n" in text
    data = json.loads(render_report(report, "json"))
    assert data["provenance"]["store"]["sha256"] == sha


def test_pending_writes_in_the_log_are_said_not_hidden(tmp_path):
    with Store(tmp_path / "open.db") as store:
        store.append(paper_run())
        report = build_report(Case(store), RUN, now=NOW)
    assert report.provenance.wal_pending is True
    assert "held writes not yet in the file" in render_report(report, "html")
    assert "its -wal file held writes not yet in the file" in render_report(report, "md")


def test_a4_pages_numbered_page_n_of_m(demo):
    page = render_report(demo[3], "html")
    assert "@page{size:A4;" in page
    assert '@bottom-right{content:"page " counter(page) " of " counter(pages)' in page
    assert "article.incident{break-before:page" in page and "tr,li,p{break-inside:avoid}" in page


def test_css_strings_cannot_end_the_string_the_rule_or_the_style():
    hostile = 'run"; } body{display:none} </style><script>x</script>\\\n'
    text = css_string(hostile)
    inner = text[1:-1]
    assert text[0] == text[-1] == '"' and not set(inner) & set('"<>{};\\\n') - {"\\"}
    assert "\\000022" in inner and "\\00003c" in inner
    # unescaping gives back the text
    assert re.sub(r"\\([0-9a-f]{6})", lambda m: chr(int(m.group(1), 16)), inner) == hostile


# --- speeds in mph --------------------------------------------------------------------------------

def test_timeline_speaks_mph_on_the_axis_and_at_the_points():
    thirty_mph = 13.4112                     # m/s, exactly 30 mph
    assert mph(thirty_mph) == pytest.approx(30.0)
    tl = ActTimeline(Timeline(20 * SECOND, 0, 25 * SECOND, "7", None, (SpeedSample(19 * SECOND, thirty_mph, 3),),
                              (), ()))
    svg = timeline_svg(tl)
    assert "speed (mph)" in svg and "m/s)</text>" not in svg
    # the axis runs to 40 mph in steps of 10, and the point sits at 30 of them
    ticks = re.findall(r'text-anchor="end">([0-9.]+)</text>', svg)
    assert ticks == ["0", "10", "20", "30", "40"]
    tick_30 = float(re.search(r'<line x1="\d+" y1="([0-9.]+)"[^>]*/><text[^>]*>30</text>', svg).group(1))
    point = float(re.search(r'<circle cx="[0-9.]+" cy="([0-9.]+)" r="3"', svg).group(1))
    assert point == pytest.approx(tick_30)
    assert '<text class="speed-value"' in svg and ">30.0 mph</text>" in svg
    assert "30.0 mph (13.4112 m/s, vehicle/7 #3)" in svg


def test_demo_timeline_and_scene_give_9_mps_as_20_1_mph(demo):
    first = demo[3].incidents[0]
    svg = timeline_svg(first.timeline, 0.0)
    assert ">20.1 mph</text>" in svg and "speed (mph)" in svg
    assert "speed 20.1 mph (9 m/s)" in scene_svg(first.scene, 1)


# --- only road users present at the moment --------------------------------------------------------

def extra(src: str, kind: str, seq: int, t: int, body: dict) -> dict:
    return {"v": 1, "run": RUN, "src": src, "seq": seq, "t": t, "kind": kind, "body": body}


def crowded_run() -> list[dict]:
    """The demo run with others around the ambulance's incident (at +40 s): a car reported 0.8 s
    before (there), a car 2.5 s before (gone quiet), a car that despawned just before, a
    pedestrian last seen 30 s before and one 0.1 s before."""
    at = INCIDENT_2
    events = paper_run() + [
        extra("vehicle/500", "entity.spawn", 0, T0, {"type": "car"}),
        extra("vehicle/500", "entity.state", 1, at - 800_000_000, {"x": 3.0, "y": -1.0, "heading_deg": 90.0,
                                                                   "speed_mps": 2.0}),
        extra("vehicle/501", "entity.spawn", 0, T0, {"type": "car"}),
        extra("vehicle/501", "entity.state", 1, at - 2_500_000_000, {"x": -4.0, "y": 3.0, "heading_deg": 0.0,
                                                                     "speed_mps": 0.0}),
        extra("vehicle/502", "entity.spawn", 0, T0, {"type": "bus"}),
        extra("vehicle/502", "entity.state", 1, at - 400_000_000, {"x": 5.0, "y": 5.0, "heading_deg": 0.0,
                                                                   "speed_mps": 1.0}),
        extra("vehicle/502", "entity.despawn", 2, at - 200_000_000, {"reason": "left the map"}),
        extra("pedestrian/p1", "entity.spawn", 0, T0, {"type": "pedestrian"}),
        extra("pedestrian/p1", "entity.state", 1, T0 + 10 * SECOND, {"x": -1.0, "y": 1.0, "speed_mps": 1.2}),
        extra("pedestrian/p2", "entity.spawn", 0, T0, {"type": "pedestrian"}),
        extra("pedestrian/p2", "entity.state", 1, at - 100_000_000, {"x": 6.0, "y": -6.0, "speed_mps": 1.2}),
    ]
    return sorted(events, key=lambda e: e["t"])


def test_a_vehicle_last_seen_30_s_before_is_not_drawn_under_the_ambulance(demo):
    second = demo[3].incidents[1]
    pic = second.scene
    old = next(v for v in pic.vehicles if v.id == "173")
    assert (old.x, old.y) == (-2.0, 0.0) and old.present is False and old.age_s == 30.0
    svg = scene_svg(pic, 2)
    assert svg.count('<g class="vehicle') == 1 and 'class="vehicle incident"' in svg
    assert "vehicle 173" not in svg and ">173 car<" not in svg
    assert "173 (30 s before)" in render_report(demo[3], "html")


def test_only_what_is_there_at_the_moment_is_drawn(tmp_path):
    report = built(closed_store(tmp_path / "crowd.db", crowded_run()))
    pic = report.incidents[1].scene
    present = {v.id: v.present for v in pic.movers}
    assert present == {"173": False, "253": True, "500": True, "501": False, "pedestrian/p1": False,
                       "pedestrian/p2": True}                  # 502 despawned: not in the scene at all
    svg = scene_svg(pic, 2)
    drawn_vehicles = re.findall(r"<title>vehicle (\w+) \(", svg)
    assert sorted(drawn_vehicles) == ["253", "500"]
    assert svg.count('class="road-user"') == 1 and ">pedestrian/p2 3 mph<" in svg and "pedestrian/p1" not in svg
    caption = render_report(report, "html")
    assert "173 (30 s before), 501 (2.5 s before), pedestrian/p1 (30 s before)" in caption


def test_freshness_window():
    t = 100 * SECOND
    def ref(at: int) -> EventRef:
        return EventRef(RUN, "vehicle/7", 1, at, "entity.state")
    assert presence_at(ref(t), t) == (True, 0.0)
    assert presence_at(ref(t - FRESH_NS), t)[0] is True
    assert presence_at(ref(t - FRESH_NS - 1), t)[0] is False
    assert presence_at(None, t) == (False, None)
    assert presence_at(ref(t + 1), t)[0] is False              # reported after the moment: not where it was then


def test_the_incident_vehicle_not_seen_lately_is_not_drawn_and_it_says_so(demo):
    pic = demo[3].incidents[1].scene
    pic = replace(pic, vehicles=tuple(replace(v, present=False, age_s=12.0) if v.incident else v
                                      for v in pic.vehicles))
    svg = scene_svg(pic, 2)
    assert 'class="vehicle incident"' not in svg
    assert "vehicle 253&#x27;s last recorded position is 12 s old: not drawn" in svg


# --- labels that do not collide -------------------------------------------------------------------

def label_boxes(svg: str) -> list[tuple[str, Box]]:
    found = re.findall(r'<text class="label" x="([-0-9.]+)" y="([-0-9.]+)"[^>]*data-box="([^"]+)"[^>]*>([^<]*)<',
                       svg)
    out = []
    for x, y, box, text in found:
        b = Box(*map(float, box.split()))
        assert (float(x), float(y)) == pytest.approx((b.x, b.y + 11 * 0.95), abs=0.02)     # written in its box
        out.append((text, b))
    return out


def test_labels_of_vehicles_close_together_do_not_overlap():
    pic = crowded_picture()
    far = replace(pic.vehicles[1], id="far", x=900.0, y=0.0)     # outside the frame: clipped, no label
    pic = replace(pic, vehicles=pic.vehicles + (far,))
    svg = scene_svg(pic, 1)
    labels = label_boxes(svg)
    texts = [t for t, _ in labels]
    assert sorted(texts) == sorted(["1 car 11 mph", "22 car 11 mph", "333 car 11 mph", "4444 car 11 mph",
                                    "55 car 11 mph", "ambulance-6 car 11 mph", "7 car 11 mph", "pedestrian/p",
                                    "monitor/m1", "junction j1"])      # 5 m/s is 11.2 mph
    for (a, box_a), (b, box_b) in itertools.combinations(labels, 2):
        assert not box_a.intersects(box_b), (a, box_a, b, box_b)
    frame = Box(0, 0, 640, 440 - 44)
    assert all(box.within(frame) for _, box in labels)
    assert texts[0] == "1 car 11 mph"          # the incident's vehicle placed first, nearest its marker
    assert scene_svg(pic, 1) == svg          # the same picture, the same layout


def test_the_placer_keeps_every_label_clear_even_at_one_spot():
    placer = Placer(Box(0, 0, 400, 300), obstacles=[Box(195, 145, 10, 10)])
    placed = [placer.place(f"label {i}", 200, 150) for i in range(24)]
    for a, b in itertools.combinations(placed, 2):
        assert not a.box.intersects(b.box), (a, b)
    assert placed[0].box.x > 200 and placed[0].box.y > 150 and not placed[0].leader    # first: right-below
    assert any(p.leader for p in placed)                          # far ones are joined to their anchor
    w, h = text_size("label 0", 11)
    assert (placed[0].box.w, placed[0].box.h) == (w, h)
