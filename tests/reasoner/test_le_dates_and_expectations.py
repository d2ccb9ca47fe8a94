"""Dates as instants, and reading `.le.tests` expectations as data."""
import pytest

from reasoner.le.dates import format_date, parse_date, reference_dates_to_iso
from reasoner.le.expectations import ExpectationError, compare, normalise, read_expectations


def test_dates_are_epoch_seconds_in_utc_and_print_as_iso_8601():
    assert parse_date("1970-01-02") == 86400
    assert parse_date("2021-10-09") == 1633737600
    assert parse_date("2021-10-09T08:30") == 1633737600 + 8 * 3600 + 30 * 60
    assert parse_date("2021-10-09T08:30:00+01:00") == 1633737600 + 7 * 3600 + 30 * 60
    assert parse_date("2021-10-09T08:30:00.5Z") == 1633737600 + 8 * 3600 + 30 * 60 + 0.5
    assert parse_date("2021-02-30") is None and parse_date("tomorrow") is None
    assert format_date(1633737600) == "2021-10-09"
    assert format_date(1633768200) == "2021-10-09T08:30:00Z"
    assert reference_dates_to_iso("at 2021-2-5T0:0:0.0 and 2021-10-9T8:30:0.0") == \
        "at 2021-02-05 and 2021-10-09T08:30:00Z"


def test_expectations_are_read_as_data():
    text = """expected(one,'Andrew email Feb 4 2021',["a b", "it's \\"quoted\\""]).
expected('not-for-profit', test, []).
"""
    e1, e2 = read_expectations(text)
    assert (e1.query, e1.scenario, e1.answers) == ("one", "Andrew email Feb 4 2021", ["a b", 'it\'s "quoted"'])
    assert (e2.query, e2.scenario, e2.answers, e2.line) == ("not-for-profit", "test", [], 2)
    for bad in ["expected(one, two).", "expected(one, two, [x]).", "halt.", "expected(a,b,['x'] "]:
        with pytest.raises(ExpectationError):
            read_expectations(bad)


def test_comparison_is_by_multiset_with_two_documented_normalisations():
    assert compare(["a", "b", "a"], ["a", "a", "b"]) == (True, True)
    assert compare(["a", "b"], ["a", "b", "b"]) == (False, False)
    assert compare(["x is a not - for - profit"], ["x is a not-for-profit"]) == (True, False)
    assert compare(["John on 2021-10-9T0:0:0.0"], ["John on 2021-10-09"]) == (True, False)
    assert normalise("  a   b ") == "a b"
