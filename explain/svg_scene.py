"""The scene at a moment as an inline SVG: the road surface as the map recorded it (svg_lanes.py:
SUMO's lanes at their widths, crossings, the yellow box, stop lines; a map without lanes gets its
roads as bands), the colour each signal approach showed at that approach's stop line, every road
user present (the incident's vehicle highlighted) pointing where it headed with its speed in mph,
and each monitor's field of view, with a legend and a scale bar.

Drawn from report_data.scene_picture only. World coordinates are metres with y up and headings
counter-clockwise from +x (as sim_replay and the Foxglove export read them); scene_view.py flips
them, and arcs are drawn as polylines, leaving no sweep flag to get wrong. The view is zoomed to
the junction that matters (the incident vehicle's, or the busiest for `gaps scene --svg`) and
the vehicle, not to the whole map: see _focus. Only road users present at the moment are drawn
(despawned and not yet spawned ones are not in the scene at all; a position older than
presence.FRESH_NS is not where the road user was), and the labels are placed by labels.py so that
none covers another.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple, cast

from .labels import Box, Label, Placer
from .picture_parts import JunctionDrawn, MonitorDrawn, Mover, Picture, SignalDrawn, StopLineDrawn
from .report_data import APPROACH_DIRECTIONS, vehicle_junction
from .scene_view import H, LEGEND_H, PAD, W, View
from .svg import colour_word, esc, f, fill, legend_colours, legend_swatches
from .svg_lanes import has_lanes, surface
from .units import mph, mph_text

NEAR_M = 40.0              # road users this close to the incident's vehicle are kept in view
JUNCTION_REACH_M = 30.0    # the view holds this much of each arm around the focus junction
LAMP_OUT_M = 2.0           # a signal lamp stands this far beyond the kerb end of its stop line
INCIDENT_COLOUR, VEHICLE_COLOUR, USER_COLOUR, MONITOR_COLOUR = "#7b1fa2", "#34495e", "#16a085", "#1d4f9c"


class _Want(NamedTuple):
    """A label a marker asks for: placed once every marker is drawn, by rank (0 first)."""

    rank: int               # 0 the incident's vehicle, 1 other vehicles, 2 road users, 3 monitors, 4 junctions
    text: str
    x: float
    y: float
    clear: float
    colour: str
    bold: bool = False


def view_of(pic: Picture) -> View:
    """The picture's world-to-pixel mapping (tests and viewers place things through it)."""
    return View(_focus(pic))


def scene_svg(pic: Picture, number: int = 1) -> str:
    """The picture as one <svg class="gaps-scene"> element; `number` keeps its clip path's id
    apart from the other pictures of the same page."""
    view = view_of(pic)
    junction = _junction(pic)
    me = pic.me
    clip = f"scene-clip-{int(number)}"
    label = (f"Scene at the incident ({pic.offset} from the run start): vehicle {pic.vehicle}"
             if pic.vehicle is not None else f"Scene at {pic.offset} from the run start")
    out = [f'<svg class="gaps-scene" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {W} {H}" width="{W}" '
           f'height="{H}" role="img" aria-label="{esc(label)}" font-family="sans-serif" font-size="11">',
           f"<title>{esc(label)}</title>",
           f'<defs><clipPath id="{clip}"><rect x="0" y="0" width="{W}" height="{H - LEGEND_H}"/>'
           "</clipPath></defs>",
           f'<rect x="0" y="0" width="{W}" height="{H}" fill="#f4f1ea"/>',
           f'<g clip-path="url(#{clip})">']
    placer = Placer(Box(0, 0, W, H - LEGEND_H))
    wants: list[_Want] = []
    out += surface(pic, view, number)
    out += _monitors(pic, view, placer, wants)
    out += _junctions(pic, view, wants)
    out += _signals(pic, view, placer)
    out += _road_users(pic, view, placer, wants)
    out += _vehicles(pic, view, placer, wants)
    missing = _not_drawn(me, pic.vehicle) if pic.vehicle is not None else None
    if missing:
        placer.block(Box(0, 0, W, PAD + 6))
        out.append(f'<text x="{W / 2}" y="{PAD}" text-anchor="middle" fill="#a40000">{esc(missing)}</text>')
    out += _labels(placer, wants)
    out.append("</g>")
    out += _legend(view, has_lanes(pic))
    out.append("</svg>")
    return "".join(out)


def drawn(item: Mover) -> bool:
    """A vehicle or road user the picture shows: placed, and present at the moment (presence.py)."""
    return item.drawn


def _at(item: Mover | MonitorDrawn) -> tuple[float, float]:
    """Where a road user or monitor the picture places is (x and y are numbers there)."""
    return cast(float, item.x), cast(float, item.y)


def out_of_view(pic: Picture) -> list[str]:
    """The road users present and placed but outside the zoomed picture, for its caption to name."""
    view = view_of(pic)
    frame = Box(0, 0, W, H - LEGEND_H)
    return [str(u.id) for u in pic.movers if drawn(u) and not frame.holds(*view(*_at(u)))]


def junctions_in_view(pic: Picture) -> list[str]:
    """The junctions whose centre the zoomed picture shows, the one it is about first: the
    caption speaks of their signals only."""
    view, frame = view_of(pic), Box(0, 0, W, H - LEGEND_H)
    shown = [str(j.id) for j in pic.junctions if frame.holds(*view(j.x, j.y))]
    focus = _junction(pic)
    return sorted(shown, key=lambda j: j != focus)


def _not_drawn(me: Mover | None, vehicle: str) -> str | None:
    """Why the incident's own vehicle is not in the picture, if it is not."""
    if me is None or me.x is None:
        return f"vehicle {vehicle} has no recorded position at this time"
    if not drawn(me):
        age = "" if me.age_s is None else f" is {me.age_s:g} s old"
        return f"vehicle {vehicle}'s last recorded position{age}: not drawn, it is not known where it was"
    return None


def _labels(placer: Placer, wants: list[_Want]) -> list[str]:
    """Every label, clear of the others, above every marker; the incident's vehicle is placed
    first, so it gets the spot nearest its marker, the junction's name last."""
    order = sorted((w for w in wants if placer.frame.holds(w.x, w.y)), key=lambda w: w.rank)   # off-frame: clipped
    out = ['<g class="labels">']
    for want in order:
        placed = placer.place(want.text, want.x, want.y, clear=want.clear, bold=want.bold)
        out.append(_label(placed, want.colour))
    return out + ["</g>"]


def _label(placed: Label, colour: str) -> str:
    out = ""
    if placed.leader:
        (ax, ay), (bx, by) = placed.anchor, placed.box.nearest(*placed.anchor)
        out += (f'<line class="leader" x1="{f(ax)}" y1="{f(ay)}" x2="{f(bx)}" y2="{f(by)}" stroke="{colour}" '
                'stroke-width="0.75"/>')
    x, y = placed.baseline
    weight = ' font-weight="bold"' if placed.bold else ""
    box = placed.box
    return out + (f'<text class="label" x="{f(x)}" y="{f(y)}" fill="{colour}"{weight} paint-order="stroke" '
                  f'stroke="#f4f1ea" stroke-width="3" stroke-linejoin="round" '
                  f'data-box="{f(box.x)} {f(box.y)} {f(box.w)} {f(box.h)}">{esc(placed.text)}</text>')


def _junction(pic: Picture) -> str | None:
    """The junction the picture zooms to: the one report_data chose, else the vehicle's."""
    return pic.junction if pic.junction is not None else vehicle_junction(pic)


def _focus(pic: Picture) -> list[tuple[float, float]]:
    """The points the view must hold: the incident's vehicle, its junction with JUNCTION_REACH_M
    of every arm (the stop lines and the queue at them), the monitors there (their cones reach
    80 m and are clipped: holding them would shrink the junction), every road user the incident
    names (pic.named: the one it would force or endanger, the one approaching, however far),
    and road users near the vehicle.

    Why not the whole map: at 600 m across, a lane is 2 px and a car a dot; at about 70 m a lane
    is some 17 px wide, a car sits visibly before or beyond its stop line, and the labels have
    room. A road user the incident does not name and that is outside the view is clipped; the
    report's caption names the nearest of them and counts the rest, `gaps scene` lists every one."""
    me = next((v for v in pic.vehicles if v.incident and drawn(v)), None)
    junction = _junction(pic)
    pts: list[tuple[float, float]] = []
    if me is not None:
        pts.append(_at(me))
    for j in pic.junctions:
        if j.id == junction:
            pts += [(j.x + dx * JUNCTION_REACH_M, j.y + dy * JUNCTION_REACH_M) for dx in (-1, 1) for dy in (-1, 1)]
    for m in pic.monitors:
        if m.x is not None and m.y is not None and (m.watching or (junction and m.junction == junction)):
            pts.append(_at(m))
    named = set(pic.named or ())
    for other in pic.movers:
        if not drawn(other):
            continue
        (ox, oy) = _at(other)
        if str(other.id) in named or (me is not None and math.hypot(ox - _at(me)[0], oy - _at(me)[1]) <= NEAR_M):
            pts.append((ox, oy))
    if not pts:        # nothing to centre on: the whole map
        pts = [(j.x, j.y) for j in pic.junctions]
        pts += [_at(m) for m in pic.monitors if m.x is not None and m.y is not None]
        pts += [_at(v) for v in pic.vehicles if drawn(v)]
    return pts


def _wedge_points(m: MonitorDrawn) -> list[tuple[float, float]]:
    """The monitor's position then its field-of-view arc (world metres)."""
    heading, fov, reach = m.heading_deg, m.fov_deg, m.range_m
    if heading is None or reach is None or reach <= 0:
        return []
    mx, my = _at(m)
    fov = 360.0 if fov is None else max(0.0, min(fov, 360.0))
    steps = 24
    start = math.radians(heading - fov / 2)
    arc = [(mx + reach * math.cos(start + math.radians(fov) * i / steps),
            my + reach * math.sin(start + math.radians(fov) * i / steps)) for i in range(steps + 1)]
    return [(mx, my)] + arc


def _junctions(pic: Picture, view: View, wants: list[_Want]) -> list[str]:
    """Each junction's name, placed last (svg_lanes.py draws the junction itself)."""
    for j in pic.junctions:
        x, y = view(j.x, j.y)
        wants.append(_Want(4, f"junction {_short(str(j.id))}", x, y, max(5.0, 4.5 * view.scale), "#333"))
    return []


def _signals(pic: Picture, view: View, placer: Placer) -> list[str]:
    """One lamp per approach showing the colour that approach faced, standing just beyond the
    kerb end of the approach's stop line, where a driver at the line sees it. An approach the map
    gives no stop line for gets its lamp on the side its traffic comes from (by compass name), to
    the approaching driver's left. Labels keep off the lamps."""
    where = {j.id: j for j in pic.junctions}
    by_junction: dict[str, list[SignalDrawn]] = {}
    for s in pic.signals:
        by_junction.setdefault(s.junction, []).append(s)
    out = []
    for junction, shown in by_junction.items():
        if junction not in where:
            continue
        j = where[junction]
        lines = {line.approach: line for line in j.stop_lines}
        for i, s in enumerate(shown):
            line = lines.get(s.approach) if isinstance(s.approach, str) else None
            x, y = view(*(_at_line(line) if line else _by_compass(j, s.approach, i, view.scale)))
            title = f"signal {junction} {s.approach}: {colour_word(s.colour)}"
            placer.block(Box(x - 7, y - 11, 14, 22))
            out.append(f'<g class="signal"><title>{esc(title)}</title>'
                       f'<rect x="{f(x - 7)}" y="{f(y - 11)}" width="14" height="22" rx="3" fill="#222"/>'
                       f'<circle cx="{f(x)}" cy="{f(y)}" r="5.5" fill="{fill(s.colour)}" stroke="#000" '
                       'stroke-width="0.5"/></g>')
    return out


def _at_line(line: StopLineDrawn) -> tuple[float, float]:
    """LAMP_OUT_M beyond the stop line's kerb end (its `b`, "to"; `a` is at the centre line)."""
    (ax, ay), (bx, by) = line.a, line.b
    length = math.hypot(bx - ax, by - ay) or 1.0
    return bx + (bx - ax) / length * LAMP_OUT_M, by + (by - ay) / length * LAMP_OUT_M


def _by_compass(j: JunctionDrawn, approach: Any, i: int, scale: float) -> tuple[float, float]:
    """About 26 px out from the centre towards where the approach's traffic comes from, and 16 px
    to that driver's left (the UK kerb side)."""
    name = approach.lower() if isinstance(approach, str) else ""
    a = math.radians(APPROACH_DIRECTIONS.get(name, 45.0 + 90.0 * i))
    dist, side = max(10.0, 26.0 / scale), 16.0 / scale
    return (j.x + dist * math.cos(a) + side * math.cos(a - math.pi / 2),
            j.y + dist * math.sin(a) + side * math.sin(a - math.pi / 2))


def _monitors(pic: Picture, view: View, placer: Placer, wants: list[_Want]) -> list[str]:
    out = []
    for m in pic.monitors:
        if m.x is None or m.y is None:
            continue
        wedge = _wedge_points(m)
        if wedge:
            pts = " ".join(f"{f(a)},{f(b)}" for a, b in (view(*p) for p in wedge))
            out.append(f'<polygon class="fov" points="{pts}" fill="#2a6fdb" fill-opacity="0.12" stroke="#2a6fdb" '
                       f'stroke-opacity="0.6" stroke-width="1"><title>{esc(_fov_title(m))}</title></polygon>')
        x, y = view(*_at(m))
        out.append(f'<rect class="monitor" x="{f(x - 5)}" y="{f(y - 5)}" width="10" height="10" fill="#2a6fdb">'
                   f"<title>{esc(_fov_title(m))}</title></rect>")
        placer.block(Box(x - 5, y - 5, 10, 10))
        wants.append(_Want(3, _short(str(m.id)), x, y, 7.0, MONITOR_COLOUR))
    return out


def _fov_title(m: MonitorDrawn) -> str:
    return (f"{m.id}: field of view {_n(m.fov_deg)}° heading {_n(m.heading_deg)}°, "
            f"range {_n(m.range_m)} m")


def _vehicles(pic: Picture, view: View, placer: Placer, wants: list[_Want]) -> list[str]:
    out = []
    for v in sorted(pic.vehicles, key=lambda v: v.incident):      # the incident's drawn last, on top
        if not drawn(v):
            continue
        x, y = view(*_at(v))
        r = 7 if v.incident else 5
        colour = INCIDENT_COLOUR if v.incident else VEHICLE_COLOUR
        cls = "vehicle incident" if v.incident else "vehicle"
        if v.heading_deg is not None:
            a = math.radians(v.heading_deg)
            hx, hy = x + 18 * math.cos(a), y - 18 * math.sin(a)
            out.append(f'<line x1="{f(x)}" y1="{f(y)}" x2="{f(hx)}" y2="{f(hy)}" stroke="{colour}" stroke-width="2"/>')
            out.append(_arrow_head(hx, hy, a, colour))
            placer.block(Box(min(x, hx) - 4, min(y, hy) - 4, abs(hx - x) + 8, abs(hy - y) + 8))
        ring = (f'<circle cx="{f(x)}" cy="{f(y)}" r="{r + 5}" fill="none" stroke="{INCIDENT_COLOUR}" '
                'stroke-width="2" stroke-dasharray="3 2"/>' if v.incident else "")
        out.append(f'<g class="{cls}">{ring}<circle cx="{f(x)}" cy="{f(y)}" r="{r}" fill="{colour}" stroke="#fff" '
                   f'stroke-width="1.5"><title>{esc(_vehicle_title(v))}</title></circle></g>')
        reach = r + 5 if v.incident else r
        placer.block(Box(x - reach, y - reach, 2 * reach, 2 * reach))
        text = _short(str(v.id)) + (" " + _short(str(v.type)) if v.type else "") + _speed(v)
        wants.append(_Want(0 if v.incident else 1, text, x, y, reach + 2, colour, v.incident))
    return out


def _speed(v: Mover) -> str:
    """" 17 mph" for a label: whole miles per hour, the unit UK roads and the Highway Code use (the
    title and the caption give the recorded m/s); nothing when no speed was recorded."""
    return "" if v.speed_mps is None else f" {mph(v.speed_mps):.0f} mph"


def _vehicle_title(v: Mover) -> str:
    speed = "speed not recorded" if v.speed_mps is None else \
        f"speed {mph_text(v.speed_mps)} ({_n(v.speed_mps)} m/s)"
    seen = "" if v.age_s is None else f", reported {v.age_s:g} s before"
    return (f"vehicle {v.id} ({v.type or 'type not recorded'}) at ({_n(v.x)}, {_n(v.y)}) m, "
            f"heading {_n(v.heading_deg)}°, {speed}{seen}")


def _road_users(pic: Picture, view: View, placer: Placer, wants: list[_Want]) -> list[str]:
    out = []
    for u in pic.road_users:
        if not drawn(u):
            continue
        x, y = view(*_at(u))
        out.append(f'<path class="road-user" d="M{f(x)},{f(y - 5)} L{f(x + 5)},{f(y)} L{f(x)},{f(y + 5)} '
                   f'L{f(x - 5)},{f(y)} Z" fill="{USER_COLOUR}"><title>{esc(u.id)} ({esc(u.type or "?")})'
                   "</title></path>")
        placer.block(Box(x - 5, y - 5, 10, 10))
        wants.append(_Want(2, _short(str(u.id)) + _speed(u), x, y, 6.0, USER_COLOUR))
    return out


def _arrow_head(x: float, y: float, a: float, colour: str) -> str:
    left = (x - 6 * math.cos(a - 0.5), y + 6 * math.sin(a - 0.5))
    right = (x - 6 * math.cos(a + 0.5), y + 6 * math.sin(a + 0.5))
    return (f'<polygon points="{f(x)},{f(y)} {f(left[0])},{f(left[1])} {f(right[0])},{f(right[1])}" '
            f'fill="{colour}"/>')


def _legend(view: View, lanes: bool) -> list[str]:
    y0 = H - LEGEND_H
    bar_m = _bar_metres(view.scale)
    bar_px = bar_m * view.scale
    out = [f'<rect x="0" y="{y0}" width="{W}" height="{LEGEND_H}" fill="#ffffff" stroke="#ccc"/>',
           f'<g class="legend" transform="translate(10,{y0 + 17})">',
           '<circle cx="6" cy="-4" r="6" fill="#7b1fa2"/><text x="16" y="0">incident vehicle</text>',
           '<circle cx="118" cy="-4" r="5" fill="#34495e"/><text x="128" y="0">other vehicle</text>',
           '<rect x="210" y="-10" width="14" height="12" fill="#2a6fdb" fill-opacity="0.25" stroke="#2a6fdb"/>'
           '<text x="228" y="0">monitor field of view</text>',
           '<path d="M365,-9 L370,-4 L365,1 L360,-4 Z" fill="#16a085"/><text x="376" y="0">road user</text>',
           f'<line x1="460" y1="-4" x2="{f(460 + bar_px)}" y2="-4" stroke="#111" stroke-width="2"/>'
           f'<text x="{f(466 + bar_px)}" y="0">{bar_m:g} m</text>',
           '<text x="0" y="20">signal lamps:</text>',
           legend_swatches(80, 20, legend_colours()),
           ('<rect x="530" y="11" width="12" height="10" fill="none" stroke="#f2c200" stroke-width="2"/>'
            '<text x="546" y="20">yellow box</text>' if lanes else ""),
           "</g>"]
    return out


def _bar_metres(scale: float) -> float:
    """A round length drawn between 40 and 150 px."""
    for m in (1, 2, 5, 10, 20, 25, 50, 100, 200, 500, 1000, 2000, 5000):
        if m * scale >= 40:
            return float(m)
    return 5000.0


def _short(text: str, limit: int = 18) -> str:
    return text if len(text) <= limit else text[:limit - 1] + "…"


def _n(value: float | None) -> str:
    return "?" if value is None else f(value)
