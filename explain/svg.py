"""What the report's two pictures share: the signal palette, escaping and number formatting.

Recorded strings (ids, types, colours, approach names) go into SVG text and titles only through
`esc`, and never into an attribute as a style: a colour is looked up in a fixed palette, so a
producer's "red; stroke:url(javascript:...)" is drawn as an unknown colour, not obeyed.
"""
from __future__ import annotations

from .explanation_formats import esc
from .labels import text_size

__all__ = ["esc", "fill", "f", "SIGNAL_FILL", "UNKNOWN_FILL", "SIGNAL_WORDS", "colour_word", "legend_colours", "legend_swatches"]

SIGNAL_FILL = {"red": "#d62020", "amber": "#f2a900", "green": "#1f9d3a", "off": "#555555",
               "red_amber": "#e8641a"}
UNKNOWN_FILL = "#ffffff"
# the words a picture's legend, caption and tooltips give each colour (the lamps' legend lists them
# in this order): a reader meets "red and amber", never the recorded token `red_amber`
SIGNAL_WORDS = {"red": "red", "red_amber": "red and amber", "amber": "amber", "green": "green", "off": "off"}
OTHER_WORD = "other"


def fill(colour: object) -> str:
    """The palette's fill for a recorded signal colour (white for anything else)."""
    return SIGNAL_FILL.get(colour, UNKNOWN_FILL) if isinstance(colour, str) else UNKNOWN_FILL


def colour_word(colour: object) -> str:
    """The legend's word for a recorded signal colour; one the palette does not know is "other",
    with what was recorded beside it, as the lamp is drawn white."""
    if isinstance(colour, str) and colour in SIGNAL_WORDS:
        return SIGNAL_WORDS[colour]
    return f"{OTHER_WORD} (recorded as {colour!r})" if colour is not None else f"{OTHER_WORD} (not recorded)"


def legend_colours() -> list[tuple[str, str]]:
    """The lamps' legend: (word, fill) for every colour the palette knows, then "other"."""
    return [(word, SIGNAL_FILL[colour]) for colour, word in SIGNAL_WORDS.items()] + [(OTHER_WORD, UNKNOWN_FILL)]


def f(value: float) -> str:
    """A coordinate, short: 12.5, 3, -0.25."""
    text = f"{value:.2f}".rstrip("0").rstrip(".")
    return "0" if text in ("-0", "") else text


def legend_swatches(x: float, y: float, items: list[tuple[str, str]], size: float = 11.0) -> str:
    """A row of labelled signal swatches: [(label, fill)] from (x, y), each label given the room
    its text takes (labels.text_size), so "red and amber" does not run into "amber"."""
    out = []
    left = x
    for label, colour in items:
        out.append(f'<rect x="{f(left)}" y="{f(y - 9)}" width="12" height="10" fill="{colour}" stroke="#333" '
                   f'stroke-width="0.5"/><text x="{f(left + 16)}" y="{f(y)}">{esc(label)}</text>')
        left += 16 + text_size(label, size)[0] + 12
    return "".join(out)
