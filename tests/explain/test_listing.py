"""One incident per line, drawn from the typed Incident: what an investigator scans for."""
from dataclasses import replace

import pytest

from explain.listing import incident_line
from reasoner.model import (Control, Finding, Incident, Margin, Penalty, Proofs, Scenarios,
                            StageProof)

T = 1732176010000000000
CONTROL = Control(in_control="driver", automated=False, engaged=False, user_in_charge=False,
                  no_user_in_charge=False, transition_demand=None, transition_demand_expired=False,
                  since=None, minimal_risk_manoeuvre=None, failure=None, last_ads_event=None)


def incident(**changes) -> Incident:
    inc = Incident(
        id="monitor/m1:1", run="r1", t=T, vehicle="173", action="enter the junction", monitor="monitor/m1",
        recorded=True, rederived=True, rule="HC 176", law=None, verdict="punishable", why=None,
        penalty=Penalty(offence="traffic light offence", law="RTA 1988 s.36", fine_gbp=100, points=3),
        liable="driver", liability=None, control=CONTROL,
        findings=(Finding(kind="decision fault", detail="it proceeded"),), evidence=(),
        judged_on="vehicle scenario", rulebook=None, rulebooks={},
        scenarios=Scenarios(vehicle=(), monitor=(), validator=(), action=None),
        proofs=Proofs(potential_violation=StageProof(rulebook=None, trees=())))
    return replace(inc, **changes)


def test_the_line_says_what_an_investigator_scans_for():
    assert incident_line(incident(), 1) == (
        "  1  2024-11-21T08:00:10.000Z  monitor/m1:1  vehicle 173  enter the junction  HC 176  punishable  "
        "£100 + 3 points  liable: driver  1 finding: decision fault")


def test_no_penalty_no_findings_and_a_margin():
    line = incident_line(incident(verdict="mitigated", penalty=None, liable="none", findings=(),
                                  margin=Margin(quantity="seconds after red the stop line was crossed", value=1.2,
                                                unit="s")))
    assert line.endswith("mitigated  no penalty  liable: none  crossed 1.2 s after red  no findings")
    assert "after red" not in incident_line(incident(margin=None))
    doubtful = Margin(quantity="a quantity of a newer reasoner", value=3, unit="m", uncertain="a gap")
    assert incident_line(incident(margin=doubtful)).count("a quantity of a newer reasoner 3 m (uncertain)") == 1


def test_a_penalty_without_a_fine_names_the_offence():
    quiet = Penalty(offence="careless driving", law=None, fine_gbp=None, points=0)
    assert "  careless driving  liable" in incident_line(incident(penalty=quiet))


def test_two_findings_are_counted_and_named():
    two = (Finding(kind="decision fault", detail=""), Finding(kind="perception fault", detail=""))
    assert incident_line(incident(findings=two)).endswith("2 findings: decision fault, perception fault")


def test_an_incident_without_a_field_cannot_be_made():
    with pytest.raises(TypeError):
        Incident(id="x", run="r")       # no silent blanks: every field is given


def test_many_findings_of_one_kind_are_counted_not_repeated():
    """Issue 39: "8 findings: contradiction, missing evidence, missing evidence, …" is unreadable."""
    many = (Finding(kind="contradiction", detail=""),) + (Finding(kind="missing evidence", detail=""),) * 7
    assert incident_line(incident(findings=many)).endswith("8 findings: contradiction, missing evidence ×7")


def test_missing_events_are_named_by_source_and_seq_ranges():
    """Issue 39: "missing evidence ×9: vehicle/173 seq 12-20, …" rather than the kind nine times."""
    gaps = tuple(Finding(kind="missing evidence", detail="", src="vehicle/173", missing_seq=(s, s)) for s in range(12, 21))
    gaps += (Finding(kind="missing evidence", detail="", src="monitor/m3", missing_seq=(732, 732)),)
    assert incident_line(incident(findings=gaps)).endswith(
        "10 findings: missing evidence ×10: vehicle/173 seq 12-20; monitor/m3 seq 732")


def test_the_counts_a_user_meets_are_explained_one_per_act():
    """Issue 39: "23 potential violations" and "25 incidents" in one demo, never explained. Two
    cameras' potential violations of one passage are one incident; an act only the car's own
    telemetry shows is another."""
    from explain.listing import acts_summary
    from reasoner.model import Source
    two_cameras = incident(sources=(Source("monitor/m1:1", "monitor/m1", "monitor.potential_violation", "recorded"),
                                    Source("monitor/m2:4", "monitor/m2", "monitor.potential_violation", "recorded")))
    own = incident(sources=(Source("vehicle/173:9", "vehicle/173", "entity.state", "measured"),))
    assert acts_summary([two_cameras, own], recorded_pvs=3) == (
        "one per act: 1 the monitors saw, citing the 2 potential violations they recorded (of 3 recorded in all); "
        "1 found only in the vehicles' own records")
