"""The scene at an incident as an inline SVG: roads, junctions, the colour each signal approach
showed, every vehicle present (the incident's highlighted) pointing where it headed, and each
monitor's field of view, scaled to fit around the incident, with a legend and a scale bar.

Drawn from report_data.scene_picture only. World coordinates are metres with y up and headings
counter-clockwise from +x (as sim_replay and the Foxglove export read them); the SVG's y runs
down, so points are flipped here and arcs are drawn as polylines, leaving no sweep flag to get
wrong. The view is centred on what matters (the vehicle, its junction, the monitors watching it,
road users within 120 m), not on the whole map, so a 400 m road does not shrink the junction to a
dot; roads are clipped to the frame. Only road users present at the moment are drawn (a position
older than presence.FRESH_NS is not where the road user was), and the labels are placed by
labels.py so that none covers another.
"""
from __future__ import annotations

import math
from typing import Any, NamedTuple

from .labels import Box, Label, Placer
from .report_data import APPROACH_DIRECTIONS, vehicle_junction
from .svg import esc, f, fill, legend_swatches
from .units import mph_text

W, H = 640, 440
PAD = 28
LEGEND_H = 44
NEAR_M = 120.0
MIN_SPAN_M = 50.0
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


class _View:
    """World metres to SVG pixels: one scale for both axes, the focus box centred."""

    def __init__(self, points: list[tuple[float, float]]) -> None:
        xs, ys = [p[0] for p in points] or [0.0], [p[1] for p in points] or [0.0]
        cx, cy = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2
        span_x = max(max(xs) - min(xs), MIN_SPAN_M) * 1.15
        span_y = max(max(ys) - min(ys), MIN_SPAN_M) * 1.15
        self.scale = min((W - 2 * PAD) / span_x, (H - LEGEND_H - 2 * PAD) / span_y)
        self.cx, self.cy = cx, cy

    def __call__(self, x: float, y: float) -> tuple[float, float]:
        return (W / 2 + (x - self.cx) * self.scale, PAD + (H - LEGEND_H - 2 * PAD) / 2 - (y - self.cy) * self.scale)


def scene_svg(pic: dict[str, Any], number: int = 1) -> str:
    """The picture as one <svg class="gaps-scene"> element; `number` keeps its clip path's id
    apart from the other pictures of the same page."""
    view = _View(_focus(pic))
    junction = vehicle_junction(pic)
    me = next((v for v in pic["vehicles"] if v["incident"]), None)
    clip = f"scene-clip-{int(number)}"
    label = f"Scene at the incident ({pic['offset']} from the run start): vehicle {pic['vehicle']}"
    out = [f'<svg class="gaps-scene" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {W} {H}" width="{W}" '
           f'height="{H}" role="img" aria-label="{esc(label)}" font-family="sans-serif" font-size="11">',
           f"<title>{esc(label)}</title>",
           f'<defs><clipPath id="{clip}"><rect x="0" y="0" width="{W}" height="{H - LEGEND_H}"/>'
           "</clipPath></defs>",
           f'<rect x="0" y="0" width="{W}" height="{H}" fill="#f4f1ea"/>',
           f'<g clip-path="url(#{clip})">']
    placer = Placer(Box(0, 0, W, H - LEGEND_H))
    wants: list[_Want] = []
    out += _roads(pic, view)
    out += _monitors(pic, view, placer, wants)
    out += _junctions(pic, view, junction, placer, wants)
    out += _signals(pic, view, placer)
    out += _road_users(pic, view, placer, wants)
    out += _vehicles(pic, view, placer, wants)
    missing = _not_drawn(me, pic["vehicle"])
    if missing:
        placer.block(Box(0, 0, W, PAD + 6))
        out.append(f'<text x="{W / 2}" y="{PAD}" text-anchor="middle" fill="#a40000">{esc(missing)}</text>')
    out += _labels(placer, wants)
    out.append("</g>")
    out += _legend(view)
    out.append("</svg>")
    return "".join(out)


def drawn(item: dict[str, Any]) -> bool:
    """A vehicle or road user the picture shows: placed, and present at the moment (presence.py)."""
    return item["x"] is not None and item["y"] is not None and item.get("present", True)


def _not_drawn(me: dict[str, Any] | None, vehicle: str) -> str | None:
    """Why the incident's own vehicle is not in the picture, if it is not."""
    if me is None or me["x"] is None:
        return f"vehicle {vehicle} has no recorded position at this time"
    if not drawn(me):
        age = "" if me.get("age_s") is None else f" is {me['age_s']:g} s old"
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


def _focus(pic: dict[str, Any]) -> list[tuple[float, float]]:
    """The points the view must hold."""
    me = next((v for v in pic["vehicles"] if v["incident"] and drawn(v)), None)
    junction = vehicle_junction(pic)
    pts: list[tuple[float, float]] = []
    if me is not None:
        pts.append((me["x"], me["y"]))
    pts += [(j["x"], j["y"]) for j in pic["junctions"] if j["id"] == junction]
    for m in pic["monitors"]:
        if m["x"] is not None and m["y"] is not None and (m["watching"] or (junction and m["junction"] == junction)):
            pts.append((m["x"], m["y"]))
            pts += _wedge_points(m)[1::4]
    if me is not None:
        for other in pic["vehicles"] + pic["road_users"]:
            if drawn(other) and math.hypot(other["x"] - me["x"], other["y"] - me["y"]) <= NEAR_M:
                pts.append((other["x"], other["y"]))
    if not pts:        # nothing to centre on: the whole map
        pts = [(j["x"], j["y"]) for j in pic["junctions"]]
        pts += [(m["x"], m["y"]) for m in pic["monitors"] if m["x"] is not None and m["y"] is not None]
        pts += [(v["x"], v["y"]) for v in pic["vehicles"] if drawn(v)]
    return pts


def _wedge_points(m: dict[str, Any]) -> list[tuple[float, float]]:
    """The monitor's position then its field-of-view arc (world metres)."""
    heading, fov, reach = m["heading_deg"], m["fov_deg"], m["range_m"]
    if heading is None or reach is None or reach <= 0:
        return []
    fov = 360.0 if fov is None else max(0.0, min(fov, 360.0))
    steps = 24
    start = math.radians(heading - fov / 2)
    arc = [(m["x"] + reach * math.cos(start + math.radians(fov) * i / steps),
            m["y"] + reach * math.sin(start + math.radians(fov) * i / steps)) for i in range(steps + 1)]
    return [(m["x"], m["y"])] + arc


def _roads(pic: dict[str, Any], view: _View) -> list[str]:
    width = max(6.0, 7.0 * view.scale)
    out = []
    for r in pic["roads"]:
        (x1, y1), (x2, y2) = view(*r["from"]), view(*r["to"])
        out.append(f'<line class="road" x1="{f(x1)}" y1="{f(y1)}" x2="{f(x2)}" y2="{f(y2)}" stroke="#b9b4aa" '
                   f'stroke-width="{f(width)}" stroke-linecap="butt"><title>road {esc(r["id"])}</title></line>')
        out.append(f'<line x1="{f(x1)}" y1="{f(y1)}" x2="{f(x2)}" y2="{f(y2)}" stroke="#ffffff" '
                   'stroke-width="1" stroke-dasharray="6 6"/>')
    return out


def _junctions(pic: dict[str, Any], view: _View, focus: str | None, placer: Placer,
               wants: list[_Want]) -> list[str]:
    out = []
    size = max(10.0, 9.0 * view.scale)
    for j in pic["junctions"]:
        x, y = view(j["x"], j["y"])
        stroke = "#333" if j["id"] == focus else "#888"
        out.append(f'<rect class="junction" x="{f(x - size / 2)}" y="{f(y - size / 2)}" width="{f(size)}" '
                   f'height="{f(size)}" fill="#d8d2c4" stroke="{stroke}" stroke-width="1">'
                   f'<title>junction {esc(j["id"])} ({esc(j["control"] or "control not recorded")})</title></rect>')
        wants.append(_Want(4, f"junction {_short(str(j['id']))}", x, y, size * 0.75, "#333"))
    return out


def _signals(pic: dict[str, Any], view: _View, placer: Placer) -> list[str]:
    """One lamp per approach, placed on the side the traffic comes from; labels keep off it."""
    where = {j["id"]: (j["x"], j["y"]) for j in pic["junctions"]}
    by_junction: dict[Any, list[dict]] = {}
    for s in pic["signals"]:
        by_junction.setdefault(s["junction"], []).append(s)
    out = []
    dist = max(10.0, 26.0 / view.scale)            # metres: about 26 px out from the centre
    side = 16.0 / view.scale                       # and 16 px to the approaching driver's left (UK kerb side)
    for junction, shown in by_junction.items():
        if junction not in where:
            continue
        jx, jy = where[junction]
        for i, s in enumerate(shown):
            name = s["approach"].lower() if isinstance(s["approach"], str) else ""
            a = math.radians(APPROACH_DIRECTIONS.get(name, 45.0 + 90.0 * i))
            x, y = view(jx + dist * math.cos(a) + side * math.cos(a - math.pi / 2),
                        jy + dist * math.sin(a) + side * math.sin(a - math.pi / 2))
            title = f"signal {junction} {s['approach']}: {s['colour']}"
            placer.block(Box(x - 7, y - 11, 14, 22))
            out.append(f'<g class="signal"><title>{esc(title)}</title>'
                       f'<rect x="{f(x - 7)}" y="{f(y - 11)}" width="14" height="22" rx="3" fill="#222"/>'
                       f'<circle cx="{f(x)}" cy="{f(y)}" r="5.5" fill="{fill(s["colour"])}" stroke="#000" '
                       'stroke-width="0.5"/></g>')
    return out


def _monitors(pic: dict[str, Any], view: _View, placer: Placer, wants: list[_Want]) -> list[str]:
    out = []
    for m in pic["monitors"]:
        if m["x"] is None or m["y"] is None:
            continue
        wedge = _wedge_points(m)
        if wedge:
            pts = " ".join(f"{f(a)},{f(b)}" for a, b in (view(*p) for p in wedge))
            out.append(f'<polygon class="fov" points="{pts}" fill="#2a6fdb" fill-opacity="0.12" stroke="#2a6fdb" '
                       f'stroke-opacity="0.6" stroke-width="1"><title>{esc(_fov_title(m))}</title></polygon>')
        x, y = view(m["x"], m["y"])
        out.append(f'<rect class="monitor" x="{f(x - 5)}" y="{f(y - 5)}" width="10" height="10" fill="#2a6fdb">'
                   f"<title>{esc(_fov_title(m))}</title></rect>")
        placer.block(Box(x - 5, y - 5, 10, 10))
        wants.append(_Want(3, _short(str(m["id"])), x, y, 7.0, MONITOR_COLOUR))
    return out


def _fov_title(m: dict[str, Any]) -> str:
    return (f"{m['id']}: field of view {_n(m['fov_deg'])}° heading {_n(m['heading_deg'])}°, "
            f"range {_n(m['range_m'])} m")


def _vehicles(pic: dict[str, Any], view: _View, placer: Placer, wants: list[_Want]) -> list[str]:
    out = []
    for v in sorted(pic["vehicles"], key=lambda v: v["incident"]):      # the incident's drawn last, on top
        if not drawn(v):
            continue
        x, y = view(v["x"], v["y"])
        r = 7 if v["incident"] else 5
        colour = INCIDENT_COLOUR if v["incident"] else VEHICLE_COLOUR
        cls = "vehicle incident" if v["incident"] else "vehicle"
        if v["heading_deg"] is not None:
            a = math.radians(v["heading_deg"])
            hx, hy = x + 18 * math.cos(a), y - 18 * math.sin(a)
            out.append(f'<line x1="{f(x)}" y1="{f(y)}" x2="{f(hx)}" y2="{f(hy)}" stroke="{colour}" stroke-width="2"/>')
            out.append(_arrow_head(hx, hy, a, colour))
            placer.block(Box(min(x, hx) - 4, min(y, hy) - 4, abs(hx - x) + 8, abs(hy - y) + 8))
        ring = (f'<circle cx="{f(x)}" cy="{f(y)}" r="{r + 5}" fill="none" stroke="{INCIDENT_COLOUR}" '
                'stroke-width="2" stroke-dasharray="3 2"/>' if v["incident"] else "")
        out.append(f'<g class="{cls}">{ring}<circle cx="{f(x)}" cy="{f(y)}" r="{r}" fill="{colour}" stroke="#fff" '
                   f'stroke-width="1.5"><title>{esc(_vehicle_title(v))}</title></circle></g>')
        reach = r + 5 if v["incident"] else r
        placer.block(Box(x - reach, y - reach, 2 * reach, 2 * reach))
        text = _short(str(v["id"])) + (" " + _short(str(v["type"])) if v["type"] else "")
        wants.append(_Want(0 if v["incident"] else 1, text, x, y, reach + 2, colour, v["incident"]))
    return out


def _vehicle_title(v: dict[str, Any]) -> str:
    speed = "speed not recorded" if v["speed_mps"] is None else \
        f"speed {mph_text(v['speed_mps'])} ({_n(v['speed_mps'])} m/s)"
    seen = "" if v.get("age_s") is None else f", reported {v['age_s']:g} s before"
    return (f"vehicle {v['id']} ({v['type'] or 'type not recorded'}) at ({_n(v['x'])}, {_n(v['y'])}) m, "
            f"heading {_n(v['heading_deg'])}°, {speed}{seen}")


def _road_users(pic: dict[str, Any], view: _View, placer: Placer, wants: list[_Want]) -> list[str]:
    out = []
    for u in pic["road_users"]:
        if not drawn(u):
            continue
        x, y = view(u["x"], u["y"])
        out.append(f'<path class="road-user" d="M{f(x)},{f(y - 5)} L{f(x + 5)},{f(y)} L{f(x)},{f(y + 5)} '
                   f'L{f(x - 5)},{f(y)} Z" fill="{USER_COLOUR}"><title>{esc(u["id"])} ({esc(u["type"] or "?")})'
                   "</title></path>")
        placer.block(Box(x - 5, y - 5, 10, 10))
        wants.append(_Want(2, _short(str(u["id"])), x, y, 6.0, USER_COLOUR))
    return out


def _arrow_head(x: float, y: float, a: float, colour: str) -> str:
    left = (x - 6 * math.cos(a - 0.5), y + 6 * math.sin(a - 0.5))
    right = (x - 6 * math.cos(a + 0.5), y + 6 * math.sin(a + 0.5))
    return (f'<polygon points="{f(x)},{f(y)} {f(left[0])},{f(left[1])} {f(right[0])},{f(right[1])}" '
            f'fill="{colour}"/>')


def _legend(view: _View) -> list[str]:
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
           legend_swatches(80, 20, [("red", fill("red")), ("red+amber", fill("red_amber")), ("amber", fill("amber")),
                                   ("green", fill("green")), ("off", fill("off")), ("other", fill(None))]),
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
