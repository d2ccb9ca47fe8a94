"""Zenoh's time-range language, as the `_time` parameter of a selector states it, read into the
store's integer nanoseconds (and written back, for the queries `gaps fetch` sends).

The syntax is Zenoh's own (its "Time DSL", zenoh-util's time_range), so any Zenoh tool can ask:

    [t1..t2]   both ends inclusive           ]t1..t2[   both exclusive (mix as wanted)
    [..t2]     open start                    [t1..]     open end          [..]   everything
    [t1;30s]   t1 and a duration: [t1..t1+30s]
    t:         2024-11-21T08:00:10Z, 2024-11-21T08:00:10.123456789Z, 2024-11-21 08:00:10 (UTC)
               or now(), now(-1h), now(90s): an offset from when the query is answered
    durations: a number of seconds, or a number with a unit u, ms, s, m, h, d, w

Decisions where Zenoh leaves room: times are read with integer arithmetic to the nanosecond
(Decimal, not floats), as the events carry them; an exclusive bound becomes the inclusive one a
nanosecond inside it; a time with an explicit offset (+01:00) is accepted and converted, where
Zenoh reads UTC only; a range whose start is after its end is valid and selects nothing.
"""
from __future__ import annotations

import calendar
import re
from datetime import datetime, timezone
from decimal import Decimal, InvalidOperation

from store import GapsError

SECOND = 1_000_000_000
UNITS = {"u": 1_000, "ms": 1_000_000, "s": SECOND, "m": 60 * SECOND, "h": 3_600 * SECOND,
         "d": 86_400 * SECOND, "w": 604_800 * SECOND}
_DURATION = re.compile(r"([0-9]*\.?[0-9]+(?:[eE][+-]?[0-9]+)?)(u|ms|s|m|h|d|w)?", re.ASCII)
_RFC3339 = re.compile(r"(\d{4})-(\d{2})-(\d{2})[Tt ](\d{2}):(\d{2}):(\d{2})(?:\.(\d{1,9}))?"
                      r"(?:([Zz])|([+-])(\d{2}):(\d{2}))?", re.ASCII)
_NOW = re.compile(r"now\((-?)(.*)\)", re.ASCII)
T_MIN, T_MAX = -(1 << 63), (1 << 63) - 1
Bounds = tuple[int | None, int | None]   # inclusive ns; None: open


class TimeRangeError(GapsError, ValueError):
    """A `_time` value that is not Zenoh's time-range syntax; the message says what is wrong."""


def parse_time_range(text: str, now_ns: int) -> Bounds:
    """(t_from, t_to), inclusive, in ns since the epoch; `now_ns` resolves now(...) forms."""
    if len(text) < 4 or text[0] not in "[]" or text[-1] not in "[]":
        raise TimeRangeError(f"_time={text!r} is not a time range: write [t1..t2], ]t1..t2[, [..t2], "
                             "[t1..] or [t1;duration]")
    start_in, end_in, inner = text[0] == "[", text[-1] == "]", text[1:-1]
    if ".." in inner:
        start, _, end = inner.partition("..")
        t_from = None if not start else _instant(start, now_ns)
        t_to = None if not end else _instant(end, now_ns)
    elif ";" in inner:
        start, _, span = inner.partition(";")
        if not start:
            raise TimeRangeError(f"_time={text!r}: [t;duration] needs a start time before the ';'")
        t_from = _instant(start, now_ns)
        t_to = t_from + duration_ns(span)
    else:
        raise TimeRangeError(f"_time={text!r}: a time range holds '..' (or ';' before a duration)")
    if t_from is not None and not start_in:
        t_from += 1
    if t_to is not None and not end_in:
        t_to -= 1
    return t_from, t_to


def format_time_range(t_from: int | None, t_to: int | None) -> str:
    """The `_time` value for inclusive ns bounds, to the nanosecond ([..] for all time)."""
    return f"[{'' if t_from is None else rfc3339(t_from)}..{'' if t_to is None else rfc3339(t_to)}]"


def rfc3339(t_ns: int) -> str:
    """A UTC RFC 3339 time with all nine digits of the fraction (2024-11-21T08:00:10.000000000Z)."""
    seconds, fraction = divmod(t_ns, SECOND)
    moment = datetime.fromtimestamp(seconds, timezone.utc)
    return f"{moment:%Y-%m-%dT%H:%M:%S}.{fraction:09d}Z"


def duration_ns(text: str) -> int:
    """A Zenoh duration (seconds, or a number and a unit) in whole ns."""
    found = _DURATION.fullmatch(text)
    if not found:
        raise TimeRangeError(f"{text!r} is not a duration: write a number of seconds, or a number with "
                             "a unit u, ms, s, m, h, d or w (e.g. 30s, 1.5h)")
    try:
        return int(Decimal(found[1]) * UNITS[found[2] or "s"])
    except (InvalidOperation, OverflowError):
        raise TimeRangeError(f"{text!r} is not a duration we can use") from None


def _instant(text: str, now_ns: int) -> int:
    """An RFC 3339 time or a now(...) offset, in ns."""
    if found := _NOW.fullmatch(text):
        offset = duration_ns(found[2]) if found[2] else 0
        return _in_range(text, now_ns - offset if found[1] else now_ns + offset)
    if found := _RFC3339.fullmatch(text):
        return _in_range(text, _rfc3339_ns(text, found))
    raise TimeRangeError(f"{text!r} is not a time: write RFC 3339 in UTC (2024-11-21T08:00:10Z, "
                         "2024-11-21T08:00:10.25Z) or now(), now(-1h)")


def _rfc3339_ns(text: str, found: re.Match) -> int:
    year, month, day, hour, minute, second = (int(found[i]) for i in range(1, 7))
    try:
        datetime(year, month, day, hour, minute, second)
    except ValueError as exc:
        raise TimeRangeError(f"{text!r} is not a time: {exc}") from None
    seconds = calendar.timegm((year, month, day, hour, minute, second))
    if found[9]:
        offset = int(found[10]) * 3600 + int(found[11]) * 60
        seconds -= offset if found[9] == "+" else -offset
    return seconds * SECOND + int((found[7] or "").ljust(9, "0"))


def _in_range(text: str, t_ns: int) -> int:
    if not T_MIN <= t_ns <= T_MAX:
        raise TimeRangeError(f"{text!r} is beyond the times the store holds (64-bit ns since 1970)")
    return t_ns
