"""The road surface of the scene picture as the map recorded it: lanes, junction areas, crossings,
the yellow box and the stop lines.

A SUMO run's map (sim_replay/net_map.py) carries every lane outside the junctions as a polyline
with its width, each junction's outline, its pedestrian crossings, its yellow box and the stop
line of each approach. Drawn at their true width through the picture's one scale (scene_view.py),
they show what the reasoner measured against: which side of the line a car stood, whether it sat
in the box. A map without lanes (the paper's hand-written run, a foreign producer that sends only
roads) gets the older drawing, each road as a grey band and each junction as a square, with the
stop lines and box it does record.

Only lanes that meet the drawing area are written, so a 600 m map does not fill the page's SVG
with paths nobody can see. Recorded ids go into titles only through `esc`.
"""
from __future__ import annotations

import math
from .picture_parts import JunctionDrawn, Picture, Point
from .scene_view import View
from .svg import esc, f

LANE_FILL = {"road": "#a8a49c", "sidewalk": "#dcd6c8", "cycle": "#c98f72"}
OTHER_LANE_FILL = "#bdb8ad"
SURFACE = LANE_FILL["road"]
BOX_YELLOW = "#f2c200"
STOP_LINE_M = 0.3          # a stop line's painted width (TSRGD: 200-300 mm)
DRAW_ORDER = {"sidewalk": 0, "cycle": 1}     # pavements under the carriageway where they meet


def has_lanes(pic: Picture) -> bool:
    """Whether the map carries lanes to draw (else the roads are drawn as bands)."""
    return bool(pic.lanes)


def surface(pic: Picture, view: View, number: int) -> list[str]:
    """Every part of the road surface, bottom to top; `number` keeps the box hatch's pattern id
    apart from the other pictures of the same page."""
    if not has_lanes(pic):
        out = roads(pic, view) + [junction_square(j, view, pic.junction) for j in pic.junctions]
    else:
        out = lanes(pic, view)
        for j in pic.junctions:
            out += junction_area(j, view, pic.junction)
        out += lane_markings(pic, view)
    hatch = f"box-hatch-{int(number)}"
    out.append(f'<defs><pattern id="{hatch}" patternUnits="userSpaceOnUse" width="8" height="8" '
               f'patternTransform="rotate(45)"><path d="M0,0 L0,8 M0,0 L8,0" stroke="{BOX_YELLOW}" '
               'stroke-width="1.5"/></pattern></defs>')
    for j in pic.junctions:
        out += crossings(j, view) + yellow_box(j, view, hatch) + stop_lines(j, view)
    return out


def lanes(pic: Picture, view: View) -> list[str]:
    """One path per lane in view, as wide as the lane; pavements first."""
    out = []
    shown = [lane for lane in pic.lanes if view.sees(lane.shape, lane.width_m)]
    for lane in sorted(shown, key=lambda lane: DRAW_ORDER.get(lane.kind or "", 2)):
        colour = LANE_FILL.get(lane.kind or "", OTHER_LANE_FILL)
        out.append(f'<path class="lane lane-{_kind_class(lane.kind)}" d="{_path(lane.shape, view)}" '
                   f'fill="none" stroke="{colour}" stroke-width="{f(lane.width_m * view.scale)}" '
                   f'stroke-linecap="butt" stroke-linejoin="round"><title>lane {esc(lane.id)} '
                   f'({esc(lane.kind or "kind not recorded")}, {f(lane.width_m)} m wide)</title></path>')
    return out


def lane_markings(pic: Picture, view: View) -> list[str]:
    """A dashed white line on the driver's offside edge of each carriageway lane (the right in
    left-hand traffic): the centre line between the directions, the separator between lanes."""
    side = -1.0 if pic.lefthand else 1.0
    out = []
    for lane in pic.lanes:
        if lane.kind != "road" or not view.sees(lane.shape, lane.width_m):
            continue
        edge = _offset(lane.shape, side * lane.width_m / 2)
        out.append(f'<path class="lane-marking" d="{_path(edge, view)}" fill="none" stroke="#ffffff" '
                   f'stroke-width="1" stroke-dasharray="{f(3 * view.scale)} {f(3 * view.scale)}"/>')
    return out


def junction_area(j: JunctionDrawn, view: View, focus: str | None) -> list[str]:
    """The junction's outline filled as carriageway, or a square where the map gives none."""
    if not j.shape:
        return [junction_square(j, view, focus)]
    pts = " ".join(f"{f(a)},{f(b)}" for a, b in (view(*p) for p in j.shape))
    return [f'<polygon class="junction" points="{pts}" fill="{SURFACE}" stroke="none">'
            f'<title>junction {esc(j.id)} ({esc(j.control or "control not recorded")})</title></polygon>']


def junction_square(j: JunctionDrawn, view: View, focus: str | None) -> str:
    """A junction the map gives only a centre for."""
    x, y = view(j.x, j.y)
    size = max(10.0, 9.0 * view.scale)
    stroke = "#333" if j.id == focus else "#888"
    return (f'<rect class="junction" x="{f(x - size / 2)}" y="{f(y - size / 2)}" width="{f(size)}" '
            f'height="{f(size)}" fill="#d8d2c4" stroke="{stroke}" stroke-width="1">'
            f'<title>junction {esc(j.id)} ({esc(j.control or "control not recorded")})</title></rect>')


def crossings(j: JunctionDrawn, view: View) -> list[str]:
    """Zebra stripes: dashes half a metre long along the crossing, as wide as it."""
    out = []
    for c in j.crossings:
        dash = f(0.5 * view.scale)
        out.append(f'<path class="crossing" d="{_path(c.shape, view)}" fill="none" stroke="#f7f7f2" '
                   f'stroke-width="{f(c.width_m * view.scale)}" stroke-dasharray="{dash} {dash}">'
                   f'<title>pedestrian crossing {esc(c.id)}</title></path>')
    return out


def yellow_box(j: JunctionDrawn, view: View, hatch: str) -> list[str]:
    """The box junction's criss-cross yellow lines (HC 174)."""
    if not j.box:
        return []
    pts = " ".join(f"{f(a)},{f(b)}" for a, b in (view(*p) for p in j.box))
    return [f'<polygon class="yellow-box" points="{pts}" fill="url(#{hatch})" stroke="{BOX_YELLOW}" '
            f'stroke-width="2"><title>yellow box of junction {esc(j.id)}</title></polygon>']


def stop_lines(j: JunctionDrawn, view: View) -> list[str]:
    """Each approach's line: solid for a signal or Stop line, dashed for Give Way."""
    out = []
    width = f(max(3.0, STOP_LINE_M * view.scale))
    for line in j.stop_lines:
        (x1, y1), (x2, y2) = view(*line.a), view(*line.b)
        dashed = ' stroke-dasharray="4 3"' if line.kind == "give_way" else ""
        out.append(f'<line x1="{f(x1)}" y1="{f(y1)}" x2="{f(x2)}" y2="{f(y2)}" stroke="#333333" '
                   f'stroke-width="{f(float(width) + 2)}"{dashed}/>')      # a dark edge: seen on a zebra too
        out.append(f'<line class="stop-line" x1="{f(x1)}" y1="{f(y1)}" x2="{f(x2)}" y2="{f(y2)}" stroke="#ffffff" '
                   f'stroke-width="{width}"{dashed}><title>{esc(_line_name(line.kind))} of junction '
                   f'{esc(j.id)}, {esc(line.approach or "approach not recorded")} approach</title></line>')
    return out


def roads(pic: Picture, view: View) -> list[str]:
    """A map without lanes: each road as a grey band with a dashed centre line."""
    width = max(6.0, 7.0 * view.scale)
    out = []
    for r in pic.roads:
        (x1, y1), (x2, y2) = view(*r.a), view(*r.b)
        out.append(f'<line class="road" x1="{f(x1)}" y1="{f(y1)}" x2="{f(x2)}" y2="{f(y2)}" stroke="#b9b4aa" '
                   f'stroke-width="{f(width)}" stroke-linecap="butt"><title>road {esc(r.id)}</title></line>')
        out.append(f'<line x1="{f(x1)}" y1="{f(y1)}" x2="{f(x2)}" y2="{f(y2)}" stroke="#ffffff" '
                   'stroke-width="1" stroke-dasharray="6 6"/>')
    return out


def _line_name(kind: str | None) -> str:
    return {"signal": "signal stop line", "stop_sign": "Stop line", "give_way": "Give Way line"}.get(kind or "",
                                                                                                 "stop line")


def _kind_class(kind: str | None) -> str:
    """A lane kind as a class name: only the known kinds, so a recorded string never becomes markup."""
    return kind if kind in LANE_FILL else "other"


def _path(points: tuple[Point, ...], view: View) -> str:
    return " ".join(("M" if i == 0 else "L") + f"{f(x)},{f(y)}" for i, (x, y) in
                    enumerate(view(*p) for p in points))


def _offset(points: tuple[Point, ...], d: float) -> tuple[Point, ...]:
    """The polyline moved `d` metres to its left (negative: right), each point along the normal of
    its segment (the first segment's for the first point)."""
    out = []
    for i, (x, y) in enumerate(points):
        a, b = (points[i - 1], points[i]) if i else (points[0], points[1])
        dx, dy = b[0] - a[0], b[1] - a[1]
        norm = math.hypot(dx, dy) or 1.0
        out.append((x - dy / norm * d, y + dx / norm * d))
    return tuple(out)
