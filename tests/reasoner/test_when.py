"""Times as typed on the command line (reasoner/when.py): exact to the nanosecond, every form."""
import pytest
from hypothesis import given
from hypothesis import strategies as st

from reasoner.when import SMALLEST_NS, T_MAX, TimeError, format_offset, format_time, parse_time

START = 1_732_176_000_000_000_000  # 2024-11-21T08:00:00Z


@given(st.integers(min_value=0, max_value=T_MAX))
def test_iso_round_trips_every_nanosecond(t):
    assert parse_time(format_time(t), None) == t


@given(st.integers(min_value=-10**12, max_value=10**13))
def test_offsets_round_trip(ns):
    assert parse_time(format_offset(ns), START) == START + ns


@given(st.integers(min_value=SMALLEST_NS, max_value=T_MAX))
def test_integers_are_nanoseconds(t):
    assert parse_time(str(t), None) == t


@pytest.mark.parametrize("text, offset", [
    ("12.5s", 12_500_000_000), ("0s", 0), ("90s", 90 * 10**9), ("+90s", 90 * 10**9), ("-2s", -2 * 10**9),
    ("1m30s", 90 * 10**9), ("1h", 3600 * 10**9), ("1h2m3.25s", 3723_250_000_000),
    ("0.000000001s", 1), ("12.100000003s", 12_100_000_003), (" 7s ", 7 * 10**9),
])
def test_seconds_from_the_run_start_are_exact(text, offset):
    assert parse_time(text, START) - START == offset


@pytest.mark.parametrize("text, t", [
    ("2024-11-21T08:00:10Z", START + 10 * 10**9),
    ("2024-11-21T08:00:10.250+00:00", START + 10_250_000_000),
    ("2024-11-21T09:00:10.250+01:00", START + 10_250_000_000),
    ("2024-11-21T07:00:10.25-0100", START + 10_250_000_000),
    ("2024-11-21 08:00:10.123456789z", START + 10_123_456_789),
    ("2024-11-21T08:00Z", START),
    ("1732176010000000000", START + 10 * 10**9),
])
def test_iso_and_nanoseconds(text, t):
    assert parse_time(text, START) == t


def test_formats():
    assert format_time(START + 10_250_000_000) == "2024-11-21T08:00:10.250Z"
    assert format_time(START + 1) == "2024-11-21T08:00:00.000000001Z"
    assert format_time(START + 1_000) == "2024-11-21T08:00:00.000001Z"
    assert format_offset(12_500_000_000) == "+12.5s" and format_offset(-2 * 10**9) == "-2s"


@pytest.mark.parametrize("text, says", [
    ("12.5", "needs a unit"),
    ("10", "10s"),                                   # a bare small number: seconds were meant
    ("2024-11-21T08:00:10", "needs a zone"),         # naive ISO is refused, never guessed
    ("2024-11-21", "not a time"),
    ("2024-02-30T00:00:00Z", "no such date"),
    ("2024-11-21T08:00:10+24:00", "no such date"),
    ("1.0000000001s", "9 decimal places"),
    ("2024-11-21T08:00:10.1234567891Z", "9 decimal places"),
    ("1969-12-31T23:59:59Z", "before 1970"),
    ("-2000000000s", "before 1970"),
    ("9999999999999999999", "after 2262"),
    ("", "not a time"), ("s", "not a time"), ("1ms", "not a time"), ("12 s", "not a time"),
    ("١٢s", "not a time"),                           # non-ASCII digits
    ("9" * 5000, "too long"),
    ("yesterday", "not a time"),
])
def test_bad_times_say_what_is_wrong_and_what_is_accepted(text, says):
    with pytest.raises(TimeError) as caught:
        parse_time(text, START)
    assert says in str(caught.value)
    assert "seconds from the run start" in str(caught.value) and "ISO 8601" in str(caught.value)
    assert isinstance(caught.value, ValueError)


def test_relative_time_needs_a_run_start():
    with pytest.raises(TimeError, match="run with events"):
        parse_time("12s", None)


# -- the explanations' and the command line's formats, in this one module ---------------------------
from reasoner.when import (SECOND, DurationError, clock, date_clock, day, format_duration, format_time_short,  # noqa: E402
                           parse_duration)


def test_explanation_times():
    t = 1_732_176_010_250_999_999          # 2024-11-21T08:00:10.250999999Z
    assert clock(t) == "08:00:10.250 UTC"
    assert day(t) == "21 November 2024"
    assert date_clock(t) == "2024-11-21 08:00:10.250 UTC"


@pytest.mark.parametrize("t, text", [
    (1_732_184_100_350_000_000, "2024-11-21T10:15:00.35Z"),
    (1_732_184_100_000_000_000, "2024-11-21T10:15:00Z"),
    (1_732_184_100_000_000_001, "2024-11-21T10:15:00.000000001Z"),
    (T_MAX, "2262-04-11T23:47:16.854775807Z"),
])
def test_format_time_short_keeps_only_the_digits_needed(t, text):
    assert format_time_short(t) == text
    assert parse_time(text, None) == t


@pytest.mark.parametrize("ns, text", [(12_350_000_000, "12.35s"), (0, "0s"), (59_999_000_000, "59.999s"),
                                      (3_723_500_000_000, "1h2m3.5s"), (60_000_000_000, "1m"),
                                      (5_000_000_000, "5s"), (7_200_000_000_000, "2h"), (100_000_000, "0.1s")])
def test_duration_is_written_one_way_the_options_read_back(ns, text):
    """One way to write a duration (issue 39: "5 s" and "0:01:00" in one table): the form `--at`
    and `--duration` take, so that what a table shows can be typed back."""
    assert format_duration(ns) == text
    assert parse_time(text, 0) == ns
    if ns:                                  # a simulation's --duration is above zero
        assert parse_duration(text) == ns


@pytest.mark.parametrize("text, ns", [("90s", 90 * SECOND), ("10m", 600 * SECOND), ("1.5h", 5400 * SECOND),
                                      ("90", 90 * SECOND), ("10min", 600 * SECOND), ("1h30m", 5400 * SECOND),
                                      (" 2.5s ", 2_500_000_000)])
def test_one_duration_parser(text, ns):
    assert parse_duration(text) == ns


@pytest.mark.parametrize("text", ["", "ten minutes", "-5s", "0", "1x", "s", "1.5h30m", "1e3s"])
def test_not_a_duration(text):
    with pytest.raises(DurationError, match="is not a duration: write"):
        parse_duration(text)


@given(st.integers(min_value=0, max_value=T_MAX))
def test_format_time_short_reads_back_exactly(t):
    assert parse_time(format_time_short(t), None) == t


@pytest.mark.parametrize("seconds, places, text", [(12.34, 1, "12.3s"), (64.5, 1, "1m4.5s"), (180.0, 3, "3m"),
                                                   (0.04, 1, "0s"), (3600.25, 3, "1h0.25s")])
def test_a_measured_time_is_written_as_every_duration(seconds, places, text):
    from reasoner.when import format_seconds
    assert format_seconds(seconds, places) == text
