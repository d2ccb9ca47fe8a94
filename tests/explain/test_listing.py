"""One incident per line, drawn from the incident's JSON shape, and the filters of `gaps incidents`."""
import pytest

from explain.listing import incident_line, matches, numbered

T = 1732176010000000000


def incident(**changes):
    d = {"id": "monitor/m1:1", "run": "r1", "t": T, "vehicle": "173", "action": "enter the junction",
         "rule": "HC 176", "verdict": "punishable", "liable": "driver",
         "penalty": {"offence": "traffic light offence", "law": "RTA 1988 s.36", "fine_gbp": 100, "points": 3},
         "findings": [{"kind": "decision fault", "detail": "it proceeded", "evidence": []}]}
    return {**d, **changes}


def test_the_line_says_what_an_investigator_scans_for():
    assert incident_line(incident(), 1) == (
        "  1  2024-11-21T08:00:10.000Z  monitor/m1:1  vehicle 173  enter the junction  HC 176  punishable  "
        "£100 + 3 points  liable: driver  1 finding: decision fault")


def test_no_penalty_no_findings_and_a_margin():
    line = incident_line(incident(verdict="mitigated", penalty=None, liable="none", findings=[],
                                  margin={"speed_mps": 2.5}))
    assert line.endswith("mitigated  no penalty  liable: none  margin speed_mps 2.5  no findings")
    assert "margin" not in incident_line(incident(margin=None))


def test_two_findings_are_counted_and_named():
    two = [{"kind": "decision fault"}, {"kind": "perception fault"}]
    assert incident_line(incident(findings=two)).endswith("2 findings: decision fault, perception fault")


def test_a_missing_key_fails_rather_than_printing_a_blank():
    broken = incident()
    del broken["liable"]
    with pytest.raises(KeyError):
        incident_line(broken)


@pytest.mark.parametrize("filters, kept", [
    ({}, True),
    ({"verdict": "punishable"}, True),
    ({"verdict": "mitigated"}, False),
    ({"vehicle": "173"}, True),
    ({"vehicle": "17"}, False),
    ({"rule": "hc 176"}, True),
    ({"rule": "HC 17"}, False),
    ({"verdict": "punishable", "vehicle": "253"}, False),
])
def test_filters(filters, kept):
    assert matches(incident(), **filters) is kept


def test_numbers_count_within_each_run():
    found = [incident(run="a"), incident(run="b"), incident(run="a")]
    assert [(n, d["run"]) for n, d in numbered(found)] == [(1, "a"), (1, "b"), (2, "a")]
