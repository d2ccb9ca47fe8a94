"""Scene pictures (explain/picture_parts.py's `Picture`) and timelines (timeline_parts.py's
`ActTimeline`) built by hand, for the label tests of test_report_print.py, test_report_pictures.py
and the browser test."""
from __future__ import annotations

from explain.picture_parts import JunctionDrawn, MonitorDrawn, Mover, Picture, RoadDrawn, SignalDrawn
from explain.timeline_parts import ActTimeline, Moment
from reasoner.timelines import ApproachPhases, Phase, SpeedSample, Timeline


def crowded_picture() -> Picture:
    """Seven vehicles within 4 m of one another at a junction, a monitor and a signal beside them."""
    cars = [("1", 0.0, 0.0, True), ("22", 1.5, 0.5, False), ("333", -1.0, 1.2, False), ("4444", 0.8, -1.5, False),
            ("55", 2.5, 2.0, False), ("ambulance-6", -2.0, -1.0, False), ("7", 3.0, -2.5, False)]
    return Picture(t=0, offset="+0s", vehicle="1", note=None,
                   roads=(RoadDrawn("r", (-50.0, 0.0), (50.0, 0.0)),),
                   junctions=(JunctionDrawn("j1", 1.0, 0.0, "lights"),),
                   signals=(SignalDrawn("j1", "west", "red", 0),),
                   monitors=(MonitorDrawn("monitor/m1", "j1", -1.0, 3.0, 0.0, 90.0, 30.0, ("1",), True),),
                   vehicles=tuple(Mover(i, "car", x, y, 0.0, 5.0, junction="j1", incident=me, age_s=0.0)
                                  for i, x, y, me in cars),
                   road_users=(Mover("pedestrian/p", "pedestrian", 0.5, 0.5, None, vehicle=False, age_s=0.0),))


def _rotate(points: list[list[float]], quarter: int) -> list[list[float]]:
    """Points turned `quarter` quarter-turns anticlockwise about the origin."""
    out = [list(p) for p in points]
    for _ in range(quarter % 4):
        out = [[-y, x] for x, y in out]
    return out


ARMS = ("west", "south", "east", "north")     # the approach from where the traffic comes; west turned by 90°s


def sumo_like_map() -> dict:
    """A run.start map as sim_replay/net_map.py writes it for a four-arm junction j1 at the origin
    (left-hand traffic): per arm a 3.5 m lane each way and a 2 m pavement each side, 188 m long,
    a stop line at 12 m on the inbound lane, a zebra crossing, the yellow box, and one lane far
    away (out of any view of j1)."""
    lanes, lines, crossings = [], [], []
    for quarter, arm in enumerate(ARMS):
        def turned(points: list[list[float]]) -> list[list[float]]:
            return _rotate(points, quarter)
        lanes += [
            {"id": f"{arm}_in_1", "kind": "road", "width_m": 3.5, "shape": turned([[-200.0, 1.75], [-12.0, 1.75]])},
            {"id": f"{arm}_out_1", "kind": "road", "width_m": 3.5, "shape": turned([[-12.0, -1.75], [-200.0, -1.75]])},
            {"id": f"{arm}_in_0", "kind": "sidewalk", "width_m": 2.0, "shape": turned([[-200.0, 4.5], [-12.0, 4.5]])},
            {"id": f"{arm}_out_0", "kind": "sidewalk", "width_m": 2.0,
             "shape": turned([[-12.0, -4.5], [-200.0, -4.5]])},
        ]
        a, b = turned([[-12.0, 0.0], [-12.0, 3.5]])
        lines.append({"approach": arm, "from": a, "to": b, "kind": "signal", "edge": f"{arm}_in", "road": "r"})
        crossings.append({"id": f":j1_c{quarter}", "arm": arm, "shape": turned([[-10.0, -3.5], [-10.0, 3.5]]),
                          "width_m": 4.0, "priority": True})
    lanes.append({"id": "far_0", "kind": "road", "width_m": 3.5, "shape": [[900.0, 500.0], [1000.0, 500.0]]})
    box = [[-8.0, -4.5], [-8.0, 4.5], [-4.5, 8.0], [4.5, 8.0], [8.0, 4.5], [8.0, -4.5], [4.5, -8.0], [-4.5, -8.0]]
    shape = [[-12.0, -5.5], [-12.0, 5.5], [-5.5, 12.0], [5.5, 12.0], [12.0, 5.5], [12.0, -5.5], [5.5, -12.0],
             [-5.5, -12.0]]
    return {"network": {"file": "test.net.xml", "sha256": "0" * 64, "lefthand": True},
            "roads": [{"id": "r1", "from": [-200.0, 0.0], "to": [200.0, 0.0], "speed_limit_mph": 30},
                      {"id": "r2", "from": [0.0, -200.0], "to": [0.0, 200.0], "speed_limit_mph": 30}],
            "junctions": [{"id": "j1", "x": 0.0, "y": 0.0, "control": "lights", "stop_lines": lines, "box": box,
                           "shape": shape, "crossings": crossings, "sumo_type": "traffic_light",
                           "approaches": [{"name": a, "edge": f"{a}_in", "road": "r"} for a in ARMS]}],
            "monitors": [{"id": "m1", "junction": "j1", "x": 15.0, "y": 10.0, "heading_deg": 190.0,
                          "range_m": 80.0, "fov_deg": 90.0}],
            "lanes": lanes}


SIGNAL_COLOURS = {"west": "red", "east": "red", "north": "green", "south": "amber"}


def lanes_picture() -> Picture:
    """A scene picture over sumo_like_map(): the incident's car stopped at the west line (on red),
    a car crossing from the south, a pedestrian on the east zebra, each approach's colour."""
    from explain.report_data import run_map
    the_map = run_map({"map": sumo_like_map()})
    return Picture(t=0, offset="+60s", vehicle="7", note=None, junction="j1", roads=the_map.roads,
                   lanes=the_map.lanes, lefthand=the_map.lefthand, junctions=the_map.junctions,
                   signals=tuple(SignalDrawn("j1", a, c, 0) for a, c in SIGNAL_COLOURS.items()),
                   monitors=(MonitorDrawn("monitor/m1", "j1", 15.0, 10.0, 190.0, 90.0, 80.0, ("7",), True),),
                   vehicles=(Mover("7", "car", -14.5, 1.75, 0.0, 0.0, incident=True, age_s=0.0),
                             Mover("8", "bus", -1.75, -20.0, 90.0, 13.41, age_s=0.0)),
                   road_users=(Mover("pedestrian/p1", "pedestrian", 10.0, 0.0, 90.0, 1.3, vehicle=False, age_s=0.0),))


# --- timelines ------------------------------------------------------------------------------------

SECOND = 1_000_000_000
# demo-sumo's incident 10 (a fire engine standing at a red light, then going through it) and
# incident 26: the moments its passage had, seconds from the incident
FIRE_ENGINE = [("stood still before the line", -8.5), ("moved off", -0.5), ("crossed the stop line", -0.07),
               ("entered the junction", 0.04), ("left the junction", 3.72)]
STOP_AND_GO = [("stood still before the line", -15.7), ("moved off", -12.4), ("stood still before the line", -9.3),
               ("moved off", -5.7), ("crossed the stop line", -5.25), ("entered the junction", -5.15),
               ("left the junction", -1.26)]
# a quick passage: it stood still a moment at the line, then went through (labels that once piled up)
QUICK = [("stood still before the line", -1.6), ("moved off", -1.2), ("crossed the stop line", -1.0),
         ("entered the junction", -0.9), ("left the junction", 0.4)]


def a_timeline(moments: list[tuple[str, float]], **extra) -> ActTimeline:
    """A fire engine's 25 s at j1 (it stands at red from -9 s, goes at the incident), with
    `moments` (what, seconds from the incident) and any `extra` parts (to_line, other)."""
    t = 100 * SECOND
    speed = tuple(SpeedSample(t + round(s * SECOND), v, i) for i, (s, v) in
                  enumerate([(-20, 13.4), (-9, 0.0), (-0.5, 0.0), (0, 1.1), (4, 6.0)]))
    signals = (ApproachPhases("south", (Phase(t - 30 * SECOND, "red"),)),
               ApproachPhases("west", (Phase(t - 30 * SECOND, "green"), Phase(t + 3 * SECOND, "amber"))))
    window = Timeline(t, t - 20 * SECOND, t + 5 * SECOND, "109", "j1", speed, (), signals)
    return ActTimeline(window, 90.0, tuple(Moment(what, t + round(s * SECOND)) for what, s in moments), **extra)
