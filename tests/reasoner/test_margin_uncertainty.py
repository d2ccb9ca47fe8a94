"""Every margin with its uncertainty, the sensors' stated tolerance, and the DSSAD record at the act
(issue 36). Written as a foreign producer writes a run (tests/helpers/foreign.py: DESIGN's events,
core vocabulary and measured fields, `tolerance` on a spawn or a map's monitor), with the law's
answer and its source beside each.

Each expected uncertainty is computed here from the raw events (the samples the margin cites, the
producer's stated tolerance), never read off the reasoner.
"""
from __future__ import annotations

import pytest

from reasoner.history import MPH_PER_MPS, STOPPED_MPS
from store import Store

from tests.helpers.foreign import LINE_M, Foreign, Motion, crossroads, ns, rate, roads_through
from tests.reasoner.test_foreign_scenarios import (BOX, ENTER, FORCED, SPEEDING, START, camera, cycle, give_way_run,
                                                   judge, mps, one, verdict)
from tests.reasoner.test_weighing import automated_red_runner, not_proven

SECOND = 1_000_000_000
MAX_DECEL = 4.0          # the braking (and pulling away) assumed possible between two samples (motion.MAX_DECEL_MPS2)


def events_of(run: Foreign, refs) -> list[dict]:
    keys = {(e["src"], e["seq"]): e for e in run.events}
    return [keys[(r.src, r.seq)] for r in refs]


# ==================================================================================================
# The Stop line (HC 171): whether it stopped, at the sampling interval the record has
# ==================================================================================================

# Slows from 10 m/s at 2 m/s² to 1.2 m/s 16 m before the centre (4 m before its line), rolls over
# the line at 1.2 m/s, and pulls away: it never stood still.
CREEPING = Motion(-60.0, 10.0, [(1.936, 0.0), (4.4, -2.0), (3.5, 0.0), (6.0, 2.0)])


def creeping_run(hz: float) -> Foreign:
    """A Stop junction (west and east arms); 7 creeps over the west Stop line, sampled at `hz` by
    its own record and by the camera alike, which states only the sign."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop_sign", "east": "stop_sign"})])
    run.spawn("7")
    times = rate(hz, START, START + 20.0)
    run.drive("7", CREEPING, "west", times, t_start=START)
    run.watch("7", CREEPING, "west", times, t_start=START, facts=camera("7", sign="stop"))
    return run


def slowest_possible(run: Foreign, hz: float) -> float:
    """From the raw entity.state: the slowest 7 can have been between two consecutive samples
    within 15 m before its line, braking and pulling away at MAX_DECEL, each speed less 0.1 m/s
    (the default tolerance: the producer states none)."""
    states = [e for e in run.events if e["src"] == "vehicle/7" and e["kind"] == "entity.state"]
    near = [(a, b) for a, b in zip(states, states[1:]) if -LINE_M - 15.0 <= b["body"]["x"] <= -LINE_M + 1.0]
    dt = 1.0 / hz
    return min(max(0.0, (a["body"]["speed_mps"] - 0.1 + b["body"]["speed_mps"] - 0.1 - MAX_DECEL * dt) / 2)
               for a, b in near)


def test_a_creep_over_a_stop_line_is_proved_at_10_hz(tmp_path):
    """HC 171: "You MUST stop behind the line at a junction with a 'Stop' sign" (RTA 1988 s.36,
    TSRGD 2016 Sch 9 Pt 7 para 1). At 10 Hz, samples 0.1 s apart at 1.2 m/s leave no time to stop
    and pull away again between them (the slowest possible is 0.9 m/s): it did not stop.
    Punishable, HC 171; the margin is its slowest measured speed before the line, 1.2 m/s
    (2.68 mph), with its uncertainty down to that slowest possible."""
    run = creeping_run(10)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    m = inc.margin
    assert m.quantity == "slowest measured speed before the Stop line" and m.unit == "mph", m
    assert abs(m.value - 1.2 * MPH_PER_MPS) <= 0.01, m
    lowest = slowest_possible(run, 10)
    assert lowest > STOPPED_MPS
    assert abs(m.uncertainty - (m.value - lowest * MPH_PER_MPS)) <= 0.02, (m.uncertainty, lowest)
    assert m.unproven is None


def test_the_same_creep_at_2_hz_is_not_proven(tmp_path):
    """The same creep sampled at 2 Hz: 0.5 s between samples at 1.2 m/s is time enough to brake
    to a standstill at the line and pull away unseen (4 m/s² each way), so the record cannot
    exclude the stop HC 171 requires. The prosecution must prove it did not stop: not proven
    (dismissed, "not proven:"), with the margin's uncertainty reaching a stop."""
    run = creeping_run(2)
    inc = one(judge(tmp_path, run), "7")
    not_proven(inc, "HC 171")
    m = inc.margin
    assert m.quantity == "slowest measured speed before the Stop line" and m.unproven, m
    assert slowest_possible(run, 2) <= STOPPED_MPS
    assert m.value - m.uncertainty <= STOPPED_MPS * MPH_PER_MPS + 0.01, m
    assert "could have stood still unseen" in inc.why, inc.why


# ==================================================================================================
# Give Way (HC 172): the other road user's deceleration, ± 2 x the speed tolerance over Δt
# ==================================================================================================

def test_a_give_way_margin_states_its_deceleration_uncertainty(tmp_path):
    """HC 172 (RTA 1988 s.36, TSRGD Sch 9 Pts 7 and 8): c2 brakes at 5 m/s² to a stop because 7
    pulled out: punishable. Its deceleration is the drop between two speed samples over the time
    between them, each speed known to ± 0.1 m/s (the default: the producer states none), so the
    margin is ± 2 × 0.1 / Δt, Δt read here from the two events the margin cites."""
    run = give_way_run(FORCED, "5 Hz", "measured")
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 172")
    m = inc.margin
    first, last = events_of(run, m.evidence)
    dt = (last["t"] - first["t"]) / SECOND
    assert abs(m.value - (first["body"]["speed_mps"] - last["body"]["speed_mps"]) / dt) <= 0.01, m
    assert m.uncertainty == pytest.approx(round(2 * 0.1 / dt, 2)), (m.uncertainty, dt)
    assert m.unproven is None
    assert "0.1 m, 0.1 m/s: the defaults" in m.method, m.method


# c2 brakes at 2.1 m/s² for 2 s (13.4 to 9.2 m/s) as 7 pulls out, and goes on: just over the
# 2 m/s² from which a change of speed is counted as forced, not by more than its uncertainty.
NEAR_THRESHOLD = Motion(-95.0, 13.4, [(4.67 - 0.3, 0.0), (2.0, -2.1), (12.0, 0.0)])


def test_a_braking_within_its_uncertainty_of_the_forcing_threshold_convicts_nobody(tmp_path):
    """HC 172 / TSRGD Sch 9 Pt 7 para 1(b): the emerging vehicle must not cause main-road traffic
    to change speed. Whether c2's 2.1 m/s² is a forced change of speed (FORCE_DECEL_MPS2 = 2 m/s²)
    is the deciding fact; measured to ± 0.2 m/s² (2 × 0.1 m/s over 1 s), it may have been under
    2: the fact is in doubt, so no conviction (before: punishable). The ground in doubt is not
    derived (derived.braked_hard), so no rule finds 7 forced c2 and the Give Way act is lawful as
    raised (mitigated, no penalty); its margin still says the braking and why it is not proven."""
    run = give_way_run(NEAR_THRESHOLD, "5 Hz", "measured")
    found = [i for i in judge(tmp_path, run) if i.vehicle == "7"]
    assert not [i for i in found if i.verdict == "punishable"], [(i.rule, i.why) for i in found]
    for inc in found:
        if inc.rule == "HC 172":
            assert inc.penalty is None and inc.liable == "none", (inc.verdict, inc.penalty, inc.liable)
            assert not [f for f in inc.derived if "would force c2" in f.sentence], inc.derived
            m = inc.margin
            assert m.unproven and 2.0 <= m.value <= 2.0 + m.uncertainty, m


# ==================================================================================================
# A box junction (HC 174): seconds stopped in the box, ± the sampling intervals either side
# ==================================================================================================

def box_run(stands_at_mps: float) -> Foreign:
    """J1 is a box junction; q1 stands queued on 7's exit; 7 drives in on green and stands (or
    crawls at `stands_at_mps`, as its own record and the camera measure it) inside the box for 6
    s. The camera watches both."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "lights", box=True)])
    mine = Motion(-60.0, 8.0, [(6.0, 0.0), (2.5, -3.2), (6.0, 0.0), (10.0, 2.0)])     # stands at s = -2
    queued = Motion(16.0, 0.0, [(14.5, 0.0), (10.0, 2.0)])
    run.spawn("7")
    run.spawn("q1")
    run.lights("J1", "west", [(0.0, "green")])
    measured = run.drive("7", mine, "west", rate(5, START, START + 24.0), t_start=START)
    measured += run.watch("7", mine, "west", rate(5, START, START + 24.0), t_start=START)
    for e in measured:
        if e["body"]["speed_mps"] == 0.0:
            e["body"]["speed_mps"] = stands_at_mps
    run.drive("q1", queued, "west", rate(2, START, START + 24.0), t_start=START)
    run.watch("q1", queued, "west", rate(5, START, START + 24.0), t_start=START)
    return run


def test_a_box_junction_margin_states_its_uncertainty(tmp_path):
    """HC 174: "You MUST NOT enter the box until your exit road or lane is clear" (TSRGD 2016
    Sch 9 Pts 7 and 8). 7 stands 6 s in the box with its exit queued: punishable. The seconds
    stopped run from its first still sample to its last, a lower bound ("at least"); it may have
    stood from the sample before the first to the one after the last, so ± those two intervals
    (0.2 s each at 5 Hz), read here from the raw states."""
    run = box_run(0.0)
    inc = one(judge(tmp_path, run), "7", BOX)
    verdict(inc, "punishable", "HC 174")
    m = inc.margin
    states = [e for e in run.events if e["src"] == "vehicle/7" and e["kind"] == "entity.state"]
    still = [i for i, e in enumerate(states) if e["body"]["speed_mps"] <= STOPPED_MPS]
    first, last = still[0], still[-1]
    expected = (states[first]["t"] - states[first - 1]["t"] + states[last + 1]["t"] - states[last]["t"]) / SECOND
    assert m.uncertainty == pytest.approx(expected), (m.uncertainty, expected)
    assert m.bound == "at least" and m.unproven is None
    assert abs(m.value - (states[last]["t"] - states[first]["t"]) / SECOND) <= 0.001, m


def test_a_crawl_in_the_box_within_the_speed_tolerance_of_a_stop_is_not_proven(tmp_path):
    """The same, but 7's record has it at 0.15 m/s where it stood: under 0.22 m/s (0.5 mph, so
    "stopped" as a speed rounds), yet with its speed known to ± 0.1 m/s it may have been moving at
    0.25 m/s, and whether it stopped in the box is the deciding fact of HC 174 (the box is not
    entered unlawfully by a vehicle that crosses it): not proven (before: punishable)."""
    inc = one(judge(tmp_path, box_run(0.15)), "7", BOX)
    not_proven(inc, "HC 174")
    assert inc.margin.unproven and "0.15 m/s" in inc.margin.unproven, inc.margin


# ==================================================================================================
# A producer's stated sensor tolerance
# ==================================================================================================

def speeding_run(v: str, mph: float, tolerance: dict | None = None) -> Foreign:
    """v drives a 30 mph road at a steady `mph`, its own entity.state at 5 Hz, past no camera."""
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=30), monitors=[])
    motion = Motion(-250.0, mps(mph))
    run.spawn(v, **({"tolerance": tolerance} if tolerance else {}))
    run.drive(v, motion, "west", rate(5, START, START + 30.0), t_start=START)
    return run


def test_speeding_by_1_mph_is_proved_at_the_default_tolerance(tmp_path):
    """RTRA 1984 s.81 and s.89: 31 mph on a 30 mph road is over the limit. Its own record states
    no tolerance, so the default (0.1 m/s, 0.22 mph) applies and the explanation says so:
    punishable, 1 mph ± 0.22 over."""
    inc = one(judge(tmp_path, speeding_run("5", 31.0)), "5", SPEEDING)
    verdict(inc, "punishable", "HC 124")
    assert inc.margin.uncertainty == pytest.approx(round(0.1 * MPH_PER_MPS, 2)), inc.margin
    assert "the defaults, its producer states none" in inc.margin.method, inc.margin.method


def test_a_coarse_stated_speed_tolerance_leaves_the_same_speeding_not_proven(tmp_path):
    """The same 31 mph, but the producer states its speed sensor to ± 1 m/s (2.24 mph) on the
    vehicle's spawn: 1 mph over is within it, so the speed over the limit is not proved (the
    prosecution proves the excess; a reading of 31 ± 2.2 mph does not): not proven. The margin
    cites the spawn that states the tolerance."""
    run = speeding_run("5", 31.0, {"position_m": 0.5, "speed_mps": 1.0})
    inc = one(judge(tmp_path, run), "5", SPEEDING)
    not_proven(inc, "HC 124")
    assert inc.margin.uncertainty == pytest.approx(round(1.0 * MPH_PER_MPS, 2)), inc.margin
    assert "stated by vehicle/5 #0 (entity.spawn)" in inc.margin.method, inc.margin.method


def test_a_monitors_stated_tolerance_in_the_map_is_its_measurements(tmp_path):
    """A camera vendor states in the map that its speeds are good to ± 1.5 m/s; the car, at 32
    mph on a 30 mph road, is measured by that camera only (no telemetry). 2 mph over is within
    ± 3.36 mph: not proven (RTRA 1984 s.89: the excess must be proved)."""
    cam = {"id": "m1", "junction": "J1", "x": 8.0, "y": 8.0, "heading_deg": 225.0, "range_m": 80.0,
           "fov_deg": 360.0, "tolerance": {"speed_mps": 1.5}}
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=30), monitors=[cam])
    motion = Motion(-70.0, mps(32.0))
    run.spawn("6")
    run.watch("6", motion, "west", rate(5, START, START + 10.0), t_start=START,
              facts=["6 has speed of 32", "the speed limit is 30"])
    run.violation("6", START + 2.0, SPEEDING, ["6 has speed of 32", "the speed limit is 30"])
    inc = one(judge(tmp_path, run), "6", SPEEDING)
    not_proven(inc, "HC 124")
    assert inc.margin.uncertainty == pytest.approx(round(1.5 * MPH_PER_MPS, 2)), inc.margin


@pytest.mark.parametrize("tolerance,problem", [({"speed_mps": -0.1}, "bigger than 0"),
                                               ({"position_m": "0.1"}, "must be number"),
                                               ({"position_m": 0}, "bigger than 0"),
                                               ("coarse", "must be object")])
def test_an_absurd_stated_tolerance_is_refused_with_its_field(tmp_path, tolerance, problem):
    """A tolerance that is negative, zero (no sensor is exact), or not a number says nothing a
    court could weigh: the spawn is refused (quarantined by the ingest) with the field named."""
    run = Foreign()
    run.spawn("7", tolerance=tolerance)
    with Store(tmp_path / "t.db") as store:
        report = store.append(run.events)
    assert len(report.rejected) == 1, report.rejected
    said = str(report.rejected[0])
    assert "body.tolerance" in said and problem in said, said


def test_an_absurd_tolerance_stated_for_a_monitor_in_the_map_is_refused_with_its_field(tmp_path):
    """The same for a monitor's entry in the run.start map: the field is named, with where."""
    cam = {"id": "m1", "junction": "J1", "x": 8.0, "y": 8.0, "heading_deg": 225.0, "range_m": 80.0,
           "fov_deg": 360.0, "tolerance": {"position_m": -2}}
    run = Foreign(monitors=[cam])
    run.spawn("7")
    with Store(tmp_path / "t.db") as store:
        report = store.append(run.events)
    said = str(report.rejected)
    assert len(report.rejected) == 1 and "monitors[0].tolerance.position_m" in said, said


# ==================================================================================================
# The DSSAD record (ads.event) at the act
# ==================================================================================================

def test_a_driver_override_just_before_the_act_makes_the_driver_liable(tmp_path):
    """Automated Vehicles Act 2024 (liability.le): while the self-driving feature is engaged the
    authorised self-driving entity answers; once the human overrides it (UN R157 5.4.4: a driver
    override deactivates the system), the human is the driver and answers for how the car is
    driven (RTA 1988 s.36, HC 176: £100 and 3 points). The camera flags the car 0.1 s before it
    reaches the line; the DSSAD records the override 0.05 s before the crossing: at the act the
    human drove. Before: the status at the camera's flag, so the ASDE."""
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=40))
    crossing = automated_red_runner(run, "7", override_after=-0.05, flag_after=-0.1)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 176")
    assert inc.liable == "driver", (inc.liable, inc.control)
    assert not inc.control.engaged
    assert inc.t < ns(crossing), "the camera's flag comes before the act"


def test_a_spawn_that_denies_the_automation_its_dssad_records_is_a_contradiction(tmp_path):
    """The spawn says a human drives 9 (SAE level 0), yet its DSSAD records the feature activated
    before it runs a red (HC 176). Who drove follows the DSSAD (AVA 2024; DESIGN "Reasoning": who
    was driving comes from the ads.event history), so the ASDE answers, and the other record's
    word against it is a contradiction finding, not silently overruled."""
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=40))
    motion = Motion(-95.0, mps(28))
    crossing = START + motion.when(-LINE_M)
    west = cycle(crossing - 2.0)
    run.emit("vehicle/9", ns(0.0), "entity.spawn", {"type": "car", "driver": "human", "automation_level": 0})
    run.lights("J1", "west", west)
    run.emit("vehicle/9", ns(0.5), "ads.event", {"event": "activated"})
    run.drive("9", motion, "west", rate(5, START, crossing + 6.0), t_start=START)
    run.watch("9", motion, "west", rate(5, START, crossing + 6.0), t_start=START, facts=camera("9", west))
    run.violation("9", crossing + 1.0, ENTER, ["9 has red light", "9 has crossed the stop line"])
    inc = one(judge(tmp_path, run), "9")
    verdict(inc, "punishable", "HC 176")
    assert inc.liable == "authorised self-driving entity", inc.liable
    said = [f for f in inc.findings if f.kind == "contradiction" and "entity.spawn" in f.detail]
    assert said and {r.kind for r in said[0].evidence} == {"entity.spawn", "ads.event"}, inc.findings
