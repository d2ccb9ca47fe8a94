"""round(x, 2) and round(x, 1), exactly, in a fraction of the time: the events' measurements.

Every entity.state rounds five of SUMO's numbers, a thousand vehicles ten times a second, and
CPython's round(x, ndigits) writes the number out as decimal text and reads it back (dtoa, printf,
strtod): a third of building a state, measured. For the values a simulation measures the same
float comes from arithmetic:

    round(x, 2) is the float nearest to N / 100, N the integer nearest to the exact x * 100

x * 100 in floating point differs from the exact product by at most 2**-53 of it, under 1.2e-10
while |x * 100| < 1e6; unless the product lies within TIE of a half (where the two could round
apart), round(x * 100) is N, and N / 100 (N and 100 exact in a double, the division correctly
rounded) is the float nearest to N / 100, as strtod gives. A result of zero takes x's sign, as
round's does ("-0e-2" reads as -0.0). Anything else (near a tie, large, NaN, infinite, not a
float) goes to round() itself. tests/sim_replay/test_rounding.py compares the two.

`rounded_rows` does the same for a tick's rows of measurements at once, with numpy: the same
products, the same nearest integers (numpy's rint rounds halves to even, as round does, and the
ties go to round() all the same), the same division; a row holding anything but floats is rounded
one value at a time. A third of a vehicle's entity.state was its five roundings, a call each.
"""
from __future__ import annotations

import math
from collections.abc import Sequence
from itertools import chain
from typing import Any, Callable

import numpy as np

__all__ = ["hundredths", "rounded_rows", "tenths"]

TIE = 1e-6           # a product this close to a half is rounded by round() itself
LIMIT = 1e6          # products at least this large too (the error bound above holds below it)
_copysign = math.copysign


def _rounder(digits: int) -> Callable[[Any], float]:
    """round(x, digits), the same float (the module docstring says why and when)."""
    scale = 10.0 ** digits       # 100.0 and 10.0: exact

    def rounded(x: Any) -> float:
        p = x * scale
        if type(x) is float and -LIMIT < p < LIMIT:
            n = round(p)
            if abs(p - n) < 0.5 - TIE:
                return n / scale if n else _copysign(0.0, x)
        return round(x, digits)

    rounded.__doc__ = f"round(x, {digits}), the same float."
    return rounded


hundredths = _rounder(2)
tenths = _rounder(1)


def rounded_rows(rows: Sequence[Sequence[Any]], digits: Sequence[int]) -> list[list[float]]:
    """[[round(x, d) for x, d in zip(row, digits)] for row in rows], the same floats (the module
    docstring says how), for many rows of the same length at once."""
    if not rows:
        return []
    if set(map(type, chain.from_iterable(rows))) != {float}:
        return [[round(x, d) for x, d in zip(row, digits)] for row in rows]
    values = np.array(rows, dtype=np.float64)
    scale = np.array([10.0 ** d for d in digits])
    with np.errstate(invalid="ignore", over="ignore"):   # inf and nan fail the shortcut: round() takes them
        products = values * scale
        nearest = np.rint(products)
        shortcut = (np.abs(products) < LIMIT) & (np.abs(products - nearest) < 0.5 - TIE)
    out = np.where(nearest == 0.0, np.copysign(0.0, values), nearest / scale).tolist()
    if not shortcut.all():
        for i, j in zip(*np.nonzero(~shortcut)):
            out[i][j] = round(rows[i][j], digits[j])
    return out
