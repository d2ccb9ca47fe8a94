"""sim_replay.rounding gives exactly the float round() gives (its repr too: -0.0 stays -0.0), for
the measurements a simulation makes and for the values where a shortcut could go wrong: halves and
their neighbours, tiny and huge numbers, zeros of either sign, NaN, infinities, integers."""
from __future__ import annotations

import math
import random

from sim_replay.rounding import hundredths, rounded_rows, tenths


def _same(a: float, b: float) -> bool:
    return repr(a) == repr(b) and type(a) is type(b)


def _values() -> list:
    rng = random.Random(13)
    out: list = [0.0, -0.0, 0.004, -0.004, 0.005, -0.005, 0.015, 0.025, 0.125, -0.125, 2.675, 1.005, 0.05, 0.15,
                 0.25, -0.35, 1e-300, -1e-300, 5e-324, 1e5, 9999.995, 1e15, 1e300, -1e300, math.inf, -math.inf,
                 math.nan, 3, -7, 0]
    for _ in range(20_000):                       # what SUMO reports: positions, headings, speeds, accelerations
        out.append(rng.uniform(-3000.0, 3000.0))
        out.append(rng.uniform(-360.0, 360.0))
        out.append(rng.uniform(-9.0, 9.0))
    for k in range(-3000, 3000):                  # halves at both scales, and the floats either side of them
        for half in ((k + 0.5) / 100, (k + 0.5) / 10):
            out += [half, math.nextafter(half, math.inf), math.nextafter(half, -math.inf)]
    return out


def test_hundredths_and_tenths_are_round_to_the_bit() -> None:
    values = _values()
    for x in values:
        assert _same(hundredths(x), round(x, 2)) or (math.isnan(x) and math.isnan(hundredths(x))), x
        assert _same(tenths(x), round(x, 1)) or (math.isnan(x) and math.isnan(tenths(x))), x
    short = sum(1 for x in values if type(x) is float and abs(x) < 1e3 and abs(x * 100.0 - round(x * 100.0)) < 0.49)
    assert short > len(values) // 2, "the values hardly try the short way"


def test_rows_rounded_at_once_are_round_to_the_bit() -> None:
    """rounded_rows (a tick's measurements through numpy) gives round()'s floats, ties, zeros,
    NaN, infinities and huge values included; a row with an integer goes value by value."""
    values = [float(x) for x in _values()]
    digits = (2, 2, 1, 2, 2)
    rows = [tuple(values[i:i + 5]) for i in range(0, len(values) - 4, 5)]
    for row, got in zip(rows, rounded_rows(rows, digits)):
        for x, d, y in zip(row, digits, got):
            assert _same(y, round(x, d)) or (math.isnan(x) and math.isnan(y)), (x, d, y)
    mixed = [(1.005, 3, 2.675, -0.0, 7), (0.125, 0.25, 1e300, math.nan, -0.004)]
    for row, got in zip(mixed, rounded_rows(mixed, digits)):
        for x, d, y in zip(row, digits, got):
            assert _same(y, round(x, d)) or (math.isnan(x) and math.isnan(y)), (x, d, y)
    assert rounded_rows([], digits) == []
