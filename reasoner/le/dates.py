"""Dates and times in LE: instants are seconds since the Unix epoch (UTC).

`2021-10-09` is midnight UTC of that day; `2021-10-09T08:30`, `2021-10-09T08:30:15.5` and an
explicit offset (`Z`, `+01:00`) are accepted too.  Rendering uses ISO 8601: a date alone when
the instant is a midnight, otherwise date, time and `Z`.  The reference implementation prints
`2021-10-9T0:0:0.0`; `reference_date` reads that form back (for comparing with its output).
"""
from __future__ import annotations

import re
from datetime import datetime, timedelta, timezone

ISO = re.compile(r"(\d{4})-(\d{1,2})-(\d{1,2})(?:T(\d{1,2}):(\d{1,2})(?::(\d{1,2})(\.\d+)?)?"
                 r"(Z|[+-]\d{2}:?\d{2})?)?$")
EPOCH = datetime(1970, 1, 1, tzinfo=timezone.utc)


def parse_date(text: str) -> int | float | None:
    """Seconds since the epoch for an LE date or date-time, or None if it is not a valid one."""
    m = ISO.match(text)
    if not m:
        return None
    y, mo, d, h, mi, s, frac, tz = m.groups()
    try:
        dt = datetime(int(y), int(mo), int(d), int(h or 0), int(mi or 0), int(s or 0), tzinfo=timezone.utc)
    except ValueError:
        return None
    if tz and tz != "Z":
        sign = 1 if tz[0] == "+" else -1
        hh, mm = int(tz[1:3]), int(tz[-2:])
        dt -= sign * timedelta(hours=hh, minutes=mm)
    seconds = int((dt - EPOCH).total_seconds())
    if frac:
        return seconds + float(frac)
    return seconds


def format_date(value) -> str:
    """ISO 8601 for an instant: `2021-10-09` at midnight, else `2021-10-09T08:30:00Z`."""
    try:
        dt = EPOCH + timedelta(seconds=value)
    except (OverflowError, TypeError, ValueError):
        return str(value)
    if dt.hour == dt.minute == dt.second == dt.microsecond == 0:
        return dt.strftime("%Y-%m-%d")
    text = dt.strftime("%Y-%m-%dT%H:%M:%S")
    if dt.microsecond:
        text += f".{dt.microsecond:06d}".rstrip("0")
    return text + "Z"


REFERENCE = re.compile(r"\b(\d{4})-(\d{1,2})-(\d{1,2})T(\d{1,2}):(\d{1,2}):(\d{1,2}(?:\.\d+)?)")


def reference_dates_to_iso(text: str) -> str:
    """Rewrite the reference's `2021-2-5T0:0:0.0` date-times in `text` as this project prints them."""
    def iso(m):
        y, mo, d, h, mi, s = m.groups()
        sec = float(s)
        try:
            dt = datetime(int(y), int(mo), int(d), int(h), int(mi), int(sec), tzinfo=timezone.utc)
        except ValueError:
            return m.group(0)
        return format_date((dt - EPOCH).total_seconds() + (sec - int(sec)))
    return REFERENCE.sub(iso, text)
