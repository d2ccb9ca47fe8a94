"""What the report's two pictures share: the signal palette, escaping and number formatting.

Recorded strings (ids, types, colours, approach names) go into SVG text and titles only through
`esc`, and never into an attribute as a style: a colour is looked up in a fixed palette, so a
producer's "red; stroke:url(javascript:...)" is drawn as an unknown colour, not obeyed.
"""
from __future__ import annotations

from .explanation_formats import esc

__all__ = ["esc", "fill", "f", "SIGNAL_FILL", "UNKNOWN_FILL", "legend_swatches"]

SIGNAL_FILL = {"red": "#d62020", "amber": "#f2a900", "green": "#1f9d3a", "off": "#555555",
               "red_amber": "#e8641a"}
UNKNOWN_FILL = "#ffffff"


def fill(colour: object) -> str:
    """The palette's fill for a recorded signal colour (white for anything else)."""
    return SIGNAL_FILL.get(colour, UNKNOWN_FILL) if isinstance(colour, str) else UNKNOWN_FILL


def f(value: float) -> str:
    """A coordinate, short: 12.5, 3, -0.25."""
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def legend_swatches(x: float, y: float, items: list[tuple[str, str]], width: float = 74) -> str:
    """A row of labelled signal swatches: [(label, fill)] from (x, y)."""
    out = []
    for i, (label, colour) in enumerate(items):
        left = x + i * width
        out.append(f'<rect x="{f(left)}" y="{f(y - 9)}" width="12" height="10" fill="{colour}" stroke="#333" '
                   f'stroke-width="0.5"/><text x="{f(left + 16)}" y="{f(y)}">{esc(label)}</text>')
    return "".join(out)
