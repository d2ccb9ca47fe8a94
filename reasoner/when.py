"""Times as an investigator types them, read exactly: the store keeps integer nanoseconds.

Accepted (DESIGN "Envelope": the CLI takes ns, seconds from the run start, and ISO 8601):

    1732176010000000000              nanoseconds since the Unix epoch (UTC), as the events carry
    12.5s  0s  +90s  -2s  1m30s  1h2m3.25s
                                     from the run start (its run.start event, else its first event);
                                     up to 9 decimal places, on the seconds only
    2024-11-21T08:00:10Z  2024-11-21T08:00:10.250+01:00  2024-11-21 08:00:10.123456789Z
                                     ISO 8601 with a zone: Z or an offset (+01:00, +0100, +01)

Decisions:
- Every form is read with integer arithmetic, never floats, so "12.5s" is exactly 12,500,000,000 ns
  after the start and an ISO time keeps all nine digits of its fraction.
- An ISO time without a zone is refused, not guessed: the store is in UTC, but a time copied from a
  local clock would silently point 1-2 hours away, and a forensic answer must not rest on a guess.
- A number without a unit ("12.5") is refused: it could be seconds or nanoseconds. So is a whole
  number below 10**15 (before 1970-01-12): "--at 10" means "10s" far more often than 10 ns after
  1970, and answering it with an empty scene would mislead; such a time can still be written in ISO.
- A time before 1970 or past what 64-bit nanoseconds hold (2262) is refused; a time before the run
  start is allowed (the scene is then empty, and says so).
"""
from __future__ import annotations

import re
from decimal import Decimal
from datetime import datetime, timedelta, timezone

from store import GapsError

# What other rooms take from here (tests/architecture/test_walls.py): the times as explanations and
# reports write them (explain/listing.py, phrases.py, scene_text.py, text.py); the forms the command
# line reads and prints it takes through `reasoner`'s face, which hands them out
__all__ = ["clock", "date_clock", "day", "format_offset", "format_time"]

SECOND = 1_000_000_000
T_MAX = (1 << 63) - 1  # SQLite's integers, and so the store's times, are signed 64-bit
SMALLEST_NS = 10**15  # 1970-01-12T13:46:40Z: a smaller bare number is a mistyped "12s", not a time

FORMS = ("nanoseconds since the epoch (1732176010000000000), seconds from the run start "
         "(12.5s, 90s, 1m30s, -2s) or ISO 8601 with a zone (2024-11-21T08:00:10.25Z, "
         "2024-11-21T09:00:10+01:00)")

_NS = re.compile(r"\d+", re.ASCII)
_RELATIVE = re.compile(r"([+-]?)(?=\d)(?:(\d+)h)?(?:(\d+)m)?(?:(\d+)(?:\.(\d+))?s)?", re.ASCII)
_ISO = re.compile(
    r"(\d{4})-(\d{2})-(\d{2})[Tt ](\d{2}):(\d{2})(?::(\d{2})(?:[.,](\d+))?)?"
    r"(?:([Zz])|([+-])(\d{2})(?::?(\d{2}))?)?", re.ASCII)
_EPOCH = datetime(1970, 1, 1, tzinfo=timezone.utc)
_UNITS = re.compile(r"[+-]?\d+(\.\d+)?", re.ASCII)
_LONGEST = 64  # characters: longer than any time, and int() of thousands of digits is slow


class TimeError(GapsError, ValueError):
    """A time that cannot be read, with what was wrong and the forms that are accepted."""

    def __init__(self, text: str, problem: str) -> None:
        super().__init__(f"cannot read the time {text!r}: {problem}; give {FORMS}")
        self.text = text
        self.problem = problem


def parse_time(text: str, run_start_ns: int | None) -> int:
    """The moment `text` names, in ns since the epoch. `run_start_ns` anchors relative times
    (None: the run has no events, so a relative time is refused)."""
    given = text.strip()
    if len(given) > _LONGEST:
        raise TimeError(text[:_LONGEST] + "…", "too long to be a time")
    if _NS.fullmatch(given):
        if int(given) < SMALLEST_NS:
            raise TimeError(text, f"a bare number is nanoseconds since the epoch, and {given} ns is in "
                                  f"January 1970; for seconds from the run start write {given}s")
        return _in_range(text, int(given))
    if relative := _RELATIVE.fullmatch(given):
        if run_start_ns is None:
            raise TimeError(text, "a time from the run start needs a run with events")
        return _in_range(text, run_start_ns + _relative_ns(text, relative))
    if iso := _ISO.fullmatch(given):
        return _in_range(text, _iso_ns(text, iso))
    if _UNITS.fullmatch(given):
        raise TimeError(text, "a number needs a unit: 's' for seconds from the run start, "
                              "or a whole number of nanoseconds since the epoch")
    raise TimeError(text, "not a time")


def format_time(t_ns: int) -> str:
    """ISO 8601 in UTC to the millisecond, with more digits only where the nanoseconds need them
    (2024-11-21T08:00:10.250Z, 2024-11-21T08:00:10.250000001Z): parse_time reads it back exactly."""
    seconds, fraction = divmod(t_ns, SECOND)
    try:
        stamp = (_EPOCH + timedelta(seconds=seconds)).strftime("%Y-%m-%dT%H:%M:%S")
    except OverflowError:
        return f"{t_ns} ns"
    digits = f"{fraction:09d}"
    while len(digits) > 3 and digits.endswith("000"):
        digits = digits[:-3]
    return f"{stamp}.{digits}Z"


def clock(t_ns: int) -> str:
    """08:00:10.000 UTC: the time of day to the millisecond, as explanations write it."""
    return _utc(t_ns).strftime("%H:%M:%S.") + f"{(t_ns // 1_000_000) % 1000:03d} UTC"


def day(t_ns: int) -> str:
    """21 November 2024"""
    moment = _utc(t_ns)
    return f"{moment.day} {moment.strftime('%B %Y')}"


def date_clock(t_ns: int) -> str:
    """2024-11-21 08:00:10.000 UTC: the date, then the time as explanations write it."""
    return f"{_utc(t_ns).strftime('%Y-%m-%d')} {clock(t_ns)}"


def _utc(t_ns: int) -> datetime:
    return _EPOCH + timedelta(seconds=t_ns // SECOND)


def _trim(number: str) -> str:
    return number.rstrip("0").rstrip(".")


def format_offset(ns: int) -> str:
    """A signed duration in seconds, exact and without trailing zeros: +12.5s, -2s, +0s."""
    sign = "-" if ns < 0 else "+"
    whole, fraction = divmod(abs(ns), SECOND)
    digits = f"{fraction:09d}".rstrip("0")
    return f"{sign}{whole}{'.' + digits if digits else ''}s"


def format_time_short(t_ns: int) -> str:
    """ISO 8601 in UTC with no trailing zeros (2024-11-21T10:15:00.35Z, 2024-11-21T10:15:00Z):
    the shortest exact form, for tables; parse_time reads it back exactly."""
    full = format_time(t_ns)
    if not full.endswith("Z"):
        return full
    return full[:-1].rstrip("0").rstrip(".") + "Z"


def format_duration(ns: int) -> str:
    """A length of time written one way everywhere, the way `--at` and `--duration` read it back
    exactly: 12.35s, 1m, 1h2m3.5s (issue 39: "5 s" and "0:01:00" stood in one table)."""
    hours, rest = divmod(ns, 3600 * SECOND)
    minutes, rest = divmod(rest, 60 * SECOND)
    seconds = format_offset(rest)[1:] if rest or not (hours or minutes) else ""
    return f"{f'{hours}h' if hours else ''}{f'{minutes}m' if minutes else ''}{seconds}"


def format_seconds(seconds: float, places: int = 1) -> str:
    """A measured length in seconds (a wall-clock time), rounded to `places` decimals and written
    as format_duration writes every duration: 12.3s, 1m4.5s."""
    return format_duration(round(seconds * 10**places) * 10**(9 - places))


class DurationError(GapsError, ValueError):
    """A length of time that cannot be read; the message shows the forms that can."""

    def __init__(self, text: str) -> None:
        super().__init__(f"{text!r} is not a duration: write e.g. 90s, 10m, 1h30m, 1.5h or plain seconds")


_DURATION = re.compile(r"(\d+(?:\.\d+)?)(s|m|min|h)?", re.ASCII)
_DURATION_UNITS = {"": SECOND, "s": SECOND, "m": 60 * SECOND, "min": 60 * SECOND, "h": 3600 * SECOND}


def parse_duration(text: str) -> int:
    """The one parser of a length of time (`gaps sim --duration`, and what format_duration
    writes), in ns, above zero: a number with a unit (90s, 10m, 10min, 1.5h), plain seconds, or
    hours, minutes and seconds as `--at` takes them (1h30m, 1m2.5s). Zenoh's `_time` selectors
    keep their own grammar (ingest/time_range.py): it is Zenoh's, with units of its own."""
    given = (text or "").strip()
    ns = 0
    if len(given) <= _LONGEST:
        if single := _DURATION.fullmatch(given):
            ns = int(Decimal(single[1]) * _DURATION_UNITS[single[2] or ""])
        elif (parts := _RELATIVE.fullmatch(given)) and not parts[1]:
            ns = _relative_ns(given, parts)
    if ns <= 0:
        raise DurationError(text)
    return ns


def _relative_ns(text: str, match: re.Match) -> int:
    sign, hours, minutes, seconds, fraction = match.groups()
    if hours is None and minutes is None and seconds is None:
        raise TimeError(text, "not a time")
    if fraction is not None and len(fraction) > 9:
        raise TimeError(text, "more than 9 decimal places (the store keeps nanoseconds)")
    ns = (int(hours or 0) * 3600 + int(minutes or 0) * 60 + int(seconds or 0)) * SECOND
    ns += int((fraction or "").ljust(9, "0"))
    return -ns if sign == "-" else ns


def _iso_ns(text: str, match: re.Match) -> int:
    year, month, day, hour, minute, second, fraction, zulu, sign, off_h, off_m = match.groups()
    if not zulu and not sign:
        raise TimeError(text, "an ISO time needs a zone: add Z for UTC (the store's times are UTC) "
                              "or an offset such as +01:00")
    if fraction is not None and len(fraction) > 9:
        raise TimeError(text, "more than 9 decimal places (the store keeps nanoseconds)")
    try:
        offset = timedelta(hours=int(off_h or 0), minutes=int(off_m or 0))
        if offset >= timedelta(hours=24):
            raise ValueError("the offset must be under 24 hours")
        zone = timezone(-offset if sign == "-" else offset)
        moment = datetime(int(year), int(month), int(day), int(hour), int(minute), int(second or 0),
                          tzinfo=zone)
    except ValueError as exc:
        raise TimeError(text, f"no such date or time ({exc})") from None
    delta = moment - _EPOCH
    seconds = delta.days * 86_400 + delta.seconds
    return seconds * SECOND + int((fraction or "").ljust(9, "0"))


def _in_range(text: str, t_ns: int) -> int:
    if t_ns < 0:
        raise TimeError(text, "before 1970-01-01T00:00:00Z, where the store's times begin")
    if t_ns > T_MAX:
        raise TimeError(text, "after 2262-04-11T23:47:16.854775807Z, the last time the store can hold")
    return t_ns
