"""Where the scene picture writes its labels so that no two overlap.

Vehicles at one stop line, a monitor beside the junction and the signal lamps all want their
label next to the same few pixels; written at a fixed offset they print over one another and
neither can be read. Placement here is small and deterministic (the same picture always gets the
same layout, so two reports of one run compare equal): each label tries offsets around its
anchor, nearest ring first and in a fixed order of directions, and takes the first spot inside the
frame that overlaps no label placed before it and, if it can, no marker (vehicle, lamp, monitor)
other than those on the anchor itself, which no nearby spot could keep off.
Labels placed first get the best spots, so the caller places the incident's vehicle first.

Text width is estimated, not measured (no font is embedded in the report): each character counts
as the widest advance of its class in the fonts a browser picks for "sans-serif" (DejaVu Sans is
the widest of them: lowercase and digits up to 0.64 em, capitals 0.79), so a box is if anything a
little wider than the text drawn in it. The browser test measures the drawn text and checks the
boxes hold it.
"""
from __future__ import annotations

import unicodedata
from dataclasses import dataclass
from typing import Iterable

NARROW, NARROW_EM = frozenset(" .,:;'!|()[]ijlft"), 0.4
WIDE, WIDE_EM = frozenset("mwMW@%"), 1.0
CAPITAL_EM, OTHER_EM, FULL_WIDTH_EM = 0.8, 0.64, 1.0
BOLD = 1.12                # bold advances are up to this much wider
LINE_EM = 1.25             # box height per em: ascender to descender
RING_PX = 9.0              # each further ring of candidates is this much further out
RINGS = 10
GRID_PX = 4.0              # the step of the last resort's search over the whole frame
LEADER_FROM_RING = 2       # from this ring on a thin line joins the label to what it names
# directions tried on each ring, as (dx, dy) of the box's side facing the anchor; right-below first
DIRECTIONS = ((1, 1), (1, 0), (1, -1), (0, 1), (0, -1), (-1, 1), (-1, 0), (-1, -1))


@dataclass(frozen=True)
class Box:
    """An axis-aligned box in SVG pixels: left, top, width, height."""

    x: float
    y: float
    w: float
    h: float

    def intersects(self, other: "Box") -> bool:
        """True when the two share more than an edge."""
        return (self.x < other.x + other.w and other.x < self.x + self.w and
                self.y < other.y + other.h and other.y < self.y + self.h)

    def within(self, frame: "Box") -> bool:
        return (self.x >= frame.x and self.y >= frame.y and self.x + self.w <= frame.x + frame.w and
                self.y + self.h <= frame.y + frame.h)

    def holds(self, x: float, y: float) -> bool:
        return self.x <= x <= self.x + self.w and self.y <= y <= self.y + self.h

    def overlap(self, other: "Box") -> float:
        """The area the two share."""
        w = min(self.x + self.w, other.x + other.w) - max(self.x, other.x)
        h = min(self.y + self.h, other.y + other.h) - max(self.y, other.y)
        return max(w, 0.0) * max(h, 0.0)

    def nearest(self, x: float, y: float) -> tuple[float, float]:
        """The point of the box nearest (x, y), where a leader line meets it."""
        return min(max(x, self.x), self.x + self.w), min(max(y, self.y), self.y + self.h)


@dataclass(frozen=True)
class Label:
    """A placed label: its text, box, the baseline to write it at, and the anchor it names."""

    text: str
    box: Box
    anchor: tuple[float, float]
    size: float
    bold: bool
    leader: bool

    @property
    def baseline(self) -> tuple[float, float]:
        """Where <text> starts (text-anchor start): the box's left, one ascent below its top."""
        return self.box.x, self.box.y + self.size * 0.95


def text_size(text: str, size: float, bold: bool = False) -> tuple[float, float]:
    """The estimated width and height of `text` at `size` px."""
    ems = sum(_advance(c) for c in text) * (BOLD if bold else 1.0)
    return ems * size, size * LINE_EM


def _advance(c: str) -> float:
    if c in NARROW:
        return NARROW_EM
    if c in WIDE:
        return WIDE_EM
    if unicodedata.east_asian_width(c) in ("W", "F"):
        return FULL_WIDTH_EM
    return CAPITAL_EM if c.isupper() else OTHER_EM


class Placer:
    """Labels placed one after another in a frame, each clear of those before it."""

    def __init__(self, frame: Box, obstacles: Iterable[Box] = ()) -> None:
        self.frame = frame
        self.obstacles: list[Box] = list(obstacles)
        self.labels: list[Label] = []

    def block(self, box: Box) -> None:
        """A marker that labels should keep off when there is room."""
        self.obstacles.append(box)

    def place(self, text: str, x: float, y: float, *, clear: float = 6.0, size: float = 11.0,
              bold: bool = False) -> Label:
        """`text` next to the anchor (x, y), at least `clear` px from it (the marker's radius)."""
        w, h = text_size(text, size, bold)
        spots = [(ring, self._candidate(x, y, w, h, clear + ring * RING_PX, d))
                 for ring in range(RINGS) for d in DIRECTIONS]
        inside = [(ring, b) for ring, b in spots if b.within(self.frame)] or spots
        taken = [lab.box for lab in self.labels]
        around = [o for o in self.obstacles if not o.holds(x, y)]     # not its own marker, nor one on it
        free = [(ring, b) for ring, b in inside if not any(b.intersects(t) for t in taken)]
        tidy = [(ring, b) for ring, b in free if not any(b.intersects(o) for o in around)]
        if tidy or free:
            ring, box = (tidy or free)[0]
        else:
            ring, box = RINGS, self._anywhere(x, y, w, h, taken) or min(
                (b for _, b in inside), key=lambda b: sum(b.overlap(t) for t in taken))
        label = Label(text, box, (x, y), size, bold, ring >= LEADER_FROM_RING)
        self.labels.append(label)
        return label

    def _anywhere(self, x: float, y: float, w: float, h: float, taken: list[Box]) -> Box | None:
        """When every ring is full: the free spot of the frame nearest the anchor, on a grid of
        GRID_PX (None if the frame has no room left: the least covered ring spot is taken then)."""
        f = self.frame
        spots = [Box(f.x + i * GRID_PX, f.y + j * GRID_PX, w, h)
                 for i in range(int((f.w - w) // GRID_PX) + 1) for j in range(int((f.h - h) // GRID_PX) + 1)]
        spots.sort(key=lambda b: ((b.x + w / 2 - x) ** 2 + (b.y + h / 2 - y) ** 2, b.x, b.y))
        return next((b for b in spots if not any(b.intersects(t) for t in taken)), None)

    @staticmethod
    def _candidate(x: float, y: float, w: float, h: float, dist: float, d: tuple[int, int]) -> Box:
        dx, dy = d
        diagonal = 0.7 if dx and dy else 1.0
        left = x + dist * diagonal if dx > 0 else x - dist * diagonal - w if dx < 0 else x - w / 2
        top = y + dist * diagonal if dy > 0 else y - dist * diagonal - h if dy < 0 else y - h / 2
        return Box(left, top, w, h)


# --- labels of moments on a time axis ---------------------------------------------------------------

ROW_GAP_PX = 6.0           # the least room between two labels of one row
LINE_CLEAR_PX = 2.0        # the least room between a label and another moment's line


@dataclass(frozen=True)
class Flag:
    """A moment's label on a time axis: written in `row` (0 nearest the plot, each further row
    above it) from `left`, `width` wide, beside its line at `at`, which runs from the top of its
    row down through every row below."""

    text: str
    at: float
    row: int
    left: float
    width: float
    crowded: bool = False
    """Placed where nothing fits: a line may strike it (the caller writes a key instead)."""


def in_rows(items: list[tuple[str, float]], lo: float, hi: float, size: float = 10.0,
            gap: float = 3.0) -> list[Flag]:
    """Each (text, x) written beside its line at x, never cut at the frame's edges lo..hi, in
    the lowest row where it overlaps no label of that row, no other line crosses it, and its own
    line crosses no label of a row below. A label goes to the right of its line where it fits
    and its box holds no line of a label that must go left; else to the left. Those to the right
    are placed from the right, those to the left after them from the left: each then can always
    go above the ones before it, whose lines end below it. The same items always get the same
    rows; the flags come back in the order given."""
    widths = [text_size(text, size)[0] for text, _ in items]
    right = [x + gap + w <= hi for (_, x), w in zip(items, widths)]
    left_fits = [x - gap - w >= lo for (_, x), w in zip(items, widths)]
    changed = True
    while changed:          # a right-hand label over the line of a left-hand one goes left too
        changed = False
        for i, (_, x) in enumerate(items):
            if right[i] and left_fits[i] and any(
                    not right[j] and x + gap - LINE_CLEAR_PX <= items[j][1] <= x + gap + widths[i] + LINE_CLEAR_PX
                    for j in range(len(items)) if j != i):
                right[i], changed = False, True
    order = sorted((i for i in range(len(items)) if right[i]), key=lambda i: (-items[i][1], i))
    order += sorted((i for i in range(len(items)) if not right[i]), key=lambda i: (items[i][1], i))
    placed: dict[int, Flag] = {}
    for i in order:
        text, x = items[i]
        width = widths[i]
        spot = x + gap if right[i] else x - gap - width if left_fits[i] else min(max(x + gap, lo), hi - width)
        done = list(placed.values())
        rows = [row for row in range(len(done) + 1) if _free(done, x, row, spot, width)]
        if not rows:        # no row beside its line: the nearest spot where nothing strikes anything
            spot, rows = _elsewhere(done, x, width, lo, hi) or (spot, rows)
        crowded = not rows
        if crowded:         # none at all: as near as fits, on top
            rows = [row for row in range(len(done) + 2) if _free(done, x, row, spot, width, own_line=False)]
        placed[i] = Flag(text, x, rows[0], spot, width, crowded)
    return [placed[i] for i in range(len(items))]


def _elsewhere(done: list[Flag], x: float, width: float, lo: float, hi: float) -> tuple[float, list[int]] | None:
    """A spot for a label that fits beside its line in no row: just clear of another label's
    line or box, or at an edge, the nearest to its own line first, in the lowest row where no
    label is struck and none overlaps (four "stood still before the line" 6 s apart: the line of
    one runs through the box of the next, whichever side each takes)."""
    edges = [lo, hi - width, x - width / 2]
    for f in done:
        edges += [f.at - LINE_CLEAR_PX - 0.5 - width, f.at + LINE_CLEAR_PX + 0.5,
                  f.left - ROW_GAP_PX - 0.5 - width, f.left + f.width + ROW_GAP_PX + 0.5]
    spots = sorted({min(max(e, lo), hi - width) for e in edges},
                   key=lambda left: (max(left - x, x - left - width, 0.0), left))
    for left in spots:
        rows = [row for row in range(len(done) + 1) if _free(done, x, row, left, width)]
        if rows:
            return left, rows
    return None


def _free(placed: list[Flag], x: float, row: int, left: float, width: float, own_line: bool = True) -> bool:
    for other in placed:
        if other.row == row and left < other.left + other.width + ROW_GAP_PX and other.left < left + width + ROW_GAP_PX:
            return False                                  # two labels of one row meet
        if other.row >= row and left - LINE_CLEAR_PX <= other.at <= left + width + LINE_CLEAR_PX:
            return False                                  # the other's line runs down through this label
        if own_line and other.row <= row and \
                other.left - LINE_CLEAR_PX <= x <= other.left + other.width + LINE_CLEAR_PX:
            return False                                  # this line runs down through the other's label
    return True
