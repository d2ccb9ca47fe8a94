"""The seconds around an incident as an inline SVG: the act on one time axis. Stacked panels share
one x scale, so a moment reads straight down through all of them: the vehicle's speed (its own
entity.state reports as a line, what monitors observed as crosses, and, where the incident says
the vehicle would force or endanger another road user, that road user's speed), its distance to
the stop line of its approach (the reasoner's passage, explain/act_data.py), and one colour band
per signal approach of its junction, with the incident and the moments of its passage the
history found (standing still, crossing the stop line, entering and leaving the junction) as
labelled lines across them.

Drawn from a timeline_parts.ActTimeline (the reasoner's window, with act_data's `to_line` and
`other`) only. Between two reports a value is drawn as a straight line and a colour as held: that
is all the record says, and the points show where it says it. The approach the vehicle came in on
(when the approaches are named by compass point) is marked ▶. Speeds are drawn in miles per hour,
as the explanation and the Highway Code state them; each point's tooltip also gives the m/s the
producer recorded.

The moments' labels sit in rows above the plot (labels.in_rows): none overlaps another, none is
cut at the picture's edge, and no line runs through a label; each label's box is written in its
`data-box` (x y width height) for the tests that check that, in Python and in a browser.
"""
from __future__ import annotations

import math
from typing import Callable

from reasoner.timelines import Phase

from .labels import Box, in_rows, text_size
from .report_data import SECOND, facing_approach
from .svg import colour_word, esc, f, fill
from .timeline_parts import ActTimeline, Moment, ToLine
from .units import mph, mph_text

W = 640
LEFT, RIGHT, TOP = 92, 16, 8
PLOT_H = 100              # the speed panel
LINE_H = 56               # the distance-to-the-line panel
PANEL_GAP = 10
BAND_H, BAND_GAP = 12, 4
AXIS_H = 34
LEGEND_ROW = 16
LABEL_SIZE, ROW_H = 10.0, 13.0
OWN, OBSERVED, OTHER, DISTANCE, INCIDENT = "#7b1fa2", "#2a6fdb", "#d35400", "#00695c", "#7b1fa2"
LINE_WORDS = {"signal": "stop line", "stop_sign": "Stop line", "give_way": "Give Way line"}


def timeline_svg(tl: ActTimeline, heading_deg: float | None = None) -> str:
    """The timeline as one <svg class="gaps-timeline"> element; `heading_deg` of the vehicle at
    the incident picks the approach it faced."""
    t0, t1 = tl.window.t_from, tl.window.t_to
    span = max(t1 - t0, 1)

    def x(t: int) -> float:
        return LEFT + (min(max(t, t0), t1) - t0) / span * (W - LEFT - RIGHT)

    legend, legend_h = _legend(tl)
    flags = _flags(tl, x)
    rows = max((fl.row for fl in flags), default=-1) + 1
    plot_top = TOP + legend_h + rows * ROW_H + 6
    to_line = tl.to_line
    line_top = plot_top + PLOT_H + PANEL_GAP
    bands = [(a.approach, a.phases) for a in tl.window.signals]
    band_top = line_top + (LINE_H if to_line else 14) + PANEL_GAP
    axis_y = band_top + len(bands) * (BAND_H + BAND_GAP) + (12 if not bands else 0)
    key, key_h = _key(tl, flags, axis_y)
    height = axis_y + AXIS_H + 4 + key_h

    label = (f"Vehicle {tl.window.vehicle} from {(t0 - tl.window.t) / SECOND:g} s to +{(t1 - tl.window.t) / SECOND:g} s around "
             f"the incident on one time axis: its speed{_other_words(tl)}, its distance to the stop line and the "
             f"signal colours at junction {tl.window.junction or '(none)'}")
    out = [f'<svg class="gaps-timeline" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {W} {f(height)}" '
           f'width="{W}" height="{f(height)}" role="img" aria-label="{esc(label)}" font-family="sans-serif" '
           f'font-size="11">', f"<title>{esc(label)}</title>",
           f'<rect x="0" y="0" width="{W}" height="{f(height)}" fill="#ffffff"/>']
    out += legend
    top = _nice_top(max([mph(v) for v in _speeds(tl)], default=0.0))

    def y(mps: float) -> float:
        return plot_top + PLOT_H - mph(mps) / top * PLOT_H

    out += _speed_axis(top, plot_top)
    out += _speed_lines(tl, x, y)
    out += _distance(tl, to_line, x, line_top)
    facing = facing_approach(heading_deg, [a for a, _ in bands])
    for i, (approach, changes) in enumerate(bands):
        out += _band(tl, approach, changes, band_top + i * (BAND_H + BAND_GAP), x, approach == facing)
    if not bands:
        out.append(f'<text x="{LEFT}" y="{band_top + 10}" fill="#666">no signal reported at this junction in this '
                   "window</text>")
    out += _time_axis(tl, x, axis_y)
    out += _lines(tl, flags, x, plot_top, axis_y)
    out += key
    out += _speed_at_incident(tl, flags, x, y, plot_top)
    out.append("</svg>")
    return "".join(out)


def _speeds(tl: ActTimeline) -> list[float]:
    """Every speed the panel draws: the vehicle's own, the monitors', the other road user's."""
    other = tl.other.speed if tl.other else ()
    return ([p.speed_mps for p in tl.window.speed] + [p.speed_mps for p in tl.window.observed_speed] +
            [p.speed_mps for p in other if p.speed_mps is not None])


def _other_words(tl: ActTimeline) -> str:
    other = tl.other
    return f" and the speed of {other.user}, whom it {other.how}" if other else ""


def _nice_top(value: float) -> float:
    """The axis's top in mph: the first round figure 10% above the fastest point."""
    for top in (10, 20, 30, 40, 50, 60, 80, 100, 120, 160, 200):
        if value * 1.1 <= top:
            return float(top)
    return float(int(value * 1.2) + 1)


# --- legend -------------------------------------------------------------------------------------------

def _legend(tl: ActTimeline) -> tuple[list[str], float]:
    """The legend's entries, flowed into rows as wide as the plot (each given its text's room)."""
    items = [(f'<line x1="0" y1="-4" x2="22" y2="-4" stroke="{OWN}" stroke-width="2"/>'
              f'<circle cx="11" cy="-4" r="2.5" fill="{OWN}"/>', "speed the vehicle reported (entity.state)"),
             (f'<path d="M8,-8 l6,6 m0,-6 l-6,6" stroke="{OBSERVED}" stroke-width="2"/>', "speed a monitor observed")]
    other = tl.other
    if other:
        who = f"{other.type} {other.user}" if other.type else str(other.user)
        items.append((f'<line x1="0" y1="-4" x2="22" y2="-4" stroke="{OTHER}" stroke-width="2" '
                      f'stroke-dasharray="5 3"/>', f"speed of {who}, whom {tl.window.vehicle} {other.how}"))
    if tl.to_line:
        items.append((f'<line x1="0" y1="-4" x2="22" y2="-4" stroke="{DISTANCE}" stroke-width="2"/>',
                      f"distance to the {_line_word(tl.to_line)}"))
    out, left, row = ['<g class="legend">'], float(LEFT), 0
    for mark, text in items:
        width = 28 + text_size(text, 11)[0]
        if left > LEFT and left + width > W - RIGHT:
            left, row = float(LEFT), row + 1
        base = TOP + 10 + row * LEGEND_ROW
        out.append(f'<g transform="translate({f(left)},{f(base)})">{mark}<text x="28" y="0">{esc(text)}</text></g>')
        left += width + 16
    return out + ["</g>"], (row + 1) * LEGEND_ROW


def _line_word(to_line: ToLine) -> str:
    return LINE_WORDS.get(to_line.kind or "", "stop line")


# --- speed --------------------------------------------------------------------------------------------

def _speed_axis(top: float, plot_top: float) -> list[str]:
    def y(v: float) -> float:
        return plot_top + PLOT_H - v / top * PLOT_H
    mid = plot_top + PLOT_H / 2
    out = [f'<text x="8" y="{f(mid)}" transform="rotate(-90 12 {f(mid)})" text-anchor="middle">speed (mph)</text>']
    for i in range(5):
        v = top * i / 4
        out.append(f'<line x1="{LEFT}" y1="{f(y(v))}" x2="{W - RIGHT}" y2="{f(y(v))}" stroke="#e3e3e3"/>'
                   f'<text x="{LEFT - 6}" y="{f(y(v) + 4)}" text-anchor="end">{v:g}</text>')
    out.append(f'<line x1="{LEFT}" y1="{f(plot_top)}" x2="{LEFT}" y2="{f(plot_top + PLOT_H)}" stroke="#888"/>')
    return out


def _speed_lines(tl: ActTimeline, x: Callable, y: Callable) -> list[str]:
    out = []
    own = tl.window.speed
    if own:
        pts = [(x(p.t), y(p.speed_mps)) for p in own]
        if own[-1].t < tl.window.t_to:       # held after the last report, dashed: not recorded, only not changed
            out.append(f'<line x1="{f(pts[-1][0])}" y1="{f(pts[-1][1])}" x2="{f(x(tl.window.t_to))}" y2="{f(pts[-1][1])}" '
                       f'stroke="{OWN}" stroke-width="1" stroke-dasharray="2 3"/>')
        out.append(f'<polyline class="speed" points="{" ".join(f"{f(a)},{f(b)}" for a, b in pts)}" fill="none" '
                   f'stroke="{OWN}" stroke-width="2"/>')
        for p, (a, b) in zip(own, pts):
            title = (f"{_rel(tl, p.t)}: {mph_text(p.speed_mps)} ({p.speed_mps:g} m/s, "
                     f"vehicle/{tl.window.vehicle} #{p.seq})")
            out.append(f'<circle cx="{f(a)}" cy="{f(b)}" r="3" fill="{OWN}"><title>{esc(title)}</title></circle>')
    for o in tl.window.observed_speed:
        a, b = x(o.t), y(o.speed_mps)
        title = (f"{_rel(tl, o.t)}: {mph_text(o.speed_mps)} ({o.speed_mps:g} m/s) observed by "
                 f"{o.monitor} #{o.seq}")
        out.append(f'<path class="observed" d="M{f(a - 4)},{f(b - 4)} l8,8 m0,-8 l-8,8" stroke="{OBSERVED}" '
                   f'stroke-width="2"><title>{esc(title)}</title></path>')
    out += _other_speed(tl, x, y)
    if not own and not tl.window.observed_speed:
        out.append(f'<text x="{LEFT + 10}" y="{f(y(0) - PLOT_H / 2)}" fill="#666">no speed recorded for vehicle '
                   f'{esc(tl.window.vehicle)} in this window</text>')
    return out


def _other_speed(tl: ActTimeline, x: Callable, y: Callable) -> list[str]:
    """The speed of the road user the vehicle would force or endanger, dashed, in its own colour."""
    other = tl.other
    points = [p for p in (other.speed if other else ()) if p.speed_mps is not None]
    if not points or other is None:
        return []
    pts = [(x(p.t), y(p.speed_mps)) for p in points]
    out = [f'<polyline class="other-speed" points="{" ".join(f"{f(a)},{f(b)}" for a, b in pts)}" fill="none" '
           f'stroke="{OTHER}" stroke-width="2" stroke-dasharray="5 3"/>']
    for p, (a, b) in zip(points, pts):
        title = (f"{_rel(tl, p.t)}: {other.user} at {mph_text(p.speed_mps)} ({p.speed_mps:g} m/s, "
                 f"{p.src} #{p.seq})")
        out.append(f'<circle class="other-point" cx="{f(a)}" cy="{f(b)}" r="2.5" fill="{OTHER}">'
                   f"<title>{esc(title)}</title></circle>")
    return out


def _speed_at_incident(tl: ActTimeline, flags: list, x: Callable, y: Callable, plot_top: float) -> list[str]:
    """The speed last reported at or before the incident, written beside its point (a printed
    page has no tooltip): above it, to whichever side and as near as no moment's line runs
    through it (the lines cross the whole panel, so only their x matters)."""
    last = next((p for p in reversed(tl.window.speed) if p.t <= tl.window.t), None)
    if last is None:
        return []
    text = mph_text(last.speed_mps)
    w, h = text_size(text, 11.0)
    px, py = x(last.t), y(last.speed_mps)
    lines = [fl.at for fl in flags]
    frame = Box(LEFT + 2, plot_top, W - RIGHT - LEFT - 2, PLOT_H)
    spots = [Box(left, top, w, h) for shift in range(0, 400, 4)
             for left in (px + 6 + shift, px - 6 - w - shift) for top in (py - 6 - h, py + 6)]
    box = next((b for b in spots if b.within(frame) and not any(b.x - 2 <= a <= b.x + b.w + 2 for a in lines)),
               next((b for b in spots if b.within(frame)), spots[0]))
    return [f'<text class="speed-value" x="{f(box.x)}" y="{f(box.y + 11.0 * 0.95)}" fill="{OWN}" '
            f'data-box="{f(box.x)} {f(box.y)} {f(box.w)} {f(box.h)}">{esc(text)}</text>']


# --- distance to the line -----------------------------------------------------------------------------

def _distance(tl: ActTimeline, to_line: ToLine | None, x: Callable, top: float) -> list[str]:
    """Metres to the stop line at each sample of the passage (above the line's zero: before it;
    below: past it), on a scale of round figures."""
    if not to_line:
        return [f'<text x="{LEFT}" y="{f(top + 10)}" fill="#666">no stop line on vehicle {esc(tl.window.vehicle)}\'s '
                "way in this window</text>"]
    points = to_line.points
    lo, hi, step = _nice_range(min(min(p.m for p in points), 0.0), max(max(p.m for p in points), 0.0))

    def y(m: float) -> float:
        return top + (hi - m) / (hi - lo) * LINE_H
    mid = top + LINE_H / 2
    word = _line_word(to_line)
    out = [f'<text x="8" y="{f(mid)}" transform="rotate(-90 12 {f(mid)})" text-anchor="middle" font-size="10">'
           f"to the line (m)</text>"]
    v = lo
    while v <= hi + 1e-9:
        zero = abs(v) < 1e-9
        stroke = ' stroke="#a40000" stroke-width="1.5"' if zero else ' stroke="#e3e3e3"'
        out.append(f'<line x1="{LEFT}" y1="{f(y(v))}" x2="{W - RIGHT}" y2="{f(y(v))}"{stroke}/>'
                   f'<text x="{LEFT - 6}" y="{f(y(v) + 4)}" text-anchor="end" fill="{"#a40000" if zero else "#333"}"'
                   f'>{"line 0" if zero else f"{v:g}"}</text>')
        v += step
    out.append(f'<line x1="{LEFT}" y1="{f(top)}" x2="{LEFT}" y2="{f(top + LINE_H)}" stroke="#888"/>')
    pts = [(x(p.t), y(p.m)) for p in points]
    out.append(f'<polyline class="to-line" points="{" ".join(f"{f(a)},{f(b)}" for a, b in pts)}" fill="none" '
               f'stroke="{DISTANCE}" stroke-width="2"/>')
    for p, (a, b) in zip(points, pts):
        where = f"{p.m:g} m before the {word}" if p.m >= 0 else f"{-p.m:g} m past the {word}"
        title = f"{_rel(tl, p.t)}: {where} of the {to_line.approach} approach ({p.src} #{p.seq})"
        out.append(f'<circle class="to-line-point" cx="{f(a)}" cy="{f(b)}" r="2" fill="{DISTANCE}">'
                   f"<title>{esc(title)}</title></circle>")
    return out


def _nice_range(lo: float, hi: float) -> tuple[float, float, float]:
    """lo..hi (lo <= 0 <= hi) widened to multiples of a round step (1, 2 or 5 times a power of
    ten) of at most four steps, so the ticks read 0, 20, 40 rather than 0, 17.3, 34.6."""
    steps = [m * 10.0 ** k for k in range(0, 6) for m in (1, 2, 5)]
    for step in steps:
        low, high = math.floor(lo / step) * step, math.ceil(hi / step) * step
        if high - low <= 4 * step:
            return low, max(high, low + step), step
    return lo, max(hi, lo + 1.0), max(hi - lo, 1.0)


# --- signals ------------------------------------------------------------------------------------------

def _band(tl: ActTimeline, approach: str, changes: tuple[Phase, ...], top: float, x: Callable,
          facing: bool) -> list[str]:
    name = f"{tl.window.junction} {approach}"
    name = name if len(name) <= 13 else name[:12] + "…"
    weight = ' font-weight="bold"' if facing else ""
    mark = "▶ " if facing else ""
    out = [f'<text x="{LEFT - 6}" y="{f(top + BAND_H - 3)}" text-anchor="end"{weight}>{mark}{esc(name)}</text>']
    for i, c in enumerate(changes):
        end = changes[i + 1].t if i + 1 < len(changes) else tl.window.t_to
        a, b = x(c.t), x(end)
        if b <= a:
            continue
        title = f"signal {tl.window.junction} {approach}: {colour_word(c.colour)} from {_rel(tl, c.t)}"
        out.append(f'<rect class="signal-band" x="{f(a)}" y="{f(top)}" width="{f(b - a)}" height="{BAND_H}" '
                   f'fill="{fill(c.colour)}" stroke="#333" stroke-width="0.5"><title>{esc(title)}</title></rect>')
    return out


# --- moments ------------------------------------------------------------------------------------------

def _flags(tl: ActTimeline, x: Callable) -> list:
    """The incident's and each moment's label, in rows above the plot (labels.in_rows). Where
    moments crowd so that no row holds their words clear of each other's lines (four "stood
    still before the line" 6 s apart), each moment is labelled by its number and _key writes
    the words under the time axis."""
    moments = tl.moments
    items = [("incident", x(tl.window.t))] + [(m.what, x(m.t)) for m in moments]
    flags = in_rows(items, 2.0, W - 2.0, LABEL_SIZE)
    if any(fl.crowded for fl in flags):
        numbered = [items[0]] + [(str(n), x(m.t)) for n, m in enumerate(moments, 1)]
        flags = in_rows(numbered, 2.0, W - 2.0, LABEL_SIZE)
    return flags


def _key(tl: ActTimeline, flags: list, axis_y: float) -> tuple[list[str], float]:
    """The words of numbered moments, under the time axis, as many to a line as fit; and the
    height they take."""
    moments = tl.moments
    if not moments or flags[1].text != "1":
        return [], 0.0
    entries = [f"{n} {m.what} ({_rel(tl, m.t)})" for n, m in enumerate(moments, 1)]
    lines: list[str] = []
    for entry in entries:
        if lines and text_size(lines[-1] + " · " + entry, LABEL_SIZE)[0] <= W - LEFT - RIGHT:
            lines[-1] += " · " + entry
        else:
            lines.append(entry)
    top = axis_y + AXIS_H
    out = [f'<text class="moment-key" x="{LEFT}" y="{f(top + i * ROW_H)}" font-size="{LABEL_SIZE:g}" '
           f'fill="#222">{esc(line)}</text>' for i, line in enumerate(lines)]
    return out, len(lines) * ROW_H


def _lines(tl: ActTimeline, flags: list, x: Callable, plot_top: float, axis_y: float) -> list[str]:
    """Each label in its row, and its line from there down through every panel to the time axis,
    so the light at the crossing and the distance at the stop read off the panels under it."""
    moments: list[Moment | None] = [None, *tl.moments]
    out = ['<g class="moments">']
    for fl, m in zip(flags, moments):
        box_top = plot_top - 6 - (fl.row + 1) * ROW_H
        box = Box(fl.left, box_top, fl.width, text_size(fl.text, LABEL_SIZE)[1])
        data = f'data-box="{f(box.x)} {f(box.y)} {f(box.w)} {f(box.h)}"'
        baseline = f(box.y + LABEL_SIZE * 0.95)
        if m is None:
            out.append(f'<line class="incident-time" x1="{f(fl.at)}" y1="{f(box_top)}" x2="{f(fl.at)}" '
                       f'y2="{f(axis_y)}" stroke="{INCIDENT}" stroke-width="1.5" stroke-dasharray="4 3"/>')
            out.append(f'<text class="incident-label" x="{f(box.x)}" y="{baseline}" fill="{INCIDENT}" '
                       f'font-size="{LABEL_SIZE:g}" {data}>incident</text>')
            continue
        title = f"{m.what} ({_rel(tl, m.t)})"
        out.append(f'<line class="moment" x1="{f(fl.at)}" y1="{f(box_top)}" x2="{f(fl.at)}" y2="{f(axis_y)}" '
                   f'stroke="#222" stroke-width="1"><title>{esc(title)}</title></line>')
        out.append(f'<text class="moment-label" x="{f(box.x)}" y="{baseline}" fill="#222" font-size="{LABEL_SIZE:g}" '
                   f'{data}>{esc(fl.text)}</text>')
    return out + ["</g>"]


def _time_axis(tl: ActTimeline, x: Callable, axis_y: float) -> list[str]:
    out = [f'<line x1="{LEFT}" y1="{f(axis_y)}" x2="{W - RIGHT}" y2="{f(axis_y)}" stroke="#888"/>']
    step = 5 * SECOND
    first = tl.window.t - ((tl.window.t - tl.window.t_from) // step) * step
    t = first
    while t <= tl.window.t_to:
        out.append(f'<line x1="{f(x(t))}" y1="{f(axis_y)}" x2="{f(x(t))}" y2="{f(axis_y + 4)}" stroke="#888"/>'
                   f'<text x="{f(x(t))}" y="{f(axis_y + 16)}" text-anchor="middle">{_rel(tl, t)}</text>')
        t += step
    out.append(f'<text x="{W - RIGHT}" y="{f(axis_y + 30)}" text-anchor="end" fill="#555">seconds from the '
               "incident</text>")
    return out


def _rel(tl: ActTimeline, t: int) -> str:
    d = (t - tl.window.t) / SECOND
    return "0 s" if d == 0 else f"{d:+g} s"
