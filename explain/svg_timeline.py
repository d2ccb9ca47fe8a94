"""The seconds around an incident as an inline SVG: the vehicle's speed (its own entity.state
reports as a line, what monitors observed as crosses) above one colour band per signal approach of
its junction, on one time axis with the incident and the moments of its passage the history found
(crossing the stop line, entering and leaving the junction, standing still) marked.

Drawn from report_data.timeline only. Between two reports the speed is drawn as a straight line
and the colour as held: that is all the record says, and the points show where it says it. The
approach the vehicle came in on (when the approaches are named by compass point) is marked ▶.
Speeds are drawn in miles per hour, as the explanation and the Highway Code state them; each
point's tooltip also gives the m/s the producer recorded.
"""
from __future__ import annotations

from typing import Any

from .report_data import SECOND, facing_approach
from .svg import esc, f, fill
from .units import mph, mph_text

W = 640
LEFT, RIGHT, TOP = 92, 16, 30
PLOT_H = 140
BAND_H, BAND_GAP = 14, 5
AXIS_H = 34


def timeline_svg(tl: dict[str, Any], heading_deg: float | None = None) -> str:
    """The timeline as one <svg class="gaps-timeline"> element; `heading_deg` of the vehicle at
    the incident picks the approach it faced."""
    bands = list(tl["signals"].items())
    height = TOP + PLOT_H + AXIS_H + len(bands) * (BAND_H + BAND_GAP) + (12 if not bands else 0) + 8
    t0, t1 = tl["t_from"], tl["t_to"]
    span = max(t1 - t0, 1)

    def x(t: int) -> float:
        return LEFT + (min(max(t, t0), t1) - t0) / span * (W - LEFT - RIGHT)

    speeds = [mph(p["speed_mps"]) for p in tl["speed"] + tl["observed_speed"]]
    top = _nice_top(max(speeds, default=0.0))

    def y(mps: float) -> float:
        return TOP + PLOT_H - mph(mps) / top * PLOT_H

    def y_mph(v: float) -> float:
        return TOP + PLOT_H - v / top * PLOT_H

    label = (f"Speed of vehicle {tl['vehicle']} and signal colours at junction {tl['junction'] or '(none)'} "
             f"from {(t0 - tl['t']) / SECOND:g} s to +{(t1 - tl['t']) / SECOND:g} s around the incident")
    out = [f'<svg class="gaps-timeline" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {W} {height}" width="{W}" '
           f'height="{height}" role="img" aria-label="{esc(label)}" font-family="sans-serif" font-size="11">',
           f"<title>{esc(label)}</title>",
           f'<rect x="0" y="0" width="{W}" height="{height}" fill="#ffffff"/>']
    out += _legend()
    out += _speed_axis(top, y_mph)
    out += _speed_line(tl, x, y)
    base = TOP + PLOT_H + 8
    facing = facing_approach(heading_deg, [a for a, _ in bands])
    for i, (approach, changes) in enumerate(bands):
        out += _band(tl, approach, changes, base + i * (BAND_H + BAND_GAP), x, approach == facing)
    if not bands:
        out.append(f'<text x="{LEFT}" y="{base + 10}" fill="#666">no signal reported at this junction in this '
                   "window</text>")
    axis_y = base + len(bands) * (BAND_H + BAND_GAP) + (12 if not bands else 0)
    out += _time_axis(tl, x, axis_y)
    out += _moments(tl, x, axis_y)
    ix = x(tl["t"])
    out.append(f'<line class="incident-time" x1="{f(ix)}" y1="{TOP - 4}" x2="{f(ix)}" y2="{f(axis_y)}" '
               'stroke="#7b1fa2" stroke-width="1.5" stroke-dasharray="4 3"/>')
    out.append(f'<text x="{f(ix + 3)}" y="{TOP + 8}" fill="#7b1fa2">incident</text>')
    out.append("</svg>")
    return "".join(out)


def _nice_top(value: float) -> float:
    """The axis's top in mph: the first round figure 10% above the fastest point."""
    for top in (10, 20, 30, 40, 50, 60, 80, 100, 120, 160, 200):
        if value * 1.1 <= top:
            return float(top)
    return float(int(value * 1.2) + 1)


def _legend() -> list[str]:
    return ['<g class="legend" transform="translate(0,14)">',
            f'<line x1="{LEFT}" y1="-4" x2="{LEFT + 22}" y2="-4" stroke="#7b1fa2" stroke-width="2"/>'
            f'<circle cx="{LEFT + 11}" cy="-4" r="2.5" fill="#7b1fa2"/>'
            f'<text x="{LEFT + 28}" y="0">speed the vehicle reported (entity.state)</text>',
            f'<path d="M{LEFT + 276},-8 l6,6 m0,-6 l-6,6" stroke="#2a6fdb" stroke-width="2"/>'
            f'<text x="{LEFT + 288}" y="0">speed a monitor observed</text>', "</g>"]


def _speed_axis(top: float, y) -> list[str]:
    out = [f'<text x="8" y="{TOP + PLOT_H / 2}" transform="rotate(-90 12 {TOP + PLOT_H / 2})" '
           'text-anchor="middle">speed (mph)</text>']
    for i in range(5):
        v = top * i / 4
        out.append(f'<line x1="{LEFT}" y1="{f(y(v))}" x2="{W - RIGHT}" y2="{f(y(v))}" stroke="#e3e3e3"/>'
                   f'<text x="{LEFT - 6}" y="{f(y(v) + 4)}" text-anchor="end">{v:g}</text>')
    out.append(f'<line x1="{LEFT}" y1="{TOP}" x2="{LEFT}" y2="{TOP + PLOT_H}" stroke="#888"/>')
    return out


def _speed_line(tl: dict[str, Any], x, y) -> list[str]:
    out = []
    own = tl["speed"]
    if own:
        pts = [(x(p["t"]), y(p["speed_mps"])) for p in own]
        if own[-1]["t"] < tl["t_to"]:       # held after the last report, dashed: not recorded, only not changed
            out.append(f'<line x1="{f(pts[-1][0])}" y1="{f(pts[-1][1])}" x2="{f(x(tl["t_to"]))}" y2="{f(pts[-1][1])}" '
                       'stroke="#7b1fa2" stroke-width="1" stroke-dasharray="2 3"/>')
        out.append(f'<polyline class="speed" points="{" ".join(f"{f(a)},{f(b)}" for a, b in pts)}" fill="none" '
                   'stroke="#7b1fa2" stroke-width="2"/>')
        for p, (a, b) in zip(own, pts):
            title = (f"{_rel(tl, p['t'])}: {mph_text(p['speed_mps'])} ({p['speed_mps']:g} m/s, "
                     f"vehicle/{tl['vehicle']} #{p['seq']})")
            out.append(f'<circle cx="{f(a)}" cy="{f(b)}" r="3" fill="#7b1fa2"><title>{esc(title)}</title></circle>')
        out += _speed_at_incident(tl, own, x, y)
    for p in tl["observed_speed"]:
        a, b = x(p["t"]), y(p["speed_mps"])
        title = (f"{_rel(tl, p['t'])}: {mph_text(p['speed_mps'])} ({p['speed_mps']:g} m/s) observed by "
                 f"{p['monitor']} #{p['seq']}")
        out.append(f'<path class="observed" d="M{f(a - 4)},{f(b - 4)} l8,8 m0,-8 l-8,8" stroke="#2a6fdb" '
                   f'stroke-width="2"><title>{esc(title)}</title></path>')
    if not own and not tl["observed_speed"]:
        out.append(f'<text x="{LEFT + 10}" y="{TOP + PLOT_H / 2}" fill="#666">no speed recorded for vehicle '
                   f'{esc(tl["vehicle"])} in this window</text>')
    return out


def _speed_at_incident(tl: dict[str, Any], own: list[dict], x, y) -> list[str]:
    """The speed last reported at or before the incident, written beside its point (a printed
    page has no tooltip)."""
    last = next((p for p in reversed(own) if p["t"] <= tl["t"]), None)
    if last is None:
        return []
    return [f'<text class="speed-value" x="{f(x(last["t"]) - 6)}" y="{f(y(last["speed_mps"]) - 7)}" '
            f'text-anchor="end" fill="#7b1fa2">{esc(mph_text(last["speed_mps"]))}</text>']


def _band(tl: dict[str, Any], approach: str, changes: list[dict], top: float, x, facing: bool) -> list[str]:
    name = f"{tl['junction']} {approach}"
    name = name if len(name) <= 13 else name[:12] + "…"
    weight = ' font-weight="bold"' if facing else ""
    mark = "▶ " if facing else ""
    out = [f'<text x="{LEFT - 6}" y="{f(top + BAND_H - 3)}" text-anchor="end"{weight}>{mark}{esc(name)}</text>']
    for i, c in enumerate(changes):
        end = changes[i + 1]["t"] if i + 1 < len(changes) else tl["t_to"]
        a, b = x(c["t"]), x(end)
        if b <= a:
            continue
        title = f"signal {tl['junction']} {approach}: {c['colour']} from {_rel(tl, c['t'])}"
        out.append(f'<rect class="signal-band" x="{f(a)}" y="{f(top)}" width="{f(b - a)}" height="{BAND_H}" '
                   f'fill="{fill(c["colour"])}" stroke="#333" stroke-width="0.5"><title>{esc(title)}</title></rect>')
    return out


def _moments(tl: dict[str, Any], x, axis_y: float) -> list[str]:
    """The moments of the vehicle's passage the history found (crossing the stop line, entering
    the junction...) as labelled vertical lines across the speed and the signal bands, so the
    light at the crossing reads off the band under it."""
    out = []
    for i, m in enumerate(tl.get("moments") or []):
        mx = x(m["t"])
        label = f"{m['what']} ({_rel(tl, m['t'])})"
        out.append(f'<line class="moment" x1="{f(mx)}" y1="{TOP}" x2="{f(mx)}" y2="{f(axis_y)}" stroke="#222" '
                   f'stroke-width="1"><title>{esc(label)}</title></line>')
        out.append(f'<text class="moment-label" x="{f(mx + 3)}" y="{TOP + 22 + 12 * (i % 4)}" fill="#222" '
                   f'font-size="10">{esc(m["what"])}</text>')
    return out


def _time_axis(tl: dict[str, Any], x, axis_y: float) -> list[str]:
    out = [f'<line x1="{LEFT}" y1="{f(axis_y)}" x2="{W - RIGHT}" y2="{f(axis_y)}" stroke="#888"/>']
    step = 5 * SECOND
    first = tl["t"] - ((tl["t"] - tl["t_from"]) // step) * step
    t = first
    while t <= tl["t_to"]:
        out.append(f'<line x1="{f(x(t))}" y1="{f(axis_y)}" x2="{f(x(t))}" y2="{f(axis_y + 4)}" stroke="#888"/>'
                   f'<text x="{f(x(t))}" y="{f(axis_y + 16)}" text-anchor="middle">{_rel(tl, t)}</text>')
        t += step
    out.append(f'<text x="{W - RIGHT}" y="{f(axis_y + 30)}" text-anchor="end" fill="#555">seconds from the '
               "incident</text>")
    return out


def _rel(tl: dict[str, Any], t: int) -> str:
    d = (t - tl["t"]) / SECOND
    return "0 s" if d == 0 else f"{d:+g} s"
