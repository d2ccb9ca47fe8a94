"""Who answers for a punishable violation, from the ads.event history (liability.le, control.py)."""
from __future__ import annotations

from tests.helpers.verdict_runs import RunBuilder, incidents

ASDE = "authorised self-driving entity"


def red_light_run(vehicle: str, level: int, driver: str, ads: list[tuple[str, float]]) -> list[dict]:
    run = RunBuilder()
    run.spawn(vehicle, "car", driver=driver, automation_level=level)
    for event, at in ads:
        run.ads(vehicle, event, at)
    run.lights(30, "red")
    run.crossing(vehicle, 30, [f"{vehicle} is of type car", f"{vehicle} has red light"],
                 [f"{vehicle} has red light", f"{vehicle} crossed the stop line on red light"])
    return run.finish()


def judged(tmp_path, events) -> dict:
    (inc,) = incidents(tmp_path / "s.db", events)
    assert inc.verdict == "punishable"
    return inc


def test_level_3_feature_engaged_the_asde_answers_and_no_points(tmp_path):
    inc = judged(tmp_path, red_light_run("7", 3, "human", [("activated", 1.0)]))
    assert inc.liable == ASDE and list(inc.liability.parties) == [ASDE]
    assert inc.penalty.points == 0 and inc.penalty.points_by_law == 3
    # no driver's fixed penalty either: the ASDE faces regulatory sanctions (AVA 2024)
    assert inc.penalty.fine_gbp is None and inc.penalty.fine_gbp_by_law == 100
    assert inc.liability.fixed_penalty == ()
    assert list(inc.penalty.regulatory_sanctions) == [ASDE]
    # the proof cites the ads.event that engaged the feature
    facts = inc.liability.evidence
    assert facts["7 is driving itself"].kind == "ads.event" and facts["7 is driving itself"].seq == 1  # after the spawn (seq 0)


def test_a_transition_demand_left_unanswered_makes_the_user_in_charge_the_driver(tmp_path):
    inc = judged(tmp_path, red_light_run("8", 3, "human", [("activated", 1.0), ("transition_demand", 15.0)]))
    assert inc.control.in_control == "user-in-charge" and inc.control.transition_demand_expired
    assert inc.liable == "user-in-charge" and inc.penalty.points == 3 and inc.penalty.fine_gbp == 100


def test_a_transition_demand_still_running_leaves_the_feature_in_control(tmp_path):
    inc = judged(tmp_path, red_light_run("9", 3, "human", [("activated", 1.0), ("transition_demand", 25.0)]))
    assert inc.control.in_control == "self-driving feature" and not inc.control.transition_demand_expired
    assert inc.liable == ASDE


def test_no_user_in_charge_vehicle_the_operator_answers_beside_the_asde(tmp_path):
    inc = judged(tmp_path, red_light_run("10", 4, "autonomous", [("activated", 1.0)]))
    assert set(inc.liability.parties) == {ASDE, "no-user-in-charge operator"}
    assert inc.liable == ASDE and inc.penalty.points == 0 and inc.penalty.fine_gbp is None


def test_a_feature_never_engaged_leaves_the_human_driver_liable(tmp_path):
    inc = judged(tmp_path, red_light_run("11", 3, "human", []))
    assert inc.control.in_control == "driver" and inc.liable == "driver"
    assert inc.penalty.points == 3 and inc.penalty.fine_gbp == 100
    assert inc.liability.fixed_penalty == ("driver",)


def test_a_liability_rulebook_that_does_not_say_who_is_offered_the_fixed_penalty_leaves_the_fine(tmp_path):
    """A run judged with a liability rulebook older than the fixed-penalty rule: the fine is
    reported as the law sets it (the reasoner does not decide who is offered it on its own)."""
    from reasoner.bundled import bundled
    text = bundled("liability.le")
    rule = text[text.index("% Road Traffic Offenders Act 1988 Part III"):
                text.index("% Automated Vehicles Act 2024: regulatory")]
    older = text.split("query fixed_penalty is:")[0].replace(rule, "").replace(
        "*a party* is offered a fixed penalty for the violation of *an action* by *a vehicle*.\n", "")
    assert "is offered a fixed penalty" not in older
    from tests.helpers.verdict_runs import incidents
    (inc,) = incidents(tmp_path / "s.db", red_light_run("7", 3, "human", [("activated", 1.0)]), rules=[older])
    assert inc.verdict == "punishable" and inc.liable == ASDE
    assert inc.liability.fixed_penalty is None
    assert (inc.penalty.fine_gbp, inc.penalty.points) == (100, 0)
