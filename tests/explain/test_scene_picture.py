"""The scene picture (issue 13, "Seen, not just stored"): the map's lanes drawn from their
polylines at their widths, stop lines and the yellow box, each approach's signal colour at its
stop line, only the road users present at the moment, speeds in mph, labels that never overlap
(also over random crowded scenes), and `gaps scene --svg` writing it."""
from __future__ import annotations

from dataclasses import replace
import itertools
import math
import re
import xml.etree.ElementTree as ET

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from explain.labels import Box
from explain.picture_parts import Mover, Picture
from explain.report_data import run_map
from explain.scene_view import H, LEGEND_H, W
from explain.svg import SIGNAL_FILL
from explain.svg_scene import LAMP_OUT_M, out_of_view, scene_svg, view_of
from sim_replay.paper import RUN, T0, paper_run
from store import Store
from tests.helpers.cli import gaps
from tests.helpers.scene_pictures import SIGNAL_COLOURS, crowded_picture, lanes_picture, sumo_like_map

SECOND = 1_000_000_000
FRAME = Box(0, 0, W, H - LEGEND_H)


def label_boxes(svg: str) -> list[tuple[str, Box]]:
    return [(text, Box(*map(float, box.split())))
            for box, text in re.findall(r'<text class="label"[^>]*data-box="([^"]+)"[^>]*>([^<]*)<', svg)]


def assert_apart(svg: str) -> None:
    labels = label_boxes(svg)
    for (a, box_a), (b, box_b) in itertools.combinations(labels, 2):
        assert not box_a.intersects(box_b), (a, box_a, b, box_b)
    assert all(box.within(FRAME) for _, box in labels), labels


# --- lanes, lines, box ------------------------------------------------------------------------------

def test_every_lane_in_view_is_drawn_from_its_polyline_at_its_width():
    pic = lanes_picture()
    svg = scene_svg(pic)
    paths = re.findall(r'<path class="lane (lane-\w+)" d="([^"]+)"[^>]*stroke-width="([0-9.]+)"[^>]*><title>lane ([^ ]+) ',
                       svg)
    view = view_of(pic)
    in_view = [lane for lane in pic.lanes if view.sees(lane.shape, lane.width_m)]
    assert len(paths) == len(in_view) == len(pic.lanes) - 1          # the far lane is left out
    assert "far_0" not in svg
    by_id = {lane.id: lane for lane in pic.lanes}
    for cls, d, width, lane_id in paths:
        lane = by_id[lane_id]
        assert cls == f"lane-{lane.kind}"
        assert float(width) == pytest.approx(lane.width_m * view.scale, abs=0.01)
        drawn = [tuple(map(float, p.split(","))) for p in re.findall(r"[ML]([-0-9.]+,[-0-9.]+)", d)]
        assert drawn == [pytest.approx(view(*p), abs=0.01) for p in lane.shape]
    assert 'class="road"' not in svg                      # lanes replace the road bands


def test_a_map_without_lanes_gets_its_roads_as_bands():
    pic = replace(lanes_picture(), lanes=())
    svg = scene_svg(pic)
    assert svg.count('class="road"') == 2 and 'class="lane' not in svg
    assert svg.count('class="stop-line"') == 4 and svg.count('class="yellow-box"') == 1    # what it records


def test_stop_lines_crossings_and_the_yellow_box_are_drawn():
    pic = lanes_picture()
    svg = scene_svg(pic)
    assert svg.count('class="stop-line"') == 4 and "signal stop line of junction j1, west approach" in svg
    assert svg.count('class="crossing"') == 4
    assert svg.count('class="yellow-box"') == 1 and 'fill="url(#box-hatch-1)"' in svg
    assert 'id="box-hatch-3"' in scene_svg(pic, 3)         # one pattern id per picture of a page
    j1 = pic.junctions[0]
    give_way = replace(pic, junctions=(replace(j1, stop_lines=(replace(j1.stop_lines[0], kind="give_way"),
                                                               *j1.stop_lines[1:])),))
    assert re.search(r'<line class="stop-line"[^>]*stroke-dasharray="4 3"><title>Give Way line', scene_svg(give_way))


def test_a_map_that_is_not_numbers_draws_what_it_can():
    raw = sumo_like_map()
    raw["lanes"][0]["shape"] = [[0, 0], ["x", 1]]
    raw["lanes"][1]["width_m"] = float("nan")
    raw["junctions"][0]["box"] = "a box"
    raw["junctions"][0]["stop_lines"][0]["to"] = None
    the_map = run_map({"map": raw})
    assert len(the_map.lanes) == len(raw["lanes"]) - 2
    assert the_map.junctions[0].box is None and len(the_map.junctions[0].stop_lines) == 3


# --- signals ------------------------------------------------------------------------------------------

def test_each_approach_shows_its_own_colour_at_its_stop_line():
    pic = lanes_picture()
    svg = scene_svg(pic)
    lamps = re.findall(r'<g class="signal"><title>signal j1 (\w+): (\w+)</title>.*?<circle cx="([-0-9.]+)" '
                       r'cy="([-0-9.]+)" r="5.5" fill="([^"]+)"', svg)
    assert {a: c for a, c, *_ in lamps} == SIGNAL_COLOURS
    view = view_of(pic)
    lines = {line.approach: line for line in pic.junctions[0].stop_lines}
    for approach, colour, cx, cy, lamp_fill in lamps:
        assert lamp_fill == SIGNAL_FILL[colour]
        (ax, ay), (bx, by) = lines[approach].a, lines[approach].b
        length = math.hypot(bx - ax, by - ay)
        want = view(bx + (bx - ax) / length * LAMP_OUT_M, by + (by - ay) / length * LAMP_OUT_M)
        assert (float(cx), float(cy)) == pytest.approx(want, abs=0.01)


def test_an_approach_without_a_stop_line_keeps_its_lamp_by_compass():
    pic = lanes_picture()
    pic = replace(pic, junctions=(replace(pic.junctions[0], stop_lines=()),))
    svg = scene_svg(pic)
    assert svg.count('<g class="signal">') == 4


# --- mph, focus, labels ---------------------------------------------------------------------------------

def test_labels_give_speeds_in_mph():
    svg = scene_svg(lanes_picture())
    texts = [t for t, _ in label_boxes(svg)]
    assert "7 car 0 mph" in texts and "8 bus 30 mph" in texts and "pedestrian/p1 3 mph" in texts
    assert "13.41" not in " ".join(texts)                 # m/s only in the title, beside the mph


def test_the_view_is_the_junction_not_the_whole_map():
    pic = lanes_picture()
    view = view_of(pic)
    x0, y0, x1, y1 = view.world_frame()
    assert x1 - x0 < 150 and y1 - y0 < 100                # the map is 400 m across
    assert view.scale * 3.5 >= 12                          # a lane is at least 12 px wide


def test_a_road_user_outside_the_zoom_is_named_not_lost():
    pic = lanes_picture()
    pic = replace(pic, vehicles=pic.vehicles + (replace(pic.vehicles[1], id="far", x=150.0, y=-1.75),))
    assert out_of_view(pic) == ["far"]
    assert ">far bus" not in scene_svg(pic)                # clipped, and no label at the frame's edge


def test_labels_over_the_lanes_do_not_overlap():
    assert_apart(scene_svg(lanes_picture()))
    assert_apart(scene_svg(crowded_picture()))


names = st.text(alphabet="abcdefghijklmnopqrstuvwxyz0123456789-/", min_size=1, max_size=14)


@st.composite
def crowded_scenes(draw) -> Picture:
    """lanes_picture() with up to 24 vehicles and 8 pedestrians within 25 m of the junction."""
    pic = lanes_picture()
    coord = st.floats(min_value=-25, max_value=25, allow_nan=False)
    n = draw(st.integers(min_value=1, max_value=24))
    ids = draw(st.lists(names, min_size=n, max_size=n, unique=True))
    vehicles = tuple(Mover(i, draw(st.sampled_from(["car", "bus", "ambulance", "cyclist", None])),
                           draw(coord), draw(coord),
                           draw(st.one_of(st.none(), st.floats(min_value=0, max_value=359))),
                           draw(st.one_of(st.none(), st.floats(min_value=0, max_value=40))),
                           incident=k == 0, age_s=0.0)
                     for k, i in enumerate(ids))
    m = draw(st.integers(min_value=0, max_value=8))
    users = tuple(Mover(f"pedestrian/p{k}", "pedestrian", draw(coord), draw(coord), None, 1.2, vehicle=False,
                        age_s=0.0) for k in range(m))
    return replace(pic, vehicles=vehicles, vehicle=ids[0], road_users=users)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(crowded_scenes())
def test_no_two_labels_ever_overlap_in_a_crowded_scene(pic):
    svg = scene_svg(pic)
    assert_apart(svg)
    drawn = [v for v in pic.movers if FRAME.holds(*view_of(pic)(v.x, v.y))]
    assert len(label_boxes(svg)) >= len(drawn)            # every road user in the frame is named


# --- only who is there, through `gaps scene --svg` --------------------------------------------------------

def event(src: str, kind: str, seq: int, t: int, body: dict) -> dict:
    return {"v": 1, "run": RUN, "src": src, "seq": seq, "t": t, "kind": kind, "body": body}


@pytest.fixture(scope="module")
def lanes_db(tmp_path_factory):
    """The paper's run with the SUMO-like map in its run.start, and three more cars around +20 s:
    600 there, 601 despawned at +19 s, 602 spawned only at +25 s."""
    events = paper_run()
    start = next(e for e in events if e["kind"] == "run.start")
    start["body"]["map"] = sumo_like_map()
    at = T0 + 20 * SECOND
    events += [
        event("vehicle/600", "entity.spawn", 0, at - 5 * SECOND, {"type": "car"}),
        event("vehicle/600", "entity.state", 1, at - SECOND // 2, {"x": -1.75, "y": -30.0, "heading_deg": 90.0,
                                                                  "speed_mps": 8.94}),
        event("vehicle/601", "entity.spawn", 0, at - 5 * SECOND, {"type": "car"}),
        event("vehicle/601", "entity.state", 1, at - 1_500_000_000, {"x": 20.0, "y": -1.75, "heading_deg": 180.0,
                                                                    "speed_mps": 5.0}),
        event("vehicle/601", "entity.despawn", 2, at - SECOND, {"reason": "left the map"}),
        event("vehicle/602", "entity.spawn", 0, at + 5 * SECOND, {"type": "car"}),
        event("vehicle/602", "entity.state", 1, at + 5 * SECOND, {"x": 1.75, "y": 30.0, "heading_deg": 270.0,
                                                                 "speed_mps": 5.0}),
    ]
    path = tmp_path_factory.mktemp("scene-svg") / "gaps.db"
    with Store(path) as store:
        report = store.append(sorted(events, key=lambda e: e["t"]))
        assert not report.rejected, report.rejected
    return path


def test_gaps_scene_svg_draws_only_who_is_there(lanes_db, tmp_path):
    out = tmp_path / "scene.svg"
    result = gaps("scene", "--run", RUN, "--at", "20s", "--svg", str(out), db=lanes_db)
    assert result.exit_code == 0, result.output
    assert f"written to {out}" in result.stdout and "junction j1" in result.stdout
    svg = out.read_text(encoding="utf-8")
    ET.fromstring(svg.encode())                            # a well-formed SVG file
    drawn = re.findall(r"<title>vehicle (\w+) \(", svg)
    assert "600" in drawn and "601" not in drawn and "602" not in drawn
    assert ">600 car 20 mph<" in svg
    assert svg.count('class="lane ') == 16                  # every lane around j1, not the far one


def test_gaps_scene_svg_mistakes_are_clear(lanes_db, tmp_path):
    result = gaps("scene", "--run", RUN, "--at", "20s", "--svg", str(tmp_path / "x.svg"), "--junction", "j9",
                  db=lanes_db)
    assert result.exit_code == 2 and "no junction 'j9' on the map" in result.output
    result = gaps("scene", "--run", RUN, "--at", "20s", "--svg", str(tmp_path / "no" / "x.svg"), db=lanes_db)
    assert result.exit_code == 2 and "no such folder" in result.output
    result = gaps("scene", "--run", RUN, "--at", "20s", "--svg", str(tmp_path / "x.svg"), "--vehicle", "601",
                  db=lanes_db)
    assert result.exit_code == 2 and "left the run" in result.output
