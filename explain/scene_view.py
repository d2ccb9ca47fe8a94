"""The scene picture's frame and its one mapping from world metres to SVG pixels.

Shared by svg_scene.py (markers, labels, legend) and svg_lanes.py (the road surface) so that both
draw through the same scale. World coordinates are metres with y up (as producers record them);
the SVG's y runs down, so the mapping flips it here and nowhere else.
"""
from __future__ import annotations

from typing import Sequence

W, H = 640, 440
PAD = 28
LEGEND_H = 44
MIN_SPAN_M = 50.0


class View:
    """World metres to SVG pixels: one scale for both axes, the focus points' box centred."""

    def __init__(self, points: list[tuple[float, float]]) -> None:
        xs, ys = [p[0] for p in points] or [0.0], [p[1] for p in points] or [0.0]
        cx, cy = (min(xs) + max(xs)) / 2, (min(ys) + max(ys)) / 2
        span_x = max(max(xs) - min(xs), MIN_SPAN_M) * 1.15
        span_y = max(max(ys) - min(ys), MIN_SPAN_M) * 1.15
        self.scale = min((W - 2 * PAD) / span_x, (H - LEGEND_H - 2 * PAD) / span_y)
        self.cx, self.cy = cx, cy
        self.mid_y = PAD + (H - LEGEND_H - 2 * PAD) / 2

    def __call__(self, x: float, y: float) -> tuple[float, float]:
        return W / 2 + (x - self.cx) * self.scale, self.mid_y - (y - self.cy) * self.scale

    def world_frame(self) -> tuple[float, float, float, float]:
        """The drawing area (above the legend) in world metres: x_min, y_min, x_max, y_max."""
        half_w = (W / 2) / self.scale
        return (self.cx - half_w, self.cy - (H - LEGEND_H - self.mid_y) / self.scale,
                self.cx + half_w, self.cy + self.mid_y / self.scale)

    def sees(self, points: Sequence[Sequence[float]], margin_m: float = 0.0) -> bool:
        """Whether the bounding box of `points`, grown by `margin_m`, meets the drawing area."""
        x0, y0, x1, y1 = self.world_frame()
        xs, ys = [p[0] for p in points], [p[1] for p in points]
        return (min(xs) - margin_m <= x1 and max(xs) + margin_m >= x0 and
                min(ys) - margin_m <= y1 and max(ys) + margin_m >= y0)
