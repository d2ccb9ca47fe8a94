"""Speeds as the report's reader reads them: mph first (the Highway Code's unit), then the m/s the
producer recorded, so the conversion can be checked against the evidence."""
import pytest

from explain.units import mph, speed_text


def test_a_mile_is_1609_344_metres():
    assert mph(1609.344 / 3600) == pytest.approx(1.0)
    assert mph(13.4112) == pytest.approx(30.0)          # 30 mph, the usual urban limit


@pytest.mark.parametrize("recorded, text", [
    (9, "20.1 mph (9 m/s)"),
    (13.4112, "30.0 mph (13.4112 m/s)"),
    (0.0, "0.0 mph (0 m/s)"),
    (None, "?"),
    ("fast", "fast (recorded, not a number of m/s)"),
    (True, "True (recorded, not a number of m/s)"),
])
def test_speed_text(recorded, text):
    assert speed_text(recorded) == text
