"""Zenoh's time-range syntax read to the nanosecond (ingest/time_range.py)."""
from __future__ import annotations

import pytest

from ingest.time_range import TimeRangeError, format_time_range, parse_time_range

NOW = 1_732_176_010_000_000_000        # 2024-11-21T08:00:10Z
S = 1_000_000_000


@pytest.mark.parametrize("text, bounds", [
    ("[..]", (None, None)),
    ("[2024-11-21T08:00:10Z..2024-11-21T08:00:11.000000001Z]", (NOW, NOW + S + 1)),
    ("]2024-11-21T08:00:10Z..2024-11-21T08:00:11Z[", (NOW + 1, NOW + S - 1)),
    ("[2024-11-21 08:00:10..]", (NOW, None)),                        # Zenoh's weak form: space, no zone
    ("[..2024-11-21T09:00:10+01:00]", (None, NOW)),
    ("[2024-11-21T08:00:10Z;1.5ms]", (NOW, NOW + 1_500_000)),
    ("[now(-1h)..now()]", (NOW - 3600 * S, NOW)),
    ("[now(2d)..]", (NOW + 2 * 86_400 * S, None)),
    ("[now(-250u)..]", (NOW - 250_000, None)),
    ("[2024-11-21T08:00:11Z..2024-11-21T08:00:10Z]", (NOW + S, NOW)),  # valid, selects nothing
])
def test_ranges(text, bounds):
    assert parse_time_range(text, NOW) == bounds


@pytest.mark.parametrize("text, says", [
    ("2024-11-21T08:00:10Z", "is not a time range"),
    ("[2024-11-21T08:00:10Z]", "holds '..'"),
    ("[;5s]", "needs a start time"),
    ("[2024-02-30T00:00:00Z..]", "day is out of range"),
    ("[2024-11-21..]", "is not a time"),
    ("[now(-5q)..]", "is not a duration"),
    ("[now(-1e30w)..]", "beyond the times the store holds"),
])
def test_mistakes_say_what_is_wrong(text, says):
    with pytest.raises(TimeRangeError, match=says):
        parse_time_range(text, NOW)


def test_what_gaps_fetch_sends_reads_back_exactly():
    for bounds in ((NOW + 123_456_789, NOW + 5 * S), (None, NOW - 1), (NOW, None), (None, None)):
        assert parse_time_range(format_time_range(*bounds), 0) == bounds
