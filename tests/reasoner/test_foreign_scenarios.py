"""End to end, the way a foreign producer writes a run: a roadside-camera vendor or a second
simulator that knows DESIGN's event catalogue, its core vocabulary and its measured fields, and
nothing of this project's (tests/helpers/foreign.py).

What such a producer writes here, and nothing else:
- `run.start` with the map (roads with `speed_limit_mph`, junctions with `control`, `stop_lines`
  with `kind`, `box`), `entity.spawn` (type, emergency), `entity.state` (x, y, heading, speed_mps,
  and `emergency` where the vendor has it), `signal.state` per approach;
- the camera's `monitor.observation`s with its measured speed_mps, x and y, and as facts only
  DESIGN's core sentences ("7 has red light", "7 has crossed the stop line", "7 is in the
  junction", "7 is stopped", "7 has a stop sign", "U is approaching V", "V is on an emergency
  call", ...), or no facts at all (a simulator that only measures: `producer="measured"`);
- where a camera flags a vehicle on line, its `monitor.potential_violation` with the core facts
  it flagged it on.
No project-private sentence is written ("crossed the stop line on C light", "has stopped at the
stop line", "would force", "too close to the stop line", "is on the main road" ...), with the
one exception the law needs and the record cannot measure: a worn Stop line (below).

Sample rates are 2 Hz, 5 Hz or irregular (2-10 Hz), never the project's own 10 Hz.

Every expected verdict and margin is the law's answer for the motion the test builds, worked out
from the legal texts (docs/legal/road-junctions-170-183.md), quoted in each test; none
is copied from what the code says. Motions are mostly at constant speed near the moment that is
measured, so that linear interpolation between samples (reasoner/rebuild.py) is exact there and
the tolerances only absorb the producer's rounding (positions to 1 mm, speeds to 1 mm/s); where a
moment or a duration can only be bracketed by samples, the tolerance is the sample spacing and
the test says so.
"""
from __future__ import annotations

import math
from pathlib import Path
from typing import Callable

import pytest

from reasoner.history import MPH_PER_MPS
from reasoner.stopping import stopping_distance_m
from store import Store

from tests.helpers.foreign import (LANE, LINE_M, OPPOSITE, Foreign, Motion, crossroads, irregular, ns, rate,
                                   roads_through)

ENTER = "enter the junction"
BOX = "enter the box junction"
SPEEDING = "exceed the speed limit"
VERDICTS = {"punishable", "mitigated", "dismissed"}
START = 5.0                     # every motion starts 5 s into the run (after run.start)
SAMPLING: dict[str, Callable[[float, float], list[float]]] = {
    "2 Hz": lambda a, b: rate(2, a, b),
    "5 Hz": lambda a, b: rate(5, a, b),
    "irregular 2-10 Hz": lambda a, b: irregular(a, b, seed=11, low=0.1, high=0.5),
}
SPACING = {"2 Hz": 0.5, "5 Hz": 0.2, "irregular 2-10 Hz": 0.5}      # the widest gap between two samples


def mps(mph: float) -> float:
    return mph / MPH_PER_MPS


# -- judging -------------------------------------------------------------------------------------

def judge(tmp_path: Path, run: Foreign, end: float | None = None) -> list:
    """Store the run's events (as an ingest would) and judge it through the public API."""
    from reasoner.investigation import Investigation

    last = max(e["t"] for e in run.events)
    run.end((last - run.events[0]["t"]) / 1e9 + 1 if end is None else end)
    with Store(tmp_path / "foreign.db") as store:
        report = store.append(run.events)
        assert not report.rejected, report.rejected
        found = Investigation(store).incidents(run.run)
    keys = {(e["src"], e["seq"]): e for e in run.events}
    for inc in found:                       # the contract every incident keeps, whatever its path
        assert inc.verdict in VERDICTS, inc.verdict
        assert inc.run == run.run
        for ref in inc.evidence:
            event = keys.get((ref.src, ref.seq))
            assert event is not None and (event["t"], event["kind"]) == (ref.t, ref.kind), ref
        if inc.verdict == "dismissed":
            assert inc.why, "a dismissal says why"
        if inc.verdict != "punishable":
            assert inc.penalty is None and inc.liable == "none"
    return found


def of(found: list, vehicle: str) -> list:
    return [i for i in found if i.vehicle == vehicle]


def one(found: list, vehicle: str, action: str = ENTER):
    """The one incident of the vehicle, which must be for `action` (a single act: a second
    incident of the vehicle would be a duplicate or an act the law does not see)."""
    mine = of(found, vehicle)
    assert [i.action for i in mine] == [action], \
        f"incidents of {vehicle}: {[(i.id, i.action, i.verdict, i.rule) for i in mine]}"
    return mine[0]


def no_incident(found: list, vehicle: str) -> None:
    mine = of(found, vehicle)
    assert not mine, f"no act, yet: {[(i.id, i.action, i.verdict, i.rule, i.why) for i in mine]}"


def no_violation(found: list, vehicle: str) -> None:
    """No breach: either nothing, or a potential violation the reasoner found lawful or unsupported."""
    bad = [i for i in of(found, vehicle) if i.verdict == "punishable"]
    assert not bad, f"punishable, yet lawful: {[(i.id, i.action, i.rule, i.why) for i in bad]}"


def verdict(inc, expected: str, rule: str) -> None:
    assert (inc.verdict, inc.rule) == (expected, rule), (inc.verdict, inc.rule, inc.why,
                                                         [(f.kind, f.detail) for f in inc.findings])


def margin(inc, words: str, unit: str, value: float, tol: float) -> None:
    m = inc.margin
    assert m is not None, f"{inc.vehicle} {inc.verdict} {inc.rule}: no margin"
    assert words in m.quantity and m.unit == unit, (m.quantity, m.unit)
    assert abs(m.value - value) <= tol, f"{m.quantity}: {m.value} {m.unit}, the law's {value:.3f} ± {tol}"
    assert m.evidence, "a margin cites the measurements it rests on"


def finding_kinds(inc) -> set[str]:
    return {f.kind for f in inc.findings}


# -- what a camera says: DESIGN's core sentences at each frame, from what it sees ---------------------

def colour_at(changes: list[tuple[float, str]], at: float) -> str | None:
    shown = [c for t, c in changes if t <= at]
    return shown[-1] if shown else None


def light_sentences(v: str, colour: str | None) -> list[str]:
    return {"red": [f"{v} has red light"], "amber": [f"{v} has amber light"], "green": [f"{v} has green light"],
            "red_amber": [f"{v} has red light", f"{v} has amber light"]}.get(colour or "", [])


def camera(v: str, changes: list[tuple[float, str]] | None = None, *, sign: str | None = None,
           also: tuple[str, ...] = (), line_m: float = LINE_M, area_m: float = LINE_M):
    """A stop-line camera's core sentences about v at each frame: the light facing its approach
    now, the sign, over the line, in the junction, stopped."""
    def facts(at: float, s: float, speed: float) -> list[str]:
        out = light_sentences(v, colour_at(changes, at)) if changes else []
        if sign:
            out.append(f"{v} has a {sign} sign")
        if s > -line_m:
            out.append(f"{v} has crossed the stop line")
        if abs(s) < area_m:
            out.append(f"{v} is in the junction")
        if speed < 0.1:
            out.append(f"{v} is stopped")
        return out + list(also)
    return facts


def cycle(red_at: float, *, amber_s: float = 3.0, red_s: float = 12.0) -> list[tuple[float, str]]:
    """A UK signal: green, amber (3 s), red, red and amber (2 s), green."""
    return [(0.0, "green"), (red_at - amber_s, "amber"), (red_at, "red"), (red_at + red_s, "red_amber"),
            (red_at + red_s + 2.0, "green")]


def cross_cycle(red_at: float, *, red_s: float = 12.0) -> list[tuple[float, str]]:
    """The cross road's signal while the first shows `cycle(red_at)`: green from 2 s after the
    other's red until 3 s before the other's red ends."""
    return [(0.0, "red"), (red_at + 1.0, "red_amber"), (red_at + 2.0, "green"), (red_at + red_s - 3.0, "amber"),
            (red_at + red_s, "red")]


def runner_run(v: str, speed: float, lag: float, sampling: str, producer: str, *, type: str = "car",
               emergency: bool | None = None, limit_mph: float = 40.0, state_extra: dict | None = None,
               also: tuple[str, ...] = ()) -> tuple[Foreign, Motion, float, list[tuple[float, str]]]:
    """v drives straight through J1 from the west at a constant `speed`, crossing its stop line
    `lag` s after the west signal turned red (negative: before). Returns the run, the motion, the
    crossing time (s from the run start) and the west signal's changes."""
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=limit_mph))
    motion = Motion(-95.0, speed)
    crossing = START + motion.when(-LINE_M)
    west = cycle(crossing - lag)
    run.spawn(v, type, emergency=emergency)
    run.lights("J1", "west", west)
    run.lights("J1", "north", cross_cycle(crossing - lag))
    times = SAMPLING[sampling](START, crossing + 8.0)
    run.drive(v, motion, "west", times, t_start=START, extra=state_extra)
    if producer == "camera":
        run.watch(v, motion, "west", rate(5, START, crossing + 8.0), t_start=START,
                  facts=camera(v, west, also=also))
    else:
        run.watch(v, motion, "west", rate(5, START, crossing + 8.0), t_start=START)
    return run, motion, crossing, west


# ==================================================================================================
# 1. Braking to a stop before the line at red: no act
# ==================================================================================================

@pytest.mark.parametrize("sampling", ["2 Hz", "irregular 2-10 Hz"])
def test_a_car_braking_to_a_stop_before_the_line_at_red_has_done_nothing(tmp_path, sampling):
    """TSRGD 2016 Sch 14 Pt 1 para 5(3): the red signal "conveys the prohibition that vehicular
    traffic must not proceed beyond the stop line"; HC 176: "You MUST NOT move forward over the
    white line when the red light is showing". The car stands 2 m before its line through the
    red: it did not proceed beyond it. No act, nothing recorded: no incident."""
    run = Foreign()
    west = cycle(START + 3.0)                                        # amber at 5 s: the car is 48 m away
    run.spawn("7")
    run.lights("J1", "west", west)
    motion = Motion.stopping_at(-60.0, mps(30), -LINE_M - 2.0, wait=30.0)
    run.drive("7", motion, "west", SAMPLING[sampling](START, START + 25.0), t_start=START)
    run.watch("7", motion, "west", rate(5, START, START + 25.0), t_start=START)
    no_incident(judge(tmp_path, run), "7")


def test_a_camera_flag_against_a_car_that_stopped_before_the_line_is_dismissed(tmp_path):
    """The same stop before the line at red (para 5(3): "must not proceed beyond the stop line";
    it did not), but the camera flagged it on line on "7 has red light" alone. The record does
    not support the potential violation: dismissed."""
    run = Foreign()
    west = cycle(START + 3.0)
    run.spawn("7")
    run.lights("J1", "west", west)
    motion = Motion.stopping_at(-60.0, mps(30), -LINE_M - 2.0, wait=30.0)
    run.drive("7", motion, "west", rate(2, START, START + 25.0), t_start=START)
    run.watch("7", motion, "west", rate(5, START, START + 25.0), t_start=START, facts=camera("7", west))
    run.violation("7", START + 9.0, ENTER, ["7 has red light", "7 is stopped"])
    inc = one(judge(tmp_path, run), "7")
    assert inc.verdict == "dismissed", (inc.verdict, inc.rule, inc.why)


# ==================================================================================================
# 2. Red-light runners: punishable (HC 176), margin seconds after red
# ==================================================================================================

RUNNERS = [  # (mph, seconds after red, sampling, producer)
    (20, 0.4, "5 Hz", "measured"),
    (20, 2.5, "2 Hz", "camera"),
    (28, 1.0, "irregular 2-10 Hz", "measured"),
    (28, 4.0, "5 Hz", "camera"),
    (38, 0.8, "2 Hz", "measured"),
    (38, 3.0, "irregular 2-10 Hz", "camera"),
]


@pytest.mark.parametrize("mph,lag,sampling,producer", RUNNERS,
                         ids=[f"{m}mph-{lag}s-{s}-{p}" for m, lag, s, p in RUNNERS])
def test_red_light_runner_is_punishable_with_the_seconds_after_red(tmp_path, mph, lag, sampling, producer):
    """HC 176: "You MUST NOT move forward over the white line when the red light is showing";
    TSRGD 2016 Sch 14 Pt 1 para 5(3). An ordinary car (no para 5(6) purpose) crossing its line
    `lag` s after red: punishable, HC 176, margin ≈ `lag` s after red.

    Tolerance 0.05 s: the car is at constant speed through the line, so linear interpolation
    between any two samples finds the crossing exactly; what remains is the rounding of the
    reported positions (1 mm, under 0.001 s at these speeds). The road's limit is 40 mph, so
    the 38 mph runner has no second act."""
    run, _, crossing, _ = runner_run("7", mps(mph), lag, sampling, producer)
    if producer == "camera":       # a stop-line camera flags it a second after the crossing
        run.violation("7", crossing + 1.0, ENTER, ["7 has red light", "7 has crossed the stop line"])
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 176")
    margin(inc, "after red", "s", lag, 0.05)


# ==================================================================================================
# 3. Over the line on green, clearing the junction on red: no violation
# ==================================================================================================

def cleared_on_red(producer: str, sampling: str) -> tuple[Foreign, float]:
    """7 crosses its line at 8 m/s on green, stops in the junction 2 m short of the centre (to
    turn, or held by traffic) for 6 s, and pulls away on red."""
    run = Foreign()
    motion = Motion(-60.0, 8.0, [(6.0, 0.0), (2.5, -3.2), (6.0, 0.0), (10.0, 2.0)])
    crossing = START + motion.when(-LINE_M)                          # 6 s after START, on green
    west = cycle(crossing + 4.0)                                     # amber 1 s after the crossing, red 4 s after
    run.spawn("7")
    run.lights("J1", "west", west)
    run.drive("7", motion, "west", SAMPLING[sampling](START, START + 22.0), t_start=START)
    run.watch("7", motion, "west", rate(5, START, START + 22.0), t_start=START,
              facts=camera("7", west) if producer == "camera" else None)
    return run, crossing


@pytest.mark.parametrize("producer,sampling", [("measured", "2 Hz"), ("camera", "irregular 2-10 Hz")])
def test_over_the_line_on_green_and_clearing_on_red_is_no_violation(tmp_path, producer, sampling):
    """Light signals (HC): "AMBER means 'Stop' at the stop line. You may go on only if the AMBER
    appears after you have crossed the stop line"; red (para 5(3)) forbids proceeding beyond the
    stop line, which the car had done on green, before the amber. Leaving the junction on red is
    no act. No incident, even when the camera's frames say "has red light" and "is in the
    junction" (a snapshot the crossing on green replaces: reasoner/rules/README.md)."""
    run, _ = cleared_on_red(producer, sampling)
    no_incident(judge(tmp_path, run), "7")


def test_a_camera_flag_against_a_car_that_crossed_on_green_is_dismissed(tmp_path):
    """The same car; the camera flagged it on its snapshot ("has red light", "is in the junction")
    while it waited in the junction. It crossed on green: the record does not support it."""
    run, crossing = cleared_on_red("camera", "5 Hz")
    run.violation("7", crossing + 5.0, ENTER, ["7 has red light", "7 is in the junction", "7 is stopped"])
    inc = one(judge(tmp_path, run), "7")
    assert inc.verdict == "dismissed", (inc.verdict, inc.rule, inc.why)


# ==================================================================================================
# 4. Amber: too close to stop (mitigated) and far enough to stop (punishable), HC 175
# ==================================================================================================

AMBERS = [  # (mph, metres before the line when amber came, sampling, producer)
    (30, 15.0, "2 Hz", "measured"),        # rule 126 at 30 mph: 23 m
    (30, 35.0, "5 Hz", "measured"),
    (40, 28.0, "irregular 2-10 Hz", "camera"),   # rule 126 at 40 mph: 36 m
    (40, 50.0, "2 Hz", "camera"),
]


@pytest.mark.parametrize("mph,distance,sampling,producer", AMBERS,
                         ids=[f"{m}mph-{d:g}m-{s}-{p}" for m, d, s, p in AMBERS])
def test_amber_too_close_to_stop_is_mitigated_and_far_away_punishable(tmp_path, mph, distance, sampling, producer):
    """HC 175: "You MUST stop behind the white 'Stop' line ... unless the light is green. If the
    amber light appears you may go on only if you have already crossed the stop line or are so
    close to it that to stop might cause a collision." The yardstick for "so close" is rule 126's
    typical stopping distance (20 mph 12 m, 30 mph 23 m, 40 mph 36 m, 50 mph 53 m): nearer than
    that when amber came: mitigated; further: it could have stopped, punishable. The car keeps
    its speed and crosses on amber (3 s of amber is longer than its distance takes).

    Margin: metres from the line when amber came, ± 0.05 m (constant speed: the interpolation at
    the change is exact but for the 1 mm rounding of positions)."""
    speed = mps(mph)
    assert distance / speed < 3.0                              # it crosses while amber still shows
    close = distance < stopping_distance_m(mph)               # the rule 126 yardstick, not the code's
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=40))
    motion = Motion(-100.0, speed)
    amber_at = START + motion.when(-LINE_M - distance)
    west = cycle(amber_at + 3.0)
    run.spawn("7")
    run.lights("J1", "west", west)
    run.drive("7", motion, "west", SAMPLING[sampling](START, amber_at + 8.0), t_start=START)
    run.watch("7", motion, "west", rate(5, START, amber_at + 8.0), t_start=START,
              facts=camera("7", west) if producer == "camera" else None)
    if producer == "camera":
        crossing = START + motion.when(-LINE_M)
        run.violation("7", crossing + 0.4, ENTER, ["7 has amber light", "7 has crossed the stop line"])
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "mitigated" if close else "punishable", "HC 175")
    margin(inc, "amber", "m", distance, 0.05)


def test_an_automated_cars_belief_that_it_was_too_close_to_stop_which_its_record_contradicts(tmp_path):
    """HC 175, as above: go on at amber only if so close that stopping might cause a collision;
    rule 126's stopping distance at 30 mph is 23 m. An automated 7 states in its own perception
    "7 is too close to the stop line to stop safely" when amber comes, while its record has it 35 m
    from the line at a steady 30 mph: it could have stopped. DESIGN "Weighing": the accused's own
    claim that helps it is checked against its measurements like any other; 12 m to spare is
    beyond their tolerance at 5 Hz (± 2.4 m), so the claim decides nothing and the verdict rests on
    what the measurements prove: it could have stopped, punishable, HC 175, with the contradiction
    a finding (a simulated automated car did this on the town map: 28.7 m from the line at 30 mph)."""
    import explain
    import reasoner
    from tests.helpers.foreign import ns

    v, speed, distance = "7", mps(30), 35.0
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=40))
    motion = Motion(-100.0, speed)
    amber_at = START + motion.when(-LINE_M - distance)
    west = cycle(amber_at + 3.0)
    run.spawn(v)
    run.lights("J1", "west", west)
    run.drive(v, motion, "west", SAMPLING["5 Hz"](START, amber_at + 8.0), t_start=START)
    run.watch(v, motion, "west", rate(5, START, amber_at + 8.0), t_start=START)
    run.emit(f"vehicle/{v}", ns(amber_at + 0.5), "vehicle.perception",
             {"facts": [f"{v} is of type car", f"{v} is driving itself", f"{v} has amber light",
                        f"{v} is too close to the stop line to stop safely"]})
    run.emit(f"vehicle/{v}", ns(amber_at + 0.5), "vehicle.decision",
             {"goal": f"{v} can enter the junction", "action": ENTER, "permitted": True, "proceeds": True})
    inc = one(judge(tmp_path, run), v)
    verdict(inc, "punishable", "HC 175")
    assert "too close to the stop line" in inc.why and "decides nothing" in inc.why, inc.why
    doubt = [f for f in inc.findings if f.kind == "contradiction"]
    assert [f.fact for f in doubt] == [f"{v} is too close to the stop line to stop safely"], inc.findings
    assert "35.0 m before the line" in doubt[0].detail and "23.0 m" in doubt[0].detail, doubt[0].detail
    with reasoner.open(tmp_path / "foreign.db") as case:
        text = explain.explanation(case, case.incident(run.run, inc.id), level="summary")
    said = " ".join(text.split())
    assert "decides nothing" in said or "contradict" in said, text


# ==================================================================================================
# 5, 6. The Stop sign (HC 171, TSRGD 2016 Sch 9 Pt 7 para 1)
# ==================================================================================================

def stop_junction(worn_line_m: float | None = None) -> dict:
    """J1 with Stop lines on the west and east arms (the major road runs north-south). With
    `worn_line_m`, the west Stop line is that far from the centre (further out than the junction's
    edge at 12 m: the mouth of the side road lies between the line and the major road)."""
    j = crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop", "east": "stop"})
    if worn_line_m is not None:
        west = next(line for line in j["stop_lines"] if line["approach"] == "west")
        west["from"], west["to"] = [-worn_line_m, 0.0], [-worn_line_m, 3.5]
        j["stop_lines"].append({"approach": "north", "from": [0.0, LINE_M], "to": [3.5, LINE_M], "kind": ""})
    return j


def stop_run(motion: Motion, sampling: str, *, worn_line_m: float | None = None, camera_facts=None,
             end: float = 25.0) -> Foreign:
    run = Foreign(junctions=[stop_junction(worn_line_m)])
    run.spawn("7")
    run.drive("7", motion, "west", SAMPLING[sampling](START, START + end), t_start=START)
    run.watch("7", motion, "west", rate(5, START, START + end), t_start=START, facts=camera_facts)
    return run


ROLLING = Motion(-60.0, 10.0, [(3.0, -2.0)])          # slows to 4 m/s, never below, rolls over the line


@pytest.mark.parametrize("sampling,producer", [("2 Hz", "measured"), ("irregular 2-10 Hz", "camera")])
def test_a_stop_sign_run_with_a_clearly_visible_line_is_punishable(tmp_path, sampling, producer):
    """HC 171: "You MUST stop behind the line at a junction with a 'Stop' sign and a solid white
    line across the road"; Sch 9 Pt 7 para 1: "every vehicle must stop before crossing the
    transverse line". The map gives the junction control "stop" and the line kind "stop"; the car
    rolls over at 4 m/s: punishable, HC 171, margin its slowest speed before the line, 4 m/s (8.95
    mph: exact, it never went below 4 m/s), which its uncertainty does not bring to a stop."""
    facts = camera("7", sign="stop") if producer == "camera" else None
    run = stop_run(ROLLING, sampling, camera_facts=facts)
    if producer == "camera":
        crossing = START + ROLLING.when(-LINE_M)
        run.violation("7", crossing + 0.5, ENTER, ["7 has a stop sign", "7 has crossed the stop line"])
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    margin(inc, "slowest measured speed before the Stop line", "mph", 4.0 * MPH_PER_MPS, 0.01)
    never_stopped(inc)


def never_stopped(inc) -> None:
    """The Stop-line margin of a vehicle that never stood at its line: its slowest measured speed
    before it, which even less its uncertainty (the slowest it can have been between two samples)
    is no stop (0.5 mph)."""
    m = inc.margin
    assert m.quantity == "slowest measured speed before the Stop line" and m.uncertainty is not None, m
    assert m.value - m.uncertainty > 0.5 and m.unproven is None, m


WORN = "the stop line is not clearly visible for 7"
WORN_AT = 16.0       # the worn west line, 4 m before the junction's edge


def test_a_stop_sign_run_over_a_worn_line_is_punishable(tmp_path):
    """Sch 9 Pt 7 para 1: "every vehicle must stop before crossing the transverse line ..., or if
    that line is not clearly visible, before entering the major road". The car never stops at
    all, so it breaks either limb: punishable, HC 171, no stop at the line (its slowest speed before it the margin).

    The worn line is the one private sentence here: `the stop line is not clearly visible for 7`
    (docs/vocabulary.md: "stated by the map or an investigator (wear is not measured)"); DESIGN's
    map has no field for it and no core sentence says it, so the camera states it. The camera
    also states the core "7 has a stop sign"."""
    facts = camera("7", sign="stop", also=(WORN,), line_m=WORN_AT)
    run = stop_run(ROLLING, "5 Hz", worn_line_m=WORN_AT, camera_facts=facts)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    never_stopped(inc)


# 7 stands 1.5 m past the (west) Stop line, 2.6 m short of the junction's edge, for 3 s
PAST_THE_LINE = Motion.stopping_at(-60.0, 10.0, -WORN_AT + 1.5, wait=3.0, then=10.0)


def test_stopping_past_a_worn_line_but_before_the_major_road_is_lawful(tmp_path):
    """Sch 9 Pt 7 para 1: where the line "is not clearly visible", the vehicle must stop "before
    entering the major road in respect of which the stop sign has been provided". The car stops
    1.5 m past the worn line, before the junction's edge, for 3 s, then goes on into an empty
    major road: no violation. (The worn line needs the private sentence, as above.)"""
    facts = camera("7", sign="stop", also=(WORN,), line_m=WORN_AT)
    run = stop_run(PAST_THE_LINE, "5 Hz", worn_line_m=WORN_AT, camera_facts=facts)
    no_violation(judge(tmp_path, run), "7")


def test_the_same_stop_past_a_clearly_visible_line_is_punishable(tmp_path):
    """The control of the worn-line test: with the line clearly visible, para 1 asks for the stop
    "before crossing the transverse line"; standing 1.5 m past it is too late: punishable,
    HC 171, with no stop at the line (the standstill was past it): the margin is its slowest speed
    before the line."""
    facts = camera("7", sign="stop", line_m=WORN_AT)
    run = stop_run(PAST_THE_LINE, "5 Hz", worn_line_m=WORN_AT, camera_facts=facts)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    never_stopped(inc)


LAWFUL_STOP = Motion.stopping_at(-60.0, 10.0, -LINE_M - 0.5, wait=3.0, then=10.0)   # 0.5 m before the line


@pytest.mark.parametrize("sampling", ["2 Hz", "irregular 2-10 Hz"])
def test_a_lawful_stop_at_the_line_is_no_violation(tmp_path, sampling):
    """HC 171 / Sch 9 Pt 7 para 1: "every vehicle must stop before crossing the transverse line";
    the car stands still 0.5 m before the line for 3 s, then goes on into an empty major road: no
    violation, and nothing was recorded: no incident."""
    run = stop_run(LAWFUL_STOP, sampling)
    no_incident(judge(tmp_path, run), "7")


@pytest.mark.parametrize("sampling", ["2 Hz", "5 Hz"])
def test_a_camera_flag_against_a_lawful_stop_is_dismissed_with_the_seconds_stationary(tmp_path, sampling):
    """The same lawful stop; a camera that only sees "has a stop sign" and "has crossed the stop
    line" flags every car over a Stop line. The car stopped (para 1): the flag is dismissed, and
    its margin is the time stationary at the line, 3 s.

    Tolerance: the margin is the time between the first and last sample below 0.5 mph, a lower
    bound. It can miss up to one sample spacing of the 3 s, and can add the moments just before
    the stop and just after pulling away while under 0.22 m/s (braking at 3.3 m/s² and pulling
    away at 2 m/s²: under 0.2 s together)."""
    facts = camera("7", sign="stop")
    run = stop_run(LAWFUL_STOP, sampling, camera_facts=facts)
    crossing = START + LAWFUL_STOP.when(-LINE_M)
    run.violation("7", crossing + 0.5, ENTER, ["7 has a stop sign", "7 has crossed the stop line"])
    inc = one(judge(tmp_path, run), "7")
    assert inc.verdict == "dismissed", (inc.verdict, inc.rule, inc.why)
    m = inc.margin
    assert m is not None and "stationary" in m.quantity and m.unit == "s", m
    assert 3.0 - SPACING[sampling] - 0.01 <= m.value <= 3.2, m


# ==================================================================================================
# 7. Give Way (HC 172)
# ==================================================================================================

def give_way_run(other: Motion, sampling: str, producer: str, mixed: bool = False) -> Foreign:
    """7 pulls out of the west Give Way line at 6 m/s without slowing; c2 comes down the major
    road from the north. The camera watches both. `mixed`: the junction's control says "stop"
    (its south arm has a Stop line), as a simulator's junction with a Stop arm and a Give Way
    arm does; the west arm's line is still a Give Way line."""
    kinds = {"west": "give_way", "south": "stop"} if mixed else {"west": "give_way", "east": "give_way"}
    j = crossroads("J1", 0.0, 0.0, "stop" if mixed else "give_way", kinds=kinds)
    run = Foreign(junctions=[j])
    run.spawn("7")
    run.spawn("c2")
    mine = Motion(-40.0, 6.0)
    times = SAMPLING[sampling](START, START + 16.0)
    run.drive("7", mine, "west", times, t_start=START)
    run.drive("c2", other, "north", times, t_start=START)
    run.watch("7", mine, "west", rate(5, START, START + 16.0), t_start=START,
              facts=camera("7", sign="give way") if producer == "camera" else None)
    run.watch("c2", other, "north", rate(5, START, START + 16.0), t_start=START)
    return run


# c2 at 13.4 m/s would reach 7's path as 7 crosses it; it brakes at 5 m/s² from 0.3 s before 7's
# line (4.67 s) and stops 6 m short of the junction's edge, then goes on once 7 has gone.
_GW = 4.67 - 0.3
FORCED = Motion(-95.0, 13.4, [(_GW, 0.0), (13.4 / 5.0, -5.0), (4.0, 0.0), (8.0, 2.0)])
UNHINDERED = Motion(-150.0, 13.4)        # 87 m away when 7 crosses its line: 7 has left before it arrives


@pytest.mark.parametrize("sampling,producer", [("5 Hz", "measured"), ("2 Hz", "camera")])
def test_a_give_way_failure_that_makes_main_road_traffic_brake_hard_is_punishable(tmp_path, sampling, producer):
    """HC 172: "You MUST give way to traffic on the main road when emerging from a junction with
    broken white lines across the road" (RTA 1988 s.36, TSRGD Sch 9 Pts 7 and 8). c2, on the main
    road, has to brake at 5 m/s² to a stop because 7 pulled out: 7 did not give way.
    Punishable, HC 172, margin c2's deceleration 5 m/s².

    Tolerance 0.25 m/s²: c2's braking is constant at 5 m/s² for 2.7 s, so any pair of samples
    1 s or more apart within it gives 5 exactly; pairs straddling its start or end give less,
    and speeds are rounded to 1 mm/s."""
    found = judge(tmp_path, give_way_run(FORCED, sampling, producer))
    inc = one(found, "7")
    verdict(inc, "punishable", "HC 172")
    margin(inc, "deceleration", "m/s²", 5.0, 0.25)
    no_incident(found, "c2")                       # braking to avoid 7 is no act of c2's


def test_a_main_road_car_no_camera_watches_is_read_from_its_own_record(tmp_path):
    """A camera that looks only down the minor (west) arm, as a simulator's Give Way camera does:
    it states the sign and that c2 comes on the main road, but c2's braking is in no camera's
    record, only in c2's own entity.state. HC 172 is about the main road's traffic; the reasoner
    reads the arms no camera covers from the road users' own records, so 7 forcing c2 to brake at
    5 m/s² is punishable, HC 172."""
    j = crossroads("J1", 0.0, 0.0, "give_way", kinds={"west": "give_way", "east": "give_way"})
    run = Foreign(junctions=[j], monitors=[{"id": "m1", "junction": "J1", "x": -30.0, "y": 8.0, "heading_deg": 0.0,
                                            "range_m": 60.0, "fov_deg": 60.0}])
    run.spawn("7")
    run.spawn("c2")
    mine = Motion(-40.0, 6.0)
    times = SAMPLING["5 Hz"](START, START + 16.0)
    run.drive("7", mine, "west", times, t_start=START)
    run.drive("c2", FORCED, "north", times, t_start=START)
    run.watch("7", mine, "west", rate(5, START, START + 16.0), t_start=START,
              facts=camera("7", sign="give way", also=("c2 is approaching 7", "c2 is on the main road")))
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 172")
    margin(inc, "deceleration", "m/s²", 5.0, 0.25)


def test_a_give_way_failure_at_a_junction_that_also_has_a_stop_arm_is_judged_by_its_own_line(tmp_path):
    """The same act at a junction whose control names its Stop arm: 7's line is a Give Way line,
    so HC 172 (not HC 171's duty to stop) applies, and its margin is c2's deceleration, 5 m/s²
    (a Stop margin, seconds stationary, would say nothing here). c2 on the major road owes no stop."""
    found = judge(tmp_path, give_way_run(FORCED, "5 Hz", "measured", mixed=True))
    inc = one(found, "7")
    verdict(inc, "punishable", "HC 172")
    margin(inc, "deceleration", "m/s²", 5.0, 0.25)
    no_incident(found, "c2")


def test_a_car_stopping_at_its_own_stop_line_across_the_junction_is_not_forced_by_a_give_way_emergence(tmp_path):
    """7 emerges from the west Give Way line while c3, on the east arm, brakes to a stop at its
    own Stop line (as HC 171 obliges it to, whoever passes), and c2 on the main road is still far
    off (UNHINDERED). HC 172's duty is to the main road's traffic; c3's stop is its own line's
    doing, not 7's. No violation by 7; c3 stopped lawfully and did nothing either."""
    j = crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "give_way", "east": "stop"})
    run = Foreign(junctions=[j])
    for user in ("7", "c2", "c3"):
        run.spawn(user)
    mine, across = Motion(-40.0, 6.0), Motion.stopping_at(-45.0, 8.0, -12.5, wait=6, then=3)
    times = SAMPLING["5 Hz"](START, START + 16.0)
    run.drive("7", mine, "west", times, t_start=START)
    run.drive("c2", UNHINDERED, "north", times, t_start=START)
    run.drive("c3", across, "east", times, t_start=START)
    # the camera states what a simulator's does: the sign, and the main-road car coming
    said = camera("7", sign="give way", also=("c2 is approaching 7", "c2 is on the main road"))
    run.watch("7", mine, "west", rate(5, START, START + 16.0), t_start=START, facts=said)
    for user, motion, arm in (("c2", UNHINDERED, "north"), ("c3", across, "east")):
        run.watch(user, motion, arm, rate(5, START, START + 16.0), t_start=START)
    found = judge(tmp_path, run)
    assert of(found, "7"), "the camera's sentences raise a potential violation to judge"
    no_violation(found, "7")
    assert not any("would force c3" in f.sentence for i in of(found, "7") for f in i.derived)
    no_incident(found, "c3")


def predicting_run(measured_c2: bool) -> Foreign:
    """7 emerges from its Give Way line (give_way_run); an automated 7 perceives c2 on the main road
    and states its own prediction, "7 would force c2 to change speed or course"; its rulebook
    answers that it cannot enter (HC 172), and it goes on anyway; the camera states c2 approaching
    on the main road. `measured_c2`: c2's own record (UNHINDERED: it keeps its speed) is in the
    run; else nothing of c2 was measured."""
    from tests.helpers.foreign import ns

    run = give_way_run(UNHINDERED, "5 Hz", "measured")
    if not measured_c2:
        run.events = [e for e in run.events if e["src"] != "vehicle/c2" and e["body"].get("vehicle") != "c2"]
    seen = ["7 is of type car", "7 is driving itself", "7 has a give way sign", "c2 is of type car",
            "c2 is approaching 7", "c2 is on the main road", "7 would force c2 to change speed or course"]
    at = START + 3.0
    run.emit("vehicle/7", ns(at), "vehicle.perception", {"facts": seen})
    run.emit("vehicle/7", ns(at), "vehicle.decision", {"goal": "7 can enter the junction", "action": ENTER,
                                                        "permitted": False, "proceeds": True})
    run.watch("7", Motion(-40.0, 6.0), "west", rate(5, START, START + 16.0), t_start=START, monitor="m2",
              facts=camera("7", sign="give way", also=("c2 is approaching 7", "c2 is on the main road")))
    return run


def test_a_vehicles_own_prediction_that_it_would_force_traffic_the_record_shows_unforced_is_no_offence(tmp_path):
    """HC 172 / TSRGD 2016 Sch 9 Pt 7 para 1 ask what happened: whether the main road's traffic was
    caused to change speed or course. 7 predicted it would force c2 and went on against its own
    rulebook's answer, but c2's own record shows it keeping its 13.4 m/s, 87 m off when 7 crossed:
    nobody was forced (issue 35, "predictions are claims"). The prediction is evidence of what 7
    believed: a decision fault, and a contradiction with c2's record; the act is lawful (at most
    mitigated, HC 172)."""
    inc = one(judge(tmp_path, predicting_run(True)), "7")
    assert inc.verdict != "punishable", (inc.verdict, inc.why)
    assert any(f.kind == "decision fault" for f in inc.findings)
    said = [f for f in inc.findings if f.kind == "contradiction" and "would force c2" in f.detail]
    assert said and "c2's own record" in said[0].detail


def test_a_vehicles_own_prediction_stands_alone_where_nothing_of_the_other_was_measured(tmp_path):
    """The same prediction with nothing of c2 in the record (no entity.state, no camera frame of
    it): the stated sentence is the only evidence of the second limb and stands (DESIGN: the
    Validator Scenario is the vehicle's own, corrected by what was witnessed or measured):
    punishable, HC 172, with the decision fault, and a finding that the claim stands alone."""
    inc = one(judge(tmp_path, predicting_run(False)), "7")
    verdict(inc, "punishable", "HC 172")
    assert any(f.kind == "decision fault" for f in inc.findings)
    alone = [f for f in inc.findings if f.kind == "unmeasured claim"]      # and the explanation says so
    assert alone and alone[0].fact == "7 would force c2 to change speed or course" and "alone" in alone[0].detail


@pytest.mark.parametrize("sampling", ["2 Hz", "irregular 2-10 Hz"])
def test_a_pull_out_that_makes_nobody_brake_is_no_violation(tmp_path, sampling):
    """HC 172's duty is to give way; 7 emerges while c2 is still 87 m up the main road, and c2
    keeps its speed (13.4 m/s throughout): nobody had to change speed or course, so 7 gave way.
    No violation (at most a potential violation found lawful), and c2 did nothing either."""
    found = judge(tmp_path, give_way_run(UNHINDERED, sampling, "measured"))
    no_violation(found, "7")
    no_incident(found, "c2")


# HC 171's second limb and who was made to change speed: 7 stands at the west Stop line of a
# crossroads whose major road runs north-south, then pulls away at 2 m/s². It reaches its line
# (0.5 m ahead) 0.71 s after setting off at 8.87 s (braking from 8 m/s: 6.87 s, then 2 s still).
_SET_OFF = 6.87 + 2.0
STOPS_THEN_GOES = Motion.stopping_at(-40.0, 8.0, -LINE_M - 0.5, wait=2.0, then=10.0)


def stop_then_go_run(*others: tuple[str, Motion, str], said: tuple[str, ...] = (), arm: str = "west",
                     lasts: float = 25.0) -> Foreign:
    """7 stops at its Stop line on `arm` (the minor road's) and goes straight on; `others` (user,
    motion, arm or "arm>exit") drive about it, watched by the camera at 5 Hz as a simulator's
    monitors are, for `lasts` s; the camera states 7's sign and `said`."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={arm: "stop", OPPOSITE[arm]: "stop"})])
    run.spawn("7")
    times = SAMPLING["5 Hz"](START, START + lasts)
    run.drive("7", STOPS_THEN_GOES, arm, times, t_start=START)
    run.watch("7", STOPS_THEN_GOES, arm, rate(5, START, START + lasts), t_start=START,
              facts=camera("7", sign="stop", also=said))
    for user, motion, arm in others:
        run.spawn(user, "bus" if user.startswith("b") else "car")
        run.drive(user, motion, arm, times, t_start=START)
        run.watch(user, motion, arm, rate(5, START, START + lasts), t_start=START)
    return run


def test_a_stop_then_a_pull_out_that_makes_main_road_traffic_brake_is_punishable(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1: "no vehicle must cross the transverse line ... so as to ...
    cause the driver of another vehicle to change its speed or course in order to avoid an
    accident" (HC 171: "Wait for a safe gap in the traffic before you move off"). 7 stopped, then
    pulled out; c2 on the main road brakes at 5 m/s² to a stop from 0.9 s after 7 crossed its
    line. Having stopped does not excuse it: punishable, HC 171."""
    c2 = Motion(-164.0, 13.4, [(_SET_OFF + 0.9 + 0.71, 0.0), (13.4 / 5.0, -5.0), (4.0, 0.0), (8.0, 2.0)])
    found = judge(tmp_path, stop_then_go_run(("c2", c2, "north")))
    inc = one(found, "7")
    verdict(inc, "punishable", "HC 171")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived)
    no_incident(found, "c2")


# When 7 (STOPS_THEN_GOES, along y = +1.75) is out of c2's way: c2 comes down the main road from the
# north along x = +1.75, and 7 is a vehicle's width (2.55 m, C&U Regs 1986 reg. 8) past that line at
# s = 4.30 m, reached 4.10 s after it set off (s = -12.5 + t², pulling away at 2 m/s²).
_OUT_OF_C2S_WAY = _SET_OFF + math.sqrt(12.5 + 1.75 + 2.55)


def braking_after_7_cleared(delay: float) -> Motion:
    """c2 at 13.4 m/s (30 mph), 20 m short of the centre `delay` s after 7 was out of its way,
    when it begins to brake at 4.5 m/s² for 2 s (then goes on at 4.4 m/s)."""
    begins = _OUT_OF_C2S_WAY + delay
    return Motion(-20.0 - 13.4 * begins, 13.4, [(begins, 0.0), (2.0, -4.5)])


def test_a_main_road_car_that_begins_to_slow_long_after_the_vehicle_left_its_way_was_not_forced(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 forbids crossing the Stop line "so as to ... cause the driver
    of another vehicle to change its speed or course in order to avoid an accident". 7 stopped,
    waited and crossed; c2, on the main road, begins to brake hard (4.5 m/s²) 3 s after 7 was out
    of its lane, 20 m short of the centre, for something of its own (the simulation's car 123, which
    slowed to turn into the arm 164 had left). A driver reacting to 7 would have begun within a
    perception-reaction time (AASHTO's 2.5 s, above the 90th percentile of drivers): by then 7 was
    gone from any point c2 would reach, so c2 did not change speed to avoid an accident with it.
    A lawful Stop and pull-out: no violation by 7, and no sentence that it forced c2."""
    found = judge(tmp_path, stop_then_go_run(("c2", braking_after_7_cleared(3.0), "north")))
    assert not any("would force c2" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")
    no_incident(found, "c2")


def test_braking_begun_within_a_reaction_time_but_well_clear_of_the_conflict_zone_was_not_forced(tmp_path):
    """c2 begins the same braking 1.5 s after 7 was out of its lane (within a perception-reaction
    time, 2.5 s), 20 m short of the centre. Had it kept its 13.4 m/s it would have reached the
    zone where the two paths meet about 2.3 s after 7 had left it: a post-encroachment time of
    2 s or more is no conflict (SUMO's SSM device, DEFAULT_THRESHOLD_PET; Allen et al. 1978), so
    there was no accident with 7 to avoid (para 1: "in order to avoid an accident"). Issue 35: "a
    car slowing ... for its own turn, 2.9 s or more clear of the conflict point, read as forced".
    A lawful Stop: no violation by 7, and no sentence that it forced c2."""
    found = judge(tmp_path, stop_then_go_run(("c2", braking_after_7_cleared(1.5), "north")))
    assert not any("would force c2" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_the_same_braking_begun_as_the_vehicle_left_the_conflict_zone_was_forced(tmp_path):
    """The control of the test above: c2 begins the same braking 0.3 s after 7 was out of its
    lane, 20 m short of the centre: unslowed, it would have been at the conflict zone about 1.1 s
    after 7 left it, under the 2 s of a conflict: it braked to avoid an accident with 7. Para 1's
    forcing: punishable, HC 171, with the measured gap in the sentence's method."""
    inc = one(judge(tmp_path, stop_then_go_run(("c2", braking_after_7_cleared(0.3), "north"))), "7")
    verdict(inc, "punishable", "HC 171")
    forced = next(f for f in inc.derived if f.sentence == "7 would force c2 to change speed or course")
    assert "unslowed" in forced.method and "SUMO SSM" in forced.method


def turning_after_7(ahead_m: float) -> Motion:
    """c2 from the west at 13.4 m/s, turning right into the south arm (the lane 7 goes down), 20 m
    short of the centre when 7 is `ahead_m` down the south arm; it then brakes at 4.5 m/s² to
    4 m/s for its turn. 7 is y = -(t² - 12.5) m at t s after setting off (2 m/s² from its line)."""
    begins = _SET_OFF + math.sqrt(ahead_m + 12.5)
    return Motion(-20.0 - 13.4 * begins, 13.4, [(begins, 0.0), (9.4 / 4.5, -4.5)])


def test_a_main_road_car_braking_for_its_turn_into_the_lane_the_vehicle_went_down_far_ahead_was_not_forced(tmp_path):
    """Para 1 again (HC 171). 7 comes out of the north arm's Stop line and goes straight on down the
    south arm; c2, on the main road from the west, turns right into that arm, into the lane 7 is
    in (the simulation's 177 behind 230 at j2). c2 begins to brake hard (4.5 m/s² down to 4 m/s)
    for its turn when 7 is already 30 m down the arm at 13 m/s, 54 m of road ahead of c2. Behind a
    vehicle that far ahead, going its way, c2 could keep the two-second gap (HC 126) braking at
    well under 2 m/s² (Hupfer's considerable reaction): it did not brake to avoid an accident with
    7. A lawful Stop: no violation by 7, and no sentence that it forced c2."""
    found = judge(tmp_path, stop_then_go_run(("c2", turning_after_7(30.0), "west>south"), arm="north"))
    assert not any("would force c2" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_a_main_road_car_braking_as_its_turn_asks_into_the_lane_the_vehicle_went_down_just_ahead_was_not_forced(tmp_path):
    """The test above with 7 nearer: c2 begins the same braking (4.5 m/s² from 13.4 to 4 m/s, ending
    at its corner: the braking its own turn asks, as above) when 7 is 3 m down the south arm at
    7.85 m/s and speeding up, 26.5 m of road ahead of c2. Unslowed, c2 would have come into their
    zone 0.99 s after 7 had left it (no collision course); as driven it came in 1.69 s after. Kept
    at its 13.4 m/s, which no right turn is taken at, it would have been inside the two-second gap
    behind 7 (5.6 m/s² to keep it); at the 4 m/s it took its turn at, 7 was 26.5 m ahead where two
    seconds and 8 m are 16 m, drawing away. c2 slowed as its turn asked and no more, with no
    accident with 7 to avoid (para 1, "in order to avoid an accident"; HC 126): a lawful Stop.
    (Until branch fa35e-turn this was read as forced, on the gap at 13.4 m/s; the paper run's 228
    behind 116 is the same case, and SUMO's account puts 228's braking down to its own minor link.
    A pull-out inside the gap at the turn's speed: test_conflict_scenarios' control, forced.)"""
    found = judge(tmp_path, stop_then_go_run(("c2", turning_after_7(3.0), "west>south"), arm="north"))
    assert not any("would force c2" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


MINOR_ARM_CAMERA = {"id": "m1", "junction": "J1", "x": -30.0, "y": 8.0, "heading_deg": 0.0, "range_m": 60.0,
                    "fov_deg": 60.0}      # looks east down the west (minor) arm into the junction, not along the main road


def unseen_main_road_run(control: str, motion: Motion, facts: list[str]) -> Foreign:
    """7 comes out of the west arm (`control`'s line) watched by MINOR_ARM_CAMERA, which states
    `facts` and nothing of the main road; c2 drives the main road from the north, braking at
    5 m/s² from 0.9 s after 7 crossed its line, in its own entity.state only (5 Hz)."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, control, kinds={"west": control, "east": control})],
                  monitors=[MINOR_ARM_CAMERA])
    run.spawn("7")
    run.spawn("c2")
    times = SAMPLING["5 Hz"](START, START + 25.0)
    run.drive("7", motion, "west", times, t_start=START)
    run.watch("7", motion, "west", rate(5, START, START + 25.0), t_start=START, facts=facts)
    return run


def stated_stop_camera():
    """camera()'s sentences about 7 at its Stop line, and "7 has stopped at the stop line" from the
    moment STOPS_THEN_GOES stands still (6.87 s in) on."""
    core = camera("7", sign="stop")
    return lambda at, s, speed: core(at, s, speed) + (["7 has stopped at the stop line"] if at - START >= 6.87 else [])


def test_a_stop_then_a_pull_out_forcing_main_road_traffic_no_camera_watches_is_punishable(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171), as in the test above, but the camera looks only down
    the Stop arm (as the simulation's town cameras do) and writes 7's sign, its measurements and,
    once it has stood at the line, "7 has stopped at the stop line", and no sentence about the main
    road: c2's braking at 5 m/s² is only in c2's own record. No sentence raises the act and no
    camera measured the braking, yet the record shows it: punishable, HC 171."""
    c2 = Motion(-164.0, 13.4, [(_SET_OFF + 0.9 + 0.71, 0.0), (13.4 / 5.0, -5.0), (4.0, 0.0), (8.0, 2.0)])
    run = unseen_main_road_run("stop", STOPS_THEN_GOES, stated_stop_camera())
    run.drive("c2", c2, "north", SAMPLING["5 Hz"](START, START + 25.0), t_start=START)
    found = judge(tmp_path, run)
    inc = one(found, "7")
    verdict(inc, "punishable", "HC 171")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived)


def test_the_same_stop_and_pull_out_with_the_unseen_main_road_clear_is_no_violation(tmp_path):
    """The same camera and the same stop and pull-out with c2 87 m further back, keeping its speed:
    7 went into a safe gap, as HC 171 asks. Nothing to judge, or nothing punishable."""
    run = unseen_main_road_run("stop", STOPS_THEN_GOES, stated_stop_camera())
    run.drive("c2", Motion(-251.0, 13.4), "north", SAMPLING["5 Hz"](START, START + 25.0), t_start=START)
    no_violation(judge(tmp_path, run), "7")


def test_a_give_way_failure_forcing_main_road_traffic_no_camera_sees_is_punishable(tmp_path):
    """HC 172 (RTA 1988 s.36, TSRGD Sch 9 Pts 7 and 8), with a camera down the Give Way arm that
    writes the sign and 7's measurements and nothing of the main road (unlike the test above where
    it states "c2 is approaching 7"): c2 braking at 5 m/s² because 7 pulled out is in c2's own
    record only. Punishable, HC 172, margin 5 m/s²."""
    run = unseen_main_road_run("give_way", Motion(-40.0, 6.0), camera("7", sign="give way"))
    run.drive("c2", FORCED, "north", SAMPLING["5 Hz"](START, START + 25.0), t_start=START)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 172")
    margin(inc, "deceleration", "m/s²", 5.0, 0.25)


def test_a_queue_already_slowing_before_the_vehicle_set_off_was_not_forced_by_it(tmp_path):
    """The same stop and pull-out, with c2 on the main road braking gently (1.2 m/s²) to stand
    behind a bus, b4, that stands 14 m from the centre, 11 m ahead of it: c2 began slowing 8 s
    before 7 set off, was down to 1.4 m/s when it did, and came to a stop 1.2 s later, as 7 crossed. Para 1 asks whether 7's
    crossing caused c2 to change speed; c2 was already stopping for the bus (the simulation's
    cyclist 171 and car 259 at j2). The camera states c2 approaching on the main road, so the act
    is looked at: no potential violation by 7 under HC 171's second limb, and no incident."""
    slowing_from = _SET_OFF - 8.0
    c2 = Motion(-25.0 - 11.0 * slowing_from - 11.0 ** 2 / 2.4, 11.0, [(slowing_from, 0.0), (11.0 / 1.2, -1.2)])
    b4 = Motion(-14.0, 0.0)
    found = judge(tmp_path, stop_then_go_run(("c2", c2, "north"), ("b4", b4, "north"),
                                             said=("c2 is approaching 7", "c2 is on the main road")))
    assert not any("would force c2" in f.sentence for i in of(found, "7") for f in i.derived)
    no_violation(found, "7")


def test_a_road_user_stopping_on_its_way_out_of_the_junction_was_not_forced(tmp_path):
    """The same stop and pull-out; c5 has come down the main road from the north, is through the
    junction as 7 sets off, and brakes at 3 m/s² to a stop 30 m out on the south arm (for whatever
    lies ahead of it, beyond the junction). A road user stopping on its way away from the junction, beyond
    the vehicle, was not made to stop by it: no violation by 7, no incident."""
    c5 = Motion(24.0 - 6.0 * _SET_OFF, 6.0, [(_SET_OFF, 0.0), (2.0, -3.0)])
    assert c5.at(_SET_OFF)[0] > LINE_M and c5.at(_SET_OFF + 3.0) == (30.0, 0.0)   # out of it, then 30 m out
    found = judge(tmp_path, stop_then_go_run(("c5", c5, "north")))
    assert not any("would force c5" in f.sentence for i in of(found, "7") for f in i.derived)
    no_incident(found, "7")


def test_a_camera_speed_the_vehicles_own_record_contradicts_is_not_proven(tmp_path):
    """RTRA 1984 s.89 (HC 124): over the limit is an offence. The camera states "28 has speed of
    38" where the limit is 30; the car's own entity.state has it at a steady 13.4 m/s (30.0 mph).
    DESIGN "Weighing": the camera's sentence is a claim, the measurements evidence; they disagree
    beyond tolerance on the fact the verdict turns on (punishable with the claim, no offence
    without), so neither decides and the speeding is not proven: dismissed, HC 124, the
    contradiction a finding and the summary saying why. The margin (the fastest measured sample)
    is 0 mph over, never "-0", and itself proves nothing."""
    import explain
    import reasoner

    v = "28"
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=30))
    motion = Motion(-95.0, 13.41)
    run.spawn(v)
    run.lights("J1", "west", [(0.0, "green")])
    run.drive(v, motion, "west", SAMPLING["5 Hz"](START, START + 9.0), t_start=START)
    run.watch(v, motion, "west", rate(5, START, START + 9.0), t_start=START,
              facts=lambda at, s, speed: [f"{v} has speed of 38", "the speed limit is 30"])
    inc = one(judge(tmp_path, run), v, SPEEDING)
    verdict(inc, "dismissed", "HC 124")
    assert inc.why.startswith("not proven:") and f"“{v} has speed of 38”" in inc.why, inc.why
    assert inc.penalty is None
    doubt = [f for f in inc.findings if f.kind == "contradiction"]
    assert doubt and doubt[0].fact == f"{v} has speed of 38" and "30.0 mph" in doubt[0].detail, doubt
    assert inc.margin is not None and str(inc.margin.value) == "0.0" and inc.margin.unproven, inc.margin
    with reasoner.open(tmp_path / "foreign.db") as case:
        text = explain.explanation(case, case.incident(run.run, inc.id), level="summary")
    said = " ".join(text.split())
    assert "not proven" in said and "it was measured at 30.0 mph then" in said, text


# ==================================================================================================
# 8. A blocked box junction (HC 174)
# ==================================================================================================

@pytest.mark.parametrize("sampling,producer", [("2 Hz", "measured"), ("irregular 2-10 Hz", "camera")])
def test_stopping_in_a_box_junction_with_the_exit_queued_is_punishable(tmp_path, sampling, producer):
    """HC 174: "You MUST NOT enter the box until your exit road or lane is clear" (TSRGD Sch 9
    Pts 7 and 8). J1 is a box junction ("box": true); q1 stands queued 4 m beyond the junction's
    edge on 7's exit while 7 drives in on green and stops inside the box for 6 s until q1 moves
    off. Punishable, HC 174, margin the seconds stopped in the box, 6 s.

    Tolerance: from one sample spacing less (the first and last samples at rest bracket the 6 s
    from inside) to 0.2 s more (samples under 0.22 m/s while braking at 3.2 m/s² or pulling away
    at 2 m/s²)."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "lights", box=True)])
    mine = Motion(-60.0, 8.0, [(6.0, 0.0), (2.5, -3.2), (6.0, 0.0), (10.0, 2.0)])   # stands at s = -2
    queued = Motion(16.0, 0.0, [(14.5, 0.0), (10.0, 2.0)])                             # moves off at 14.5 s
    run.spawn("7")
    run.spawn("q1")
    run.lights("J1", "west", [(0.0, "green")])
    times = SAMPLING[sampling](START, START + 24.0)
    run.drive("7", mine, "west", times, t_start=START)
    run.drive("q1", queued, "west", rate(2, START, START + 24.0), t_start=START)
    run.watch("7", mine, "west", rate(5, START, START + 24.0), t_start=START,
              facts=camera("7", [(0.0, "green")]) if producer == "camera" else None)
    run.watch("q1", queued, "west", rate(5, START, START + 24.0), t_start=START)
    inc = one(judge(tmp_path, run), "7", BOX)
    verdict(inc, "punishable", "HC 174")
    m = inc.margin
    assert m is not None and "box" in m.quantity and m.unit == "s", m
    assert 6.0 - SPACING[sampling] - 0.01 <= m.value <= 6.2, m


def test_a_queue_facing_the_junction_on_the_exit_arm_does_not_block_the_exit(tmp_path):
    """HC 174 forbids entering the box "until your exit road or lane is clear". 7 stands in the
    box for 6 s; beyond the junction on its exit arm the only road user is q2, standing at that
    arm's own line in the other lane, facing the junction (waiting for its own light). 7's exit
    lane was clear: no violation. (The simulation's ground truth found the reasoner counting such
    a queue as a blocked exit.)"""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "lights", box=True)])
    mine = Motion(-60.0, 8.0, [(6.0, 0.0), (2.5, -3.2), (6.0, 0.0), (10.0, 2.0)])   # stands at s = -2
    waiting = Motion(-16.0, 0.0, [(24.0, 0.0)])                                        # on the east arm, facing west
    run.spawn("7")
    run.spawn("q2")
    run.lights("J1", "west", [(0.0, "green")])
    times = SAMPLING["5 Hz"](START, START + 24.0)
    run.drive("7", mine, "west", times, t_start=START)
    run.drive("q2", waiting, "east", rate(2, START, START + 24.0), t_start=START)
    run.watch("7", mine, "west", rate(5, START, START + 24.0), t_start=START)
    run.watch("q2", waiting, "east", rate(5, START, START + 24.0), t_start=START)
    found = judge(tmp_path, run)
    no_violation(found, "7")
    no_incident(found, "q2")


# ==================================================================================================
# 9. Emergency vehicles on red (TSRGD 2016 Sch 14 Pt 1 para 5(4)-(6))
# ==================================================================================================

AMBULANCE_LAG = 2.0


def pedestrian(run: Foreign, who: str, crossing: float, type: str = "pedestrian", speed: float = 1.4) -> None:
    """A pedestrian (or cyclist) coming down the north arm towards the junction while the vehicle
    crosses: 26 m from the centre at the crossing. A pedestrian waits at the kerb 13 m out; a
    cyclist rides on (it reaches the junction 3.5 s after the crossing, when the vehicle has left)."""
    stops = [((26.0 - 13.0) / speed + (crossing - START), 0.0), (1.0, -speed * 2)] if type == "pedestrian" else []
    motion = Motion(-26.0 - speed * (crossing - START), speed, stops)
    run.spawn(who, type, role="pedestrian" if type == "pedestrian" else "vehicle")
    run.drive(who, motion, "north", rate(2, START, crossing + 8.0), t_start=START,
              role="pedestrian" if type == "pedestrian" else "vehicle")
    run.watch(who, motion, "north", rate(5, START, crossing + 8.0), t_start=START,
              facts=[f"{who} is of type {type}"])


def stepping_out(run: Foreign, who: str, crossing: float) -> None:
    """A pedestrian walking north at 1.4 m/s across the west-east road, on the line x = -1.75 (the
    south arm's lane), reaching the vehicle's lane (y = +1.75) 1 s after the vehicle crossed its
    line, as the vehicle (12.5 m/s, 12 m from the centre at its line) gets there."""
    motion = Motion(1.75 - 1.4 * (crossing + 1.0 - START), 1.4)
    run.spawn(who, "pedestrian", role="pedestrian")
    run.drive(who, motion, "south", rate(2, START, crossing + 8.0), t_start=START, role="pedestrian")
    run.watch(who, motion, "south", rate(5, START, crossing + 8.0), t_start=START,
              facts=[f"{who} is of type pedestrian"])


def north_car(run: Foreign, who: str, crossing: float, *, brakes: bool, decel: float = 5.0) -> None:
    """A car on the north arm, its light green: 45 m from the centre at the crossing; it either
    keeps its 12 m/s (it reaches the junction after the vehicle has left) or brakes at `decel`
    from 0.5 s before the crossing to a stop outside the junction."""
    s_then = -45.0
    if brakes:
        lead = crossing - 0.5 - START
        motion = Motion(-30.0 - 12.0 * lead, 12.0, [(lead, 0.0), (12.0 / decel, -decel), (5.0, 0.0), (8.0, 2.0)])
    else:
        motion = Motion(s_then - 12.0 * (crossing - START), 12.0)
    run.spawn(who)
    run.drive(who, motion, "north", rate(2, START, crossing + 8.0), t_start=START)
    run.watch(who, motion, "north", rate(5, START, crossing + 8.0), t_start=START)


EMERGENCY = [  # id, type, how it is on a call (None: not), who else is there, the law's verdict
    ("ambulance-on-call-nobody", "ambulance", "spawn", None, "mitigated"),
    ("ambulance-on-call-core-sentence", "ambulance", "sentence", None, "mitigated"),
    ("unmarked-police-car-on-call", "car", "state", None, "mitigated"),
    ("ambulance-off-call", "ambulance", None, None, "punishable"),
    # a pedestrian walking towards the junction who waits at the kerb 13 m out never enters the
    # ambulance's path: not likely to be endangered by it (para 5(5)); mitigated (issue 35)
    ("ambulance-on-call-pedestrian-waiting-at-the-kerb", "ambulance", "spawn", "pedestrian", "mitigated"),
    # a cyclist reaching the junction 3.5 s after the ambulance crossed, 2 s or more after it left
    # the point where their paths meet (SUMO SSM's PET threshold): not endangered; mitigated
    ("ambulance-on-call-cyclist-after-it-left", "ambulance", "spawn", "cyclist", "mitigated"),
    # a pedestrian stepping into the ambulance's path as it comes: likely to endanger; punishable
    ("ambulance-on-call-pedestrian-stepping-into-its-path", "ambulance", "spawn", "pedestrian in its path",
     "punishable"),
    ("ambulance-on-call-car-approaching-unhindered", "ambulance", "spawn", "car", "mitigated"),
    ("ambulance-on-call-car-forced-to-brake", "ambulance", "spawn", "car braking", "punishable"),
    # a car on green braking at 7 m/s² to a stop as the ambulance crosses its path: "to cause the
    # driver of another vehicle to change its speed ... in order to avoid an accident"; punishable
    ("ambulance-on-call-car-braking-at-7", "ambulance", "spawn", "car braking at 7", "punishable"),
]


@pytest.mark.parametrize("type,call,other,expected", [e[1:] for e in EMERGENCY], ids=[e[0] for e in EMERGENCY])
def test_emergency_vehicle_on_red(tmp_path, type, call, other, expected):
    """TSRGD 2016 Sch 14 Pt 1 para 5: (3) the red signal's prohibition is "subject to
    sub-paragraphs (4) to (6)"; (4) para (5) applies "where a vehicle is being used for at least
    one of the purposes set out in sub-paragraph (6) and the observance of the prohibition ...
    would be likely to hinder" that use; (5) then "the vehicle must not proceed beyond the stop
    line in such a manner or at such a time as to be likely to endanger any person or to cause
    the driver of another vehicle to change its speed or course in order to avoid an accident";
    (6) the purposes include "(c) ambulance" and "(h) police". The exemption follows the purpose,
    not the vehicle: on a call with nobody about, mitigated (HC 176, the rule it modifies); an
    unmarked police car (type car) on a call likewise; an ambulance off a call is bound by
    para 5(3): punishable; a pedestrian or cyclist in or entering its path as it comes is "likely
    to be endangered": punishable, but one walking towards the junction who waits at the kerb, or
    rides through after it has gone, is not (issue 35); a car that keeps its speed was not caused
    to change it: mitigated; a car that had to brake hard (5 or 7 m/s²) to a stop was: punishable.

    It crosses 2 s after red at 28 mph; margin 2 s after red (± 0.05 s, constant speed)."""
    v = "253"
    emergency = True if call == "spawn" else (False if call is None else None)
    run, _, crossing, _ = runner_run(
        v, mps(28), AMBULANCE_LAG, "5 Hz", "camera", type=type, emergency=emergency,
        state_extra={"emergency": True} if call == "state" else None,
        also=(f"{v} is on an emergency call",) if call == "sentence" else ())
    if other in ("pedestrian", "cyclist"):
        pedestrian(run, "p1", crossing, type=other, speed=1.4 if other == "pedestrian" else 4.0)
    elif other == "pedestrian in its path":
        stepping_out(run, "p1", crossing)
    elif other is not None:
        north_car(run, "c2", crossing, brakes=other.startswith("car braking"),
                  decel=7.0 if other.endswith("at 7") else 5.0)
    found = judge(tmp_path, run)
    inc = one(found, v)
    verdict(inc, expected, "HC 176")
    margin(inc, "after red", "s", AMBULANCE_LAG, 0.05)
    for bystander in ("p1", "c2"):
        no_incident(found, bystander)


def test_emergency_vehicle_with_a_pedestrian_stated_approaching_by_the_camera(tmp_path):
    """Para 5(5) from core sentences alone: the camera says "p1 is approaching 253" and "p1 is of
    type pedestrian" while the ambulance (on a call) crosses on red: likely to endanger a person,
    punishable, HC 176."""
    v = "253"
    run, _, crossing, _ = runner_run(v, mps(28), AMBULANCE_LAG, "2 Hz", "camera", type="ambulance", emergency=True,
                                     also=(f"p1 is approaching {v}", "p1 is of type pedestrian"))
    inc = one(judge(tmp_path, run), v)
    verdict(inc, "punishable", "HC 176")
    margin(inc, "after red", "s", AMBULANCE_LAG, 0.05)


# ==================================================================================================
# 10. Speeding on and off a call (RTRA 1984 s.89, s.87)
# ==================================================================================================

SPEEDERS = [  # id, type, on a call, the law's verdict
    ("car-off-call", "car", False, "punishable"),
    ("ambulance-off-call", "ambulance", False, "punishable"),
    ("ambulance-on-call", "ambulance", True, "mitigated"),
    ("unmarked-police-car-on-call", "car", True, "mitigated"),
]


@pytest.mark.parametrize("type,on_call,expected", [s[1:] for s in SPEEDERS], ids=[s[0] for s in SPEEDERS])
@pytest.mark.parametrize("sampling", ["2 Hz", "irregular 2-10 Hz"])
def test_speeding_on_and_off_a_call(tmp_path, type, on_call, expected, sampling):
    """The road's limit is 30 mph (the map's speed_limit_mph); the vehicle is measured at 45 mph
    through a green junction. RTRA 1984 s.89 (HC 124): exceeding the limit is an offence,
    punishable. s.87: "No statutory speed limit applies to a vehicle on an occasion when it is
    being used for fire and rescue authority, ambulance, police or National Crime Agency
    purposes ... if observing the limit would be likely to hinder the use of the vehicle for
    the purpose": on a call (the purpose, not the type: an unmarked police car too), mitigated;
    an ambulance off a call is bound by the limit. Margin 15 mph over (± 0.1 mph: a constant
    speed reported to 1 mm/s)."""
    v = "28"
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=30))
    motion = Motion(-95.0, mps(45))
    run.spawn(v, type, emergency=True if on_call and type == "ambulance" else None)
    run.lights("J1", "west", [(0.0, "green")])
    extra = {"emergency": True} if on_call and type == "car" else None
    run.drive(v, motion, "west", SAMPLING[sampling](START, START + 9.0), t_start=START, extra=extra)
    run.watch(v, motion, "west", rate(5, START, START + 9.0), t_start=START)
    inc = one(judge(tmp_path, run), v, SPEEDING)
    verdict(inc, expected, "HC 124")
    margin(inc, "over the speed limit", "mph", 15.0, 0.1)


# ==================================================================================================
# 11. Sequence gaps around the act
# ==================================================================================================

def test_a_gap_in_the_vehicles_positions_around_a_crossing_well_into_red(tmp_path):
    """HC 176 / para 5(3). The car's own entity.state loses 4 events (0.8 s) around the
    crossing, 3 s after red. The samples either side of the hole are both well into red: the
    crossing still lies between them, on red (the car's speed is steady, so the moment
    interpolated across the hole is still right): punishable, HC 176, margin 3 s after red
    (± 0.05 s), and a "missing evidence" finding names the lost events of vehicle/7."""
    lag = 3.0
    run, motion, crossing, _ = runner_run("7", mps(28), lag, "5 Hz", "measured")
    states = [e for e in run.events if e["src"] == "vehicle/7" and e["kind"] == "entity.state"]
    around = sorted(states, key=lambda e: abs(e["t"] - states[0]["t"] - (crossing - START) * 1e9))[:4]
    run.drop("vehicle/7", [e["seq"] for e in around])
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 176")
    margin(inc, "after red", "s", lag, 0.05)
    gaps = [f for f in inc.findings if f.kind == "missing evidence" and f.src == "vehicle/7"]
    assert gaps, [(f.kind, f.detail) for f in inc.findings]


def test_a_lost_red_report_leaves_the_crossing_light_uncertain(tmp_path):
    """The west signal's report of red is lost (signal/J1-west seq 2): the record shows amber,
    then (after a gap in the signal's numbering) red and amber. A UK signal goes amber -> red ->
    red and amber, so the car crossed on amber or on red; either way it had been 45 m away when
    amber came, beyond rule 126's 23 m at 28 mph, so it could have stopped: punishable (HC 175
    for amber, HC 176 for red). A "missing evidence" finding names the signal's lost event, and
    the margin says the light is uncertain."""
    lag = 0.4
    run, motion, crossing, west = runner_run("7", mps(28), lag, "5 Hz", "measured")
    red = next(e for e in run.events if e["src"] == "signal/J1-west" and e["body"]["colour"] == "red")
    run.drop("signal/J1-west", [red["seq"]])
    inc = one(judge(tmp_path, run), "7")
    assert inc.verdict == "punishable" and inc.rule in ("HC 175", "HC 176"), (inc.verdict, inc.rule, inc.why)
    assert any(f.kind == "missing evidence" and f.src == "signal/J1-west" for f in inc.findings), \
        [(f.kind, f.detail) for f in inc.findings]
    assert inc.margin is not None and inc.margin.uncertain, inc.margin


def test_a_gap_across_the_onset_of_red_leaves_the_crossing_light_uncertain(tmp_path):
    """The car crosses 0.3 s after red, and its own positions and the camera's measurements of it
    are lost from 0.7 s before to 0.7 s after the crossing: the two samples around it bracket the
    change to red, so what it crossed on
    rests on the interpolation (exact here, at a steady speed, but not shown by a sample). It had
    been 43 m from the line when amber came (28 mph: rule 126's 23 m), so it could have stopped
    either way: punishable (HC 176, or HC 175 if taken as amber); the margin says its light is
    uncertain, and the lost events are a "missing evidence" finding."""
    lag = 0.3
    run, motion, crossing, _ = runner_run("7", mps(28), lag, "5 Hz", "measured")
    for src in ("vehicle/7", "monitor/m1"):
        gone = [e["seq"] for e in run.events if e["src"] == src and e["kind"] in ("entity.state", "monitor.observation")
                and abs(e["t"] - run.events[0]["t"] - crossing * 1e9) < 0.7e9]
        assert len(gone) >= 6
        run.drop(src, gone)
    inc = one(judge(tmp_path, run), "7")
    assert inc.verdict == "punishable" and inc.rule in ("HC 175", "HC 176"), (inc.verdict, inc.rule, inc.why)
    assert inc.margin is not None and inc.margin.uncertain, inc.margin
    assert any(f.kind == "missing evidence" and f.src == "vehicle/7" for f in inc.findings), \
        [(f.kind, f.detail) for f in inc.findings]


# ==================================================================================================
# Reactions that are not the emerging vehicle's doing (issue 12, the one-hour run's disagreements)
# ==================================================================================================

def _give_way_only() -> Foreign:
    """J1 with Give Way lines on its west and east arms: the main road runs north-south."""
    return Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds={"west": "give_way", "east": "give_way"})])


def test_a_main_road_car_braking_while_the_vehicle_still_waits_at_its_line_is_not_approaching_it(tmp_path):
    """HC 172: "You MUST give way to traffic on the main road when emerging". 7 waits 6 s at its
    Give Way line; meanwhile c2, on the main road from the north, brakes at 5 m/s² from 8 m/s and
    stands 32 m from the centre (to let someone out, say), 0.2 s before 7 sets off. When 7 emerges
    nobody on the main road is coming: c2 stands still, and its braking happened while 7 waited
    where the law asks it to wait. 7 gave way; no potential violation, no incident (the one-hour
    run's car 181 at j4 and the bus 3081 braking 2 s before it set off). Sampled at 4 Hz."""
    waits = Motion.stopping_at(-40.0, 8.0, -LINE_M - 0.5, wait=6.0, then=10.0)    # sets off at 12.875 s
    c2 = Motion(-38.4 - 8.0 * 11.1, 8.0, [(11.1, 0.0), (1.6, -5.0)])              # stands at -32 m from 12.7 s
    assert abs(c2.at(12.8)[0] + 32.0) < 0.01 and c2.at(12.8)[1] == 0.0
    run = _give_way_only()
    run.spawn("7")
    run.spawn("c2")
    times = rate(4, START, START + 22.0)
    run.drive("7", waits, "west", times, t_start=START)
    run.drive("c2", c2, "north", times, t_start=START)
    for user, motion, arm in (("7", waits, "west"), ("c2", c2, "north")):
        run.watch(user, motion, arm, times, t_start=START)
    found = judge(tmp_path, run)
    assert not any(f.sentence.startswith("c2 is approaching") for i in of(found, "7") for f in i.derived)
    no_incident(found, "7")
    no_incident(found, "c2")


def _turning_left_from_the_south(motion: Motion, t: float, radius: float = 6.0) -> tuple[float, float, float, float]:
    """x, y, heading and speed of a car coming up the south arm (x = -1.75) that turns left into the
    west arm (y = -1.75, heading west) on a quarter circle of `radius`: s along its path, 0 where
    the turn begins."""
    s, v = motion.at(t)
    start_y = -(LANE + radius)
    if s <= 0:
        return -LANE, start_y + s, 90.0, v
    arc = math.pi / 2 * radius
    if s <= arc:
        a = s / radius                                   # angle turned
        cx, cy = -(LANE + radius), start_y
        return cx + radius * math.cos(a), cy + radius * math.sin(a), 90.0 + math.degrees(a), v
    return -(LANE + radius) - (s - arc), -LANE, 180.0, v


def pull_out_before_a_left_turn(mine: Motion, c3: Motion, seconds: float) -> Foreign:
    """7 out of the west Give Way line on `mine`; c3 up the main road from the south on `c3`, turning
    left into the west arm, in its own entity.state and the camera's measurements (4 Hz); the camera
    states 7's sign and that c3 approaches on the main road."""
    run = _give_way_only()
    run.spawn("7")
    run.spawn("c3")
    times = rate(4, START, START + seconds)
    run.drive("7", mine, "west", times, t_start=START)
    for at in times:
        x, y, heading, v = _turning_left_from_the_south(c3, at - START)
        run.emit("vehicle/c3", ns(at), "entity.state",
                 {"x": round(x, 3), "y": round(y, 3), "heading_deg": heading, "speed_mps": round(v, 3)})
        run.emit("monitor/m1", ns(at), "monitor.observation",
                 {"vehicle": "c3", "facts": [], "speed_mps": round(v, 3), "x": round(x, 3), "y": round(y, 3)})
    run.watch("7", mine, "west", times, t_start=START,
              facts=camera("7", sign="give way", also=("c3 is approaching 7", "c3 is on the main road")))
    return run


def test_a_main_road_car_slowing_to_turn_into_the_arm_the_vehicle_leaves_was_not_forced(tmp_path):
    """7 pulls out of the west Give Way line at 6 m/s and goes straight on (7's lane: y = +1.75).
    c3, on the main road from the south, slows at 4 m/s² from 13.4 to 6 m/s as 7 crosses, and
    turns left into the west arm (its lane: y = -1.75, the other side of the road from 7's). Its
    path never comes within 3.5 m of 7's: there is no point where both could be, so it slowed for
    its own turn, not "to avoid an accident" with 7 (TSRGD Sch 9 Pt 7 para 1's words; HC 172's
    giving way is not making the main road's traffic change speed or course). 7 gave way: no
    violation, and no "would force" (the one-hour run's 1336 and 2850 at j4). Sampled at 4 Hz."""
    mine = Motion(-40.0, 6.0)                                     # crosses its line at 4.67 s
    c3 = Motion(-21.85 - 13.4 * 3.5, 13.4, [(3.5, 0.0), (1.85, -4.0), (3.0, 0.0), (5.0, 2.0)])
    found = judge(tmp_path, pull_out_before_a_left_turn(mine, c3, 16.0))
    assert of(found, "7"), "the camera's c3 approaching on the main road raises the act to judge"
    no_violation(found, "7")
    assert not any("would force c3" in f.sentence for i in of(found, "7") for f in i.derived)
    no_incident(found, "c3")


def test_a_main_road_car_whose_turn_outlasts_the_reaction_window_is_read_to_the_end_of_its_turn(tmp_path):
    """The same pull-out and the same turn of c3's, later: c3 brakes from 3.0 s after 7 crossed
    its line, after 7 has gone on; its turn into the west arm is not over until 1 s after the 3 s
    in which a reaction to 7 is counted. Whether its braking was for 7 or for its own turn is told
    by its way through the junction (3.5 m from 7's at the nearest: the other side of the road),
    so that way is read to its end, not cut where the reaction window closes; cut there, it showed
    no way at all and its braking was taken for 7's doing (the hour's 161 at j19, braking 4.3 m/s²
    into a left turn 1.75 s after 246 had left). 7 gave way: no violation, no "would force". 4 Hz."""
    mine = Motion(-40.0, 6.0)                                     # crosses its line at 4.67 s, out at 8.67 s
    c3 = Motion(-21.85 - 13.4 * 8.0, 13.4, [(8.0, 0.0), (1.85, -4.0), (3.0, 0.0), (5.0, 2.0)])
    found = judge(tmp_path, pull_out_before_a_left_turn(mine, c3, 24.0))
    assert of(found, "7"), "the camera's c3 approaching on the main road raises the act to judge"
    no_violation(found, "7")
    assert not any("would force c3" in f.sentence for i in of(found, "7") for f in i.derived)


def test_a_main_road_car_made_to_brake_hard_far_out_was_approaching(tmp_path):
    """HC 172 (RTA 1988 s.36, TSRGD Sch 9 Pts 7 and 8): "give way to traffic on the main road". c2
    comes down the main road at 30 mph and, 70 m out, brakes at 5 m/s² to 6 m/s as 7 pulls across
    from the Give Way line (the camera looks down the minor arm only; c2 is in its own record).
    Further out than the 50 m within which a road user is said to approach, but a car made to brake
    that hard by 7's pull-out, with nothing else to explain it, was approaching 7 when it did.
    Punishable, HC 172, margin c2's deceleration 5 m/s²."""
    c2 = Motion(-70.0 - 13.4 * 4.37, 13.4, [(4.37, 0.0), (1.48, -5.0), (3.0, 0.0), (5.0, 2.0)])
    run = unseen_main_road_run("give_way", Motion(-40.0, 6.0), camera("7", sign="give way"))
    run.drive("c2", c2, "north", SAMPLING["5 Hz"](START, START + 25.0), t_start=START)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 172")
    assert any(f.sentence == "c2 is approaching 7" for f in inc.derived)
    margin(inc, "deceleration", "m/s²", 5.0, 0.25)


def test_a_pedestrian_walking_towards_the_junction_along_the_main_road_is_not_main_road_traffic(tmp_path):
    """HC 172 and TSRGD 2016 Sch 9 Pts 7 and 8 protect "the driver of ... a vehicle on the major road":
    a Give Way line asks the emerging driver to give way to the main road's traffic. 7 pulls out of
    the west Give Way line with the main road empty of vehicles; p2 walks towards the junction down
    the main road's north arm, 30 m out. No vehicle was there to give way to, and p2 was not
    endangered (it stops at the kerb 13 m out): no incident (the hour's 1978 at j14 was judged
    'mitigated' for the pedestrian p2 35 m away, 'on the main road')."""
    run = unseen_main_road_run("give_way", Motion(-40.0, 6.0), camera("7", sign="give way"))
    pedestrian(run, "p2", START + 4.67)
    found = judge(tmp_path, run)
    no_incident(found, "7")
