"""Every verdict path of tests/reasoner/test_verdict_paths.py as a small run, for the explanation
tests: `explained(name, tmp)` stores the run and returns (incident, document) of its vehicle."""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from tests.helpers.verdict_runs import ENTER, RUN, SPEEDING, RunBuilder, car

from explain.explanation_doc import document
from reasoner.investigation import Investigation
from store import Store


def paper(run: RunBuilder) -> None:
    run.spawn("173", "car")
    run.spawn("253", "ambulance", emergency=True)
    run.lights(10, "red")
    run.crossing("173", 10, car("173") + ["173 has red light"],
                 ["173 has red light", "173 crossed the stop line on red light"])
    run.lights(40, "red")
    run.crossing("253", 40, ["253 is of type ambulance", "253 has red light", "253 is on an emergency call"],
                 ["253 has red light", "253 crossed the stop line on red light"])


def off_call(run: RunBuilder) -> None:
    run.spawn("254", "ambulance", emergency=False)
    run.lights(10, "red")
    run.crossing("254", 10, ["254 is of type ambulance", "254 has red light"],
                 ["254 has red light", "254 crossed the stop line on red light"])


def forcing(run: RunBuilder) -> None:
    run.spawn("255", "ambulance", emergency=True)
    run.lights(10, "red")
    run.crossing("255", 10, ["255 is of type ambulance", "255 has red light", "255 is on an emergency call",
                             "p1 is of type pedestrian", "255 would force p1 to change speed or course"],
                 ["255 has red light", "255 crossed the stop line on red light"])


def amber(run: RunBuilder) -> None:
    run.spawn("5", "car")
    run.spawn("6", "car")
    run.lights(10, "amber")
    run.crossing("5", 10, car("5") + ["5 has amber light"],
                 ["5 has amber light", "5 crossed the stop line on amber light"])
    run.lights(40, "amber")
    # over the line when the amber came (HC 175): it crossed on green, and the monitor saw it do so
    over = ["6 has amber light", "6 has crossed the stop line", "6 crossed the stop line on green light"]
    run.crossing("6", 40, car("6") + over, over)


def amber_too_close(run: RunBuilder) -> None:
    run.spawn("7", "car")
    run.lights(10, "amber")
    run.crossing("7", 10, car("7") + ["7 has amber light", "7 is too close to the stop line to stop safely"],
                 ["7 has amber light", "7 crossed the stop line on amber light"])


def stop_sign(run: RunBuilder) -> None:
    run.spawn("8", "car")
    run.crossing("8", 10, car("8") + ["8 has a stop sign", "8 has crossed the stop line"],
                 ["8 has a stop sign", "8 has crossed the stop line"], junction="j2")


def speeding(run: RunBuilder) -> None:
    run.spawn("28", "car")
    run.lights(10, "green")
    speed = ["28 has speed of 38", "the speed limit is 30"]
    run.crossing("28", 10, car("28") + ["28 has green light"] + speed, ["28 has green light"] + speed,
                 action=SPEEDING, goal=ENTER, speed_mps=17.0)


def av_saw_green(run: RunBuilder) -> None:
    run.spawn("300", "car", driver="autonomous", automation_level=4)
    run.ads("300", "activated", 10)
    run.lights(30, "red")
    run.crossing("300", 30, car("300") + ["300 is driving itself", "300 has green light"],
                 ["300 has red light", "300 crossed the stop line on red light"])


def av_taken_over(run: RunBuilder) -> None:
    run.spawn("301", "car", driver="autonomous", automation_level=4)
    run.ads("301", "activated", 0.5)
    run.ads("301", "driver_override", 25, reason="driver took the wheel")
    run.lights(30, "red")
    run.crossing("301", 30, car("301") + ["301 has red light"],
                 ["301 has red light", "301 crossed the stop line on red light"])


def av_engaged(run: RunBuilder) -> None:
    run.spawn("301", "car", driver="autonomous", automation_level=4)
    run.ads("301", "activated", 0.5)
    run.lights(30, "red")
    run.crossing("301", 30, car("301") + ["301 is driving itself", "301 has red light"],
                 ["301 has red light", "301 crossed the stop line on red light"])


def dismissed(run: RunBuilder) -> None:
    run.spawn("42", "car")
    run.lights(10, "red")
    run.crossing("42", 10, car("42") + ["42 has red light"], ["42 has red light", "42 is stopped"], proceeds=False)


def unrecorded(run: RunBuilder) -> None:
    run.spawn("41", "car")
    run.lights(10, "red")
    run.crossing("41", 10, car("41") + ["41 has red light"], ["41 has red light", "41 is in the junction"],
                 record=False, observations=2)


def decision_fault(run: RunBuilder) -> None:
    run.spawn("173", "car")
    run.lights(10, "red")
    run.crossing("173", 10, car("173") + ["173 has red light"],
                 ["173 has red light", "173 crossed the stop line on red light"], says=True)


# name -> (how the run is built, whose incident is explained)
CASES: dict[str, tuple[Callable[[RunBuilder], None], str]] = {
    "paper_car_173_punishable": (paper, "173"),
    "paper_ambulance_253_mitigated": (paper, "253"),
    "ambulance_off_call_punishable": (off_call, "254"),
    "ambulance_forcing_pedestrian_punishable": (forcing, "255"),
    "amber_punishable": (amber, "5"),
    "amber_after_crossing_dismissed": (amber, "6"),
    "amber_too_close_mitigated": (amber_too_close, "7"),
    "stop_sign_punishable": (stop_sign, "8"),
    "speeding_punishable": (speeding, "28"),
    "av_perception_fault_asde": (av_saw_green, "300"),
    "av_taken_over_driver": (av_taken_over, "301"),
    "av_engaged_asde": (av_engaged, "301"),
    "dismissed": (dismissed, "42"),
    "unrecorded": (unrecorded, "41"),
    "decision_fault": (decision_fault, "173"),
}


def store_run(path: Path, name: str) -> Path:
    build, _ = CASES[name]
    run = RunBuilder()
    build(run)
    with Store(path) as store:
        report = store.append(run.finish())
        assert not report.rejected, report.rejected
    return path


def explained(path: Path, name: str, **kw) -> tuple[dict, dict]:
    """Store the case's run at `path` (if not there yet) and explain its vehicle's incident."""
    if not path.exists():
        store_run(path, name)
    vehicle = CASES[name][1]
    with Store(path) as store:
        inv = Investigation(store)
        (inc,) = [i for i in inv.incidents(RUN) if i.vehicle == vehicle]
        return inc, document(inc, inv.explanation(inc, **kw), store)
