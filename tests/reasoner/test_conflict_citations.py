"""Issue 35, what the first pass left open: the cited rule is the rule applied, and a cyclist is
traffic, endangered only where measured in or entering the vehicle's path. Scenarios as a foreign
producer writes them (tests/helpers/foreign.py), the law's answer beside each:

- TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): past a Stop line "so as to be likely to endanger any
  person or to cause the driver of another vehicle to change its speed or course"; Sch 14 Pt 1
  para 5(5) (HC 176): the same two limbs for a vehicle proceeding on red under the exemption;
- HC 172 / Sch 9 Pts 7 and 8: a cyclist on the major road is the driver of a vehicle there,
  traffic to give way to; it is endangered only when in or entering the vehicle's path within
  2 s of it (derived.ENDANGER_S), not for riding towards the junction.
"""
from __future__ import annotations

import json
import math

from tests.helpers.foreign import Foreign, Motion, crossroads, ns, rate
from tests.reasoner.test_conflict_scenarios import walk
from tests.reasoner.test_foreign_scenarios import (AMBULANCE_LAG, START, camera, STOPS_THEN_GOES, _SET_OFF, judge, mps,
                                                   no_violation, of, one, runner_run, stated_stop_camera,
                                                   unseen_main_road_run, verdict)


def _labels_of(node, sentence_part: str) -> set:
    """The labels of every proof node (in an incident's JSON) whose text says `sentence_part`."""
    found = set()
    if isinstance(node, dict):
        if sentence_part in str(node.get("text", "")) and node.get("rule") is not None:
            found.add(node.get("label"))
        for v in node.values():
            found |= _labels_of(v, sentence_part)
    elif isinstance(node, list):
        for v in node:
            found |= _labels_of(v, sentence_part)
    return found


def _ride(run, who: str, motion: Motion, arm: str) -> None:
    """A cyclist's own positions at 5 Hz (entity.state), its type in its entity.spawn."""
    run.spawn(who, "cyclist")
    run.drive(who, motion, arm, rate(5, START, START + 25.0), t_start=START)


def test_a_stop_sign_case_cites_the_stop_law_not_the_signals_exemption(tmp_path):
    """7 stops at its Stop line and pulls out; the camera states "7 would force p9 to change speed
    or course" of the pedestrian p9, nothing of whom is measured, so the statement stands alone
    (the explanation says so): a pedestrian made to change speed or course is endangered, para 1,
    punishable, HC 171. Every rule of the proof cites HC 171: the endangering it rests on is
    para 1's, not HC 176's (traffic lights, para 5(5)), which the proof cited on main."""
    said = ["7 would force p9 to change speed or course", "p9 is of type pedestrian"]
    stop = stated_stop_camera()
    run = unseen_main_road_run("stop", STOPS_THEN_GOES, lambda at, s_, v: stop(at, s_, v) + (said if s_ > -12 else []))
    run.drive("c2", Motion(-251.0, 13.4), "north", rate(5, START, START + 25.0), t_start=START)
    from explain.explanation_doc import document
    from explain.explanation_formats import render
    from reasoner.investigation import Investigation
    from store import Store

    run.end(START + 26.0)
    with Store(tmp_path / "s.db") as store:
        store.append(run.events)
        inv = Investigation(store)
        (inc,) = [i for i in inv.incidents(run.run) if i.vehicle == "7"]
        verdict(inc, "punishable", "HC 171")
        text = render(document(inc, inv.explanation(inc), store), "text", "full")
    doc = inc.to_json()
    assert _labels_of(doc, "would endanger p9") == {"HC 171"}, _labels_of(doc, "would endanger p9")
    assert "HC 176" not in json.dumps(doc) and "HC 176" not in text
    assert "would endanger p9 [HC 171" in text


def test_a_signals_case_cites_the_exemptions_endangering(tmp_path):
    """The control: an ambulance on a call crosses red 2 s after it came (para 5(4)); the camera
    states "p1 is approaching 253", nothing of p1 measured: para 5(5)'s "likely to endanger any
    person", punishable, HC 176, and the endangering rule of the proof is HC 176's."""
    run, _, _, _ = runner_run("253", mps(28), AMBULANCE_LAG, "5 Hz", "camera", type="ambulance", emergency=True,
                              also=("p1 is approaching 253", "p1 is of type pedestrian"))
    inc = one(judge(tmp_path, run), "253")
    verdict(inc, "punishable", "HC 176")
    assert _labels_of(inc.to_json(), "would endanger p1") == {"HC 176"}


# 7 (STOPS_THEN_GOES, west arm, along y = +1.75) reaches the main road's northbound lane (x = -1.75)
# 3.28 s after it set off (s = -12.5 + t² from its line, at 2 m/s²)
_AT_NORTHBOUND = _SET_OFF + math.sqrt(12.5 - 1.75)


def test_a_cyclist_riding_the_main_road_well_clear_of_the_vehicle_is_not_endangered(tmp_path):
    """b1 rides north on the main road at 5 m/s, 45 m south of the centre as 7 sets off, and keeps
    its speed: it reaches 7's path about 5 s after 7 has left it. The camera flags 7, stating "b1
    is approaching 7" and that b1 is a cyclist. The law: b1 is the driver of a vehicle on the
    major road (HC 172), not made to change speed or course, and never in or entering 7's path
    within 2 s of 7: no second limb of para 1, a lawful Stop. (A control: main also finds no
    offence here, the monitor rules raising nothing on a stated approach; the ambulance test below
    is the one where main read the cyclist's approach as danger.)"""
    run = unseen_main_road_run("stop", STOPS_THEN_GOES, stated_stop_camera())
    run.drive("c2", Motion(-251.0, 13.4), "north", rate(5, START, START + 25.0), t_start=START)
    _ride(run, "b1", Motion(-45.0 - 5.0 * _SET_OFF, 5.0), "south")
    run.violation("7", START + _SET_OFF + 1.0, "enter the junction",
                  ["7 has a stop sign", "7 has crossed the stop line", "b1 is approaching 7", "b1 is of type cyclist"])
    found = judge(tmp_path, run)
    assert of(found, "7"), "the camera's flag is judged"
    no_violation(found, "7")
    assert not any("endanger b1" in f.sentence for i in of(found, "7") for f in i.derived)


def test_a_cyclist_entering_the_vehicles_path_is_endangered_and_is_traffic(tmp_path):
    """b1 rides north on the main road at 5 m/s and reaches 7's path as 7 gets there, without
    slowing. The law: in 7's path as it comes, likely to be endangered (para 1): punishable,
    HC 171, on "7 would endanger b1", measured from the conflict (post-encroachment time 0), and
    no rule of the proof cites HC 176. (A control: main reaches the same verdict, reading the
    danger from b1's "approaching"; here "b1 is approaching 7", where derived, is traffic's
    closing on the junction, HC 172, not the danger.)"""
    run = unseen_main_road_run("stop", STOPS_THEN_GOES, stated_stop_camera())
    run.drive("c2", Motion(-251.0, 13.4), "north", rate(5, START, START + 25.0), t_start=START)
    _ride(run, "b1", Motion(1.75 - 5.0 * _AT_NORTHBOUND, 5.0), "south")
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    shown = {f.sentence: f for f in inc.derived}
    assert "7 would endanger b1" in shown, sorted(shown)
    assert "in or entering 7's path" in shown["7 would endanger b1"].method
    assert "b1 is approaching 7" not in shown or "from the centre" in shown["b1 is approaching 7"].method
    assert "HC 176" not in json.dumps(inc.to_json())


def test_a_camera_saying_a_cyclist_approaches_an_ambulance_is_not_danger_by_itself(tmp_path):
    """TSRGD 2016 Sch 14 Pt 1 para 5(5): an ambulance on a call may cross red, but not so as to be
    "likely to endanger any person". 253 crosses 2 s after red at 28 mph; the camera states "b1 is
    approaching 253" and "b1 is of type cyclist". b1, in its own record, rides north on the main
    road at 5 m/s, 40 m south of the centre as 253 crosses its line, keeps its speed and reaches
    253's path about 6 s after 253 has left it. A cyclist riding towards the junction is traffic
    (the driver of a vehicle), not a person endangered: b1 changed neither speed nor course and was
    never in or entering 253's path within 2 s of it. Mitigated, HC 176 (on main the rules read the
    cyclist's approach as endangering: punishable)."""
    v = "253"
    run, _, crossing, _ = runner_run(v, mps(28), AMBULANCE_LAG, "5 Hz", "camera", type="ambulance", emergency=True,
                                     also=(f"b1 is approaching {v}", "b1 is of type cyclist"))
    run.spawn("b1", "cyclist")
    run.drive("b1", Motion(-40.0 - 5.0 * (crossing - START), 5.0), "south", rate(5, START, crossing + 8.0),
              t_start=START)
    inc = one(judge(tmp_path, run), v)
    verdict(inc, "mitigated", "HC 176")
    assert not any("endanger b1" in f.sentence for f in inc.derived)


def _swerving(run, who: str, motion: Motion, arm: str, bump: tuple[float, float, float], times) -> None:
    """`who`'s own entity.state on `motion` (seconds from START), moved sideways by a smooth bump
    (start, end, metres east: a raised cosine), its heading following its way; speed kept."""
    start, end, width = bump
    for at in times:
        def east(t: float) -> float:
            if not start <= t <= end:
                return 0.0
            return width * (1 - math.cos(2 * math.pi * (t - start) / (end - start))) / 2
        x, y, _, v = run._where(motion, arm, "J1", at - START)
        x2, y2, _, _ = run._where(motion, arm, "J1", at - START + 0.05)
        dx, dy = (x2 + east(at - START + 0.05)) - (x + east(at - START)), y2 - y
        run.emit(f"vehicle/{who}", ns(at), "entity.state",
                 {"x": round(x + east(at - START), 3), "y": round(y, 3),
                  "heading_deg": round(math.degrees(math.atan2(dy, dx)) % 360.0, 2), "speed_mps": round(v, 3)})


# c2 keeps 13.4 m/s down the main road from the north along x = +1.75 (Motion(-164, 13.4) from START):
# at 7's lane (y = +1.75) 12.11 s after START, where 7 (STOPS_THEN_GOES) is 0.5 s later
_C2_AT_7S_LANE = (164.0 - 1.75) / 13.4


def test_a_main_road_car_that_swerves_round_the_pulling_out_vehicle_without_braking_was_forced(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 forbids crossing the Stop line "so as to ... cause the driver
    of another vehicle to change its speed or course in order to avoid an accident". 7 stops and
    pulls out; c2, on the main road at 30 mph and on course to meet 7 where their paths cross
    (about 0.5 s apart), keeps its speed and swerves 3 m to its left round 7's front, then goes on
    down the main road. A change of course, not of speed, made to avoid an accident with 7:
    punishable, HC 171, the swerve named with its measured offset, its threshold (1 m) and the
    post-encroachment time c2 would have had on its line. (On main only braking counted: no
    violation.) In c2's own record only, as the town cameras see a main road."""
    run = unseen_main_road_run("stop", STOPS_THEN_GOES, stated_stop_camera())
    _swerving(run, "c2", Motion(-164.0, 13.4), "north",
              (_C2_AT_7S_LANE - 1.6, _C2_AT_7S_LANE + 1.6, 3.0), rate(5, START, START + 25.0))
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    forced = next((f for f in inc.derived if f.sentence == "7 would force c2 to change speed or course"), None)
    assert forced is not None, [f.sentence for f in inc.derived]
    assert "changed course" in forced.method and "from 1 m" in forced.method, forced.method
    assert "braked" not in forced.method


def test_a_main_road_car_keeping_its_line_well_clear_is_not_forced_by_a_lane_drift(tmp_path):
    """The control: the same 3 m sideways move by c2, but 87 m further back (Motion(-251, 13.4)),
    so that on its line it would have reached 7's path long after 7 left it: no accident to avoid,
    so no change of course caused by 7. A lawful Stop: no violation, no "would force c2"."""
    run = unseen_main_road_run("stop", STOPS_THEN_GOES, stated_stop_camera())
    late = (251.0 - 1.75) / 13.4
    _swerving(run, "c2", Motion(-251.0, 13.4), "north", (late - 1.6, late + 1.6, 3.0), rate(5, START, START + 25.0))
    found = judge(tmp_path, run)
    no_violation(found, "7")
    assert not any("would force c2" in f.sentence for i in of(found, "7") for f in i.derived)


def test_a_cyclist_on_the_main_road_made_to_brake_by_a_give_way_emergence_is_traffic_given_way_to(tmp_path):
    """HC 172: "You MUST give way to traffic on the main road" (RTA 1988 s.36, TSRGD 2016 Sch 9
    Pts 7 and 8: not to cause "the driver of a vehicle on the major road" to change its speed or
    course). b1, a cyclist on the main road, the driver of a vehicle, rides at 6 m/s towards 7's
    path, where unslowed it would have met 7, and brakes at 3 m/s² from 1.5 s before 7 crosses its
    Give Way line to a stop 9 m short of the centre, going on once 7 has gone. It never entered 7's path (not endangered) but it
    was traffic 7 had to give way to and was made to change speed: punishable, HC 172 (on main a
    cyclist was read as approaching only when in or entering V's path, so 7 owed it nothing).
    Both in the road users' own records and a camera's measurements."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds={"west": "give_way", "east": "give_way"})])
    run.spawn("7")
    mine = Motion(-40.0, 6.0)                   # over its line (s = -12) 4.67 s after START
    brakes = 4.67 - 1.5                         # from 15 m short of the centre, to a stop 9 m short of it
    ride = Motion(-15.0 - 6.0 * brakes, 6.0, [(brakes, 0.0), (2.0, -3.0), (4.0, 0.0), (6.0, 1.0)])
    times = rate(5, START, START + 16.0)
    run.drive("7", mine, "west", times, t_start=START)
    run.watch("7", mine, "west", times, t_start=START, facts=camera("7", sign="give way"))
    run.spawn("b1", "cyclist")
    run.drive("b1", ride, "north", times, t_start=START)
    run.watch("b1", ride, "north", times, t_start=START)
    found = judge(tmp_path, run)
    inc = one(found, "7")
    verdict(inc, "punishable", "HC 172")
    shown = {f.sentence for f in inc.derived}
    assert {"b1 is approaching 7", "b1 is on the main road", "7 would force b1 to change speed or course"} <= shown
    assert "7 would endanger b1" not in shown
