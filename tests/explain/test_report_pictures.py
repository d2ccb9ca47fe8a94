"""Report pictures a court can read (issue 39, "Pictures"): the timeline's labels never overlap,
are never cut at the picture's edge and no line strikes one through; every road user an incident
names is inside its scene picture; the caption speaks of the junction in view in the legend's
words; and the act stands on one time axis (speed, distance to the stop line, the light, and the
speed of the road user it would force).

Label boxes are read back from the drawn SVG (x, y, font size, text), sized with the font
metrics the renderer lays out with (labels.text_size, which the browser test checks against the
text Chromium draws), not taken from the layout's own record of them.
"""
from __future__ import annotations

import itertools
from dataclasses import replace
import re
from datetime import datetime, timezone
from html import unescape

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from explain.labels import Box, text_size
from explain.picture_parts import JunctionDrawn, SignalDrawn
from explain.report_parts import Report
from explain.timeline_parts import LinePoint, OtherParty, OtherSpeed, ToLine
from reasoner import Case
from explain.report import build_report, render_report
from explain.report_html import _scene_caption
from explain.scene_view import H, LEGEND_H, W
from explain.svg_scene import out_of_view, scene_svg, view_of
from explain.svg_timeline import timeline_svg
from reasoner.timelines import SpeedSample
from store import Store
from tests.helpers.foreign import Motion
from tests.helpers.scene_pictures import FIRE_ENGINE, QUICK, STOP_AND_GO, a_timeline, lanes_picture
from tests.reasoner.test_foreign_scenarios import _SET_OFF, stop_then_go_run

SECOND = 1_000_000_000
NOW = datetime(2026, 1, 2, tzinfo=timezone.utc)
FRAME = Box(0, 0, W, H - LEGEND_H)

def drawn_labels(svg: str) -> list[tuple[str, Box]]:
    """Every text the timeline writes as a label (the moments', the incident's, the speed at it),
    boxed from where it is drawn: its x (or its end, for text-anchor end), its baseline and size."""
    out = []
    for attrs, text in re.findall(r'<text ([^>]*class="(?:moment-label|incident-label|speed-value)"[^>]*)>([^<]*)<',
                                  svg):
        x, y = float(re.search(r'\bx="([-0-9.]+)"', attrs).group(1)), float(re.search(r'\by="([-0-9.]+)"',
                                                                                      attrs).group(1))
        sized = re.search(r'font-size="([0-9.]+)"', attrs)
        size = float(sized.group(1)) if sized else 11.0         # the svg element's font-size
        w, h = text_size(unescape(text), size)
        left = x - w if 'text-anchor="end"' in attrs else x - w / 2 if 'text-anchor="middle"' in attrs else x
        out.append((unescape(text), Box(left, y - size * 0.95, w, h)))
    return out


def drawn_lines(svg: str) -> list[tuple[float, float, float]]:
    """The moments' and the incident's lines: (x, top, bottom)."""
    return [(float(x1), min(float(y1), float(y2)), max(float(y1), float(y2))) for x1, y1, y2 in
            re.findall(r'<line class="(?:moment|incident-time)" x1="([-0-9.]+)" y1="([-0-9.]+)" x2="[-0-9.]+" '
                       r'y2="([-0-9.]+)"', svg)]


def view_box(svg: str) -> Box:
    w, h = re.search(r'viewBox="0 0 ([0-9.]+) ([0-9.]+)"', svg).groups()
    return Box(0, 0, float(w), float(h))


def assert_readable(svg: str, count: int) -> None:
    labels, lines = drawn_labels(svg), drawn_lines(svg)
    frame = view_box(svg)
    for text, box in labels:
        assert box.within(frame), f"{text!r} is cut at the picture's edge: {box} in {frame}"
    for (a, box_a), (b, box_b) in itertools.combinations(labels, 2):
        assert not box_a.intersects(box_b), f"{a!r} {box_a} and {b!r} {box_b} overlap"
    for text, box in labels:
        for x, top, bottom in lines:
            struck = box.x < x < box.x + box.w and top < box.y + box.h and box.y < bottom
            assert not struck, f"the line at x={x} strikes {text!r} {box} through"
    assert len(labels) == count and len(lines) == count - 1, (labels, lines)     # the speed's label has no line


# --- timeline labels --------------------------------------------------------------------------------

@pytest.mark.parametrize("moments", [FIRE_ENGINE, STOP_AND_GO, QUICK], ids=["fire-engine", "stop-and-go", "quick"])
def test_timeline_labels_never_overlap_are_never_cut_and_no_line_strikes_one(moments):
    svg = timeline_svg(a_timeline(moments), 90.0)
    assert_readable(svg, len(moments) + 2)          # the moments, "incident" and the speed at it
    assert "left the junction</text>" in svg        # written whole, not "left the junctio"


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.lists(st.tuples(st.sampled_from(["stood still before the line", "moved off", "crossed the stop line",
                                           "entered the junction", "left the junction"]),
                          st.floats(min_value=-20.0, max_value=5.0)), min_size=1, max_size=8))
def test_any_moments_get_readable_labels(moments):
    moments = sorted(moments, key=lambda m: m[1])
    assert_readable(timeline_svg(a_timeline(moments)), len(moments) + 2)


def test_same_timeline_same_layout():
    assert timeline_svg(a_timeline(STOP_AND_GO)) == timeline_svg(a_timeline(STOP_AND_GO))


# --- the act on one time axis -------------------------------------------------------------------------

def test_speed_distance_light_and_the_other_road_users_speed_share_one_time_axis():
    t = 100 * SECOND
    at = [t - 2 * SECOND, t, t + 2 * SECOND]
    tl = a_timeline(FIRE_ENGINE,
                    to_line=ToLine("j1", "south", "signal", tuple(LinePoint(s, m, "vehicle/109", i) for i, (s, m)
                                                                  in enumerate(zip(at, [4.0, 0.0, -6.5])))),
                    other=OtherParty("c2", "car", "would force to change speed or course", "109",
                                     tuple(OtherSpeed(s, v, "vehicle/c2", i)
                                           for i, (s, v) in enumerate(zip(at, [13.4, 13.4, 4.0])))))
    own = tuple(SpeedSample(s, v, i) for i, (s, v) in enumerate(zip(at, [3.0, 2.0, 4.0])))
    tl = replace(tl, window=replace(tl.window, speed=own))
    svg = timeline_svg(tl, 90.0)
    own = [float(x) for x in re.findall(r'<circle cx="([0-9.]+)" cy="[0-9.]+" r="3"', svg)]
    line = [float(x) for x in re.findall(r'<circle class="to-line-point" cx="([0-9.]+)"', svg)]
    other = [float(x) for x in re.findall(r'<circle class="other-point" cx="([0-9.]+)"', svg)]
    assert len(own) == len(line) == len(other) == 3
    assert own == pytest.approx(line) and own == pytest.approx(other)      # one x for one moment in every panel
    incident_x = float(re.search(r'<line class="incident-time" x1="([0-9.]+)"', svg).group(1))
    assert own[1] == pytest.approx(incident_x)
    amber = re.search(r'<rect class="signal-band" x="([0-9.]+)"[^>]*><title>signal j1 west: amber', svg)
    assert float(amber.group(1)) == pytest.approx(incident_x + (own[2] - own[1]) * 1.5)     # +3 s on the same scale
    assert "speed of car c2, whom 109 would force to change speed or course" in svg
    assert "distance to the stop line" in svg
    # the distance is read off one scale: 4 m before the line above its zero, 6.5 m past it below
    ys = [float(y) for y in re.findall(r'<circle class="to-line-point" cx="[0-9.]+" cy="([0-9.]+)"', svg)]
    zero = float(re.search(r'<line x1="\d+" y1="([0-9.]+)"[^>]*stroke="#a40000"', svg).group(1))
    assert ys[0] < zero < ys[2] and ys[1] == pytest.approx(zero)
    assert (zero - ys[0]) / (ys[2] - zero) == pytest.approx(4.0 / 6.5, abs=0.005)      # drawn to 0.01 px


# --- a forcing, from the store to the report ----------------------------------------------------------

@pytest.fixture(scope="module")
def forcing(tmp_path_factory) -> Report:
    """Issue 35's control scenario (tests/reasoner/test_attribution.py): 7 stops at its Stop line
    and pulls out; c2, on the main road, 30 m short of the centre brakes at 5 m/s² to a stop.
    The law (TSRGD 2016 Sch 9 Pt 7 para 1, HC 171): 7 caused c2 to change speed to avoid an
    accident, punishable. At the incident c2 is some 66 m up the main road."""
    begins = _SET_OFF + 3.43
    c2 = Motion(-30.0 - 13.4 * begins, 13.4, [(begins, 0.0), (13.4 / 5.0, -5.0)])
    run = stop_then_go_run(("c2", c2, "north"))
    run.end((max(e["t"] for e in run.events) - run.events[0]["t"]) / 1e9 + 1)
    with Store(tmp_path_factory.mktemp("forcing") / "forcing.db") as store:
        assert not store.append(run.events).rejected
        return build_report(Case(store), run.run, now=NOW)


def test_the_forced_road_user_is_inside_its_incidents_picture(forcing):
    (entry,) = [e for e in forcing.incidents if e.row.vehicle == "7"]
    pic = entry.scene
    c2 = next(v for v in pic.vehicles if v.id == "c2")
    assert c2.present and c2.y > 40          # far up the main road: outside a view of the junction alone
    assert out_of_view(pic) == [] and "outside the picture" not in _scene_caption(pic)
    assert {"7", "c2"} <= set(pic.named)
    view = view_of(pic)
    for user in pic.named:
        u = next(v for v in pic.movers if str(v.id) == user)
        assert FRAME.holds(*view(u.x, u.y)), f"{user} is named by the incident but outside its picture"
    assert ">c2 car 30 mph</text>" in scene_svg(pic, 1)


def test_the_forcing_timeline_carries_the_other_speed_and_the_distance_to_the_line(forcing):
    (entry,) = [e for e in forcing.incidents if e.row.vehicle == "7"]
    tl = entry.timeline
    other = tl.other
    assert (other.user, other.how) == ("c2", "would force to change speed or course")
    speeds = [p.speed_mps for p in other.speed]
    assert max(speeds) == pytest.approx(13.4, abs=0.01) and min(speeds) < 5     # the braking is on the axis
    line = tl.to_line
    assert (line.approach, line.kind) == ("west", "stop_sign")
    metres = [p.m for p in line.points]
    assert min(metres) < 0 < max(metres)                    # before the line, then past it
    stood = [p.m for p in line.points if abs(p.t - tl.window.t) < 5 * SECOND]
    assert any(abs(m) < 1.0 for m in stood)                 # it stopped at the line (12.5 m out, 0.5 m short)
    svg = timeline_svg(tl, tl.heading_deg)
    assert "whom 7 would force to change speed or course" in svg and "distance to the Stop line" in svg
    text = render_report(forcing, "md")             # the Markdown report's table carries the same rows
    assert re.search(r"\| speed of c2 30\.0 mph .*whom 7 would force to change speed or course", text)
    assert re.search(r"\| [0-9.]+ m before the line \|", text) and re.search(r"\| [0-9.]+ m past the line \|", text)


# --- captions -------------------------------------------------------------------------------------------

def test_the_caption_names_the_signals_of_the_junction_in_view_in_the_legends_words():
    pic = lanes_picture()
    pic = replace(pic, signals=(replace(pic.signals[0], colour="red_amber"), *pic.signals[1:],       # west
                                SignalDrawn("j9", "west", "green", 0)),
                  junctions=pic.junctions + (JunctionDrawn("j9", 500.0, 0.0, "lights"),))
    caption = _scene_caption(pic)
    assert "red_amber" not in caption and "j9" not in caption
    assert "Signals at junction j1: west red and amber; east red; north green; south amber." in caption
    svg = scene_svg(pic, 1)
    assert ">red and amber</text>" in svg and "red+amber" not in svg        # the legend's words are the caption's
    assert "signal j1 west: red and amber" in svg


def test_the_report_caption_of_a_stop_junction_lists_no_other_junctions_signals(forcing):
    html = render_report(forcing, "html")
    assert "No signal reported at junction J1." in html and "Signals:" not in html


def test_a_busy_maps_caption_names_the_nearest_outside_the_picture_and_counts_the_rest():
    pic = lanes_picture()
    base = pic.vehicles[1]
    pic = replace(pic, vehicles=pic.vehicles + tuple(replace(base, id=f"far{i}", x=200.0 + 10 * i, y=1.75)
                                                     for i in range(14)))
    caption = _scene_caption(pic)
    assert ("Present but outside the picture, nearest first: far0, far1, far2, far3, far4, far5, far6, far7, "
            "far8, far9 and 4 more elsewhere on the map.") in caption


def test_moments_too_crowded_for_their_words_are_numbered_with_a_key():
    """Four stops 6 s apart (a queue): no row holds "stood still before the line" four times clear
    of each other's lines, whichever side each takes. Each moment is numbered beside its line and
    its words written under the time axis, none struck (hypothesis found it)."""
    moments = [("stood still before the line", float(t)) for t in (-18, -12, -6, 0)]
    svg = timeline_svg(a_timeline(moments))
    assert_readable(svg, len(moments) + 2)
    key = " · ".join(re.findall(r'<text class="moment-key"[^>]*>([^<]*)<', svg))
    assert key.startswith("1 stood still before the line (") and key.count("stood still before the line") == 4
    assert sorted(t for t, _ in drawn_labels(svg) if t.isdigit()) == ["1", "2", "3", "4"]
