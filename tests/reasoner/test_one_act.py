"""One act, one offence; the whole record; penalties by road user; the map's stop-line kinds
(issue 36), written as a foreign producer writes a run (tests/helpers/foreign.py): DESIGN's
events, its core sentences and measured fields, nothing of ours.

The law's answer and its source stand beside each test. The shared notes
(docs/legal/road-junctions-170-183.md, "Notes on the table"): "One act, one offence.
A single passage through a junction or a single continuous stretch over a limit is one offence,
however many cameras recorded it; a court would not convict twice on the same act."
"""
from __future__ import annotations

import json

import pytest

from tests.helpers.cli import gaps
from tests.helpers.foreign import DIRECTION, Foreign, Motion, crossroads, rate, roads_through
from tests.reasoner.test_foreign_scenarios import (BOX, ENTER, SPEEDING, START, camera, cross_cycle, cycle, judge,
                                                   mps, of, one, verdict)

LIMIT_MPH = 30


def monitor(ident: str, x: float, y: float, heading: float) -> dict:
    return {"id": ident, "junction": "J1", "x": x, "y": y, "heading_deg": heading, "range_m": 80.0, "fov_deg": 360.0}


THREE = [monitor("m1", 8.0, 8.0, 225.0), monitor("m2", -8.0, -8.0, 45.0), monitor("m3", 8.0, -8.0, 135.0)]


def runner(v: str, speed: float, lag: float, *, monitors: list[dict] | None = None, junction: dict | None = None,
           type: str = "car", cameras: tuple[str, ...] = ()) -> tuple[Foreign, Motion, float, list]:
    """v drives straight through J1 from the west at `speed`, crossing its line `lag` s after the
    west signal turned red, in its own 5 Hz telemetry; each of `cameras` watches it at 5 Hz
    stating the light, the crossing and the junction (the cameras of `monitors`, J1 as given)."""
    run = Foreign(junctions=[junction or crossroads("J1", 0.0, 0.0, "lights")],
                  roads=roads_through(0.0, 0.0, limit_mph=40), monitors=monitors or THREE[:1])
    motion = Motion(-95.0, speed)
    crossing = START + motion.when(-12.0)
    west = cycle(crossing - lag)
    run.spawn(v, type)
    run.lights("J1", "west", west)
    run.lights("J1", "north", cross_cycle(crossing - lag))
    run.drive(v, motion, "west", rate(5, START, crossing + 8.0), t_start=START)
    for m in cameras:
        run.watch(v, motion, "west", rate(5, START, crossing + 8.0), t_start=START, monitor=m, facts=camera(v, west))
    return run, motion, crossing, west


def srcs(inc) -> set[str]:
    return {s.src for s in inc.sources}


def cited(inc) -> set[str]:
    return {ref.src for ref in inc.evidence}


# ==================================================================================================
# 1. One act, one offence
# ==================================================================================================

def test_two_cameras_on_one_red_light_passage_are_one_incident_and_one_penalty(tmp_path):
    """7 crosses its line 2 s into red at 30 mph, once. Cameras m1 and m2 both watch the stop line,
    state the light and the crossing, and each flags it a second after the crossing. HC 176 / RTA
    1988 s.36: one passage over the line on red, one traffic light offence: one incident, £100 and
    3 points once (RTOA 1988 Sch 2; Fixed Penalty Order 2000), both cameras cited."""
    run, _, crossing, _ = runner("7", mps(30), 2.0, monitors=THREE[:2], cameras=("m1", "m2"))
    for m in ("m1", "m2"):
        run.violation("7", crossing + 1.0, ENTER, ["7 has red light", "7 has crossed the stop line"], monitor=m)
    found = judge(tmp_path, run)
    inc = one(found, "7")
    verdict(inc, "punishable", "HC 176")
    assert (inc.penalty.fine_gbp, inc.penalty.points) == (100, 3), inc.penalty
    assert {"monitor/m1", "monitor/m2"} <= srcs(inc), inc.sources
    assert {"monitor/m1", "monitor/m2"} <= cited(inc), cited(inc)
    assert inc.act is not None and inc.act.kind == "junction passage" and inc.act.where == "J1", inc.act
    assert inc.found_in == "monitors"


def test_two_cameras_on_one_speeding_passage_are_one_offence(tmp_path):
    """28 drives through J1 at a steady 45 mph on a 30 mph road, seen by two cameras 0.2 s apart
    (the issue's "two £100 + 3 points 0.2 s apart"). RTRA 1984 s.89: one continuous stretch over
    the limit, one speeding offence, one £100 + 3 points."""
    v = "28"
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=LIMIT_MPH), monitors=THREE[:2])
    motion = Motion(-95.0, mps(45))
    run.spawn(v)
    run.lights("J1", "west", [(0.0, "green")])
    run.drive(v, motion, "west", rate(5, START, START + 9.0), t_start=START)
    said = [f"{v} has speed of 45", "the speed limit is 30"]           # each camera states what it measured
    run.watch(v, motion, "west", rate(5, START, START + 9.0), t_start=START, monitor="m1", facts=said)
    run.watch(v, motion, "west", rate(5, START + 0.2, START + 9.0), t_start=START, monitor="m2", facts=said)
    found = judge(tmp_path, run)
    inc = one(found, v, SPEEDING)
    verdict(inc, "punishable", "HC 124")
    assert (inc.penalty.fine_gbp, inc.penalty.points) == (100, 3), inc.penalty
    assert {"monitor/m1", "monitor/m2"} <= srcs(inc), inc.sources
    assert inc.act is not None and inc.act.kind == "speeding stretch", inc.act


def test_one_vehicle_at_one_junction_seen_by_three_monitors_is_one_incident(tmp_path):
    """One red-light crossing at J1 (3 s into red, 25 mph) watched by three cameras, which flag it
    at different moments of the one passage: m1 as the car nears the line on red, m2 at the
    crossing, m3 as it crosses the junction 4 s later (the issue's three penalties, 9 points,
    within 6 s at one junction). HC 176: one act, one offence, one penalty, three cameras cited."""
    run, _, crossing, _ = runner("7", mps(25), 3.0, monitors=THREE, cameras=("m1", "m2", "m3"))
    run.violation("7", crossing - 0.5, ENTER, ["7 has red light"], monitor="m1")
    run.violation("7", crossing + 0.2, ENTER, ["7 has red light", "7 has crossed the stop line"], monitor="m2")
    run.violation("7", crossing + 4.0, ENTER, ["7 has red light", "7 has crossed the stop line",
                                               "7 is in the junction"], monitor="m3")
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 176")
    assert (inc.penalty.fine_gbp, inc.penalty.points) == (100, 3), inc.penalty
    assert {"monitor/m1", "monitor/m2", "monitor/m3"} <= srcs(inc), inc.sources


def test_two_stretches_over_the_limit_apart_are_two_offences(tmp_path):
    """The other side of "one act": 7 does 40 mph for 8 s, eases to 20 mph for 10 s, then 40 mph
    again, all in its own telemetry far from any junction. Two continuous stretches over the limit
    (apart by far more than the stated gap tolerance), two acts: two speeding offences (s.89)."""
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=LIMIT_MPH, length=2000.0))
    fast, slow = mps(40), mps(20)
    motion = Motion(-1800.0, fast, [(8.0, 0.0), (2.0, (slow - fast) / 2.0), (10.0, 0.0), (2.0, (fast - slow) / 2.0),
                                    (8.0, 0.0)])
    run.spawn("7")
    run.drive("7", motion, "west", rate(10, START, START + 30.0), t_start=START)
    mine = of(judge(tmp_path, run), "7")
    assert [i.action for i in mine] == [SPEEDING, SPEEDING], [(i.id, i.action, i.t) for i in mine]
    assert all(i.verdict == "punishable" for i in mine), [(i.verdict, i.why) for i in mine]


# ==================================================================================================
# 2. The whole record
# ==================================================================================================

def test_a_camera_stating_only_the_light_beside_the_cars_own_positions_finds_the_red_crossing(tmp_path):
    """The camera vendor's feed states the light facing 7 at each frame ("7 has red light") but
    not the crossing; 7's own telemetry gives its positions at 10 Hz; no signal controller feed.
    7 crosses its line 2 s into red. HC 176 / TSRGD 2016 Sch 14 Pt 1 para 5(3): proceeding beyond
    the stop line on red is the offence, whoever recorded which half of it: punishable."""
    run = Foreign()
    motion = Motion(-95.0, mps(30))
    crossing = START + motion.when(-12.0)
    west = cycle(crossing - 2.0)
    run.spawn("7")
    run.drive("7", motion, "west", rate(10, START, crossing + 8.0), t_start=START)
    run.watch("7", motion, "west", rate(5, START, crossing + 8.0), t_start=START,
              facts=lambda at, s, speed: [f"7 has {c} light" for c in _colours(west, at)])
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 176")
    assert "vehicle/7" in srcs(inc) and "monitor/m1" in srcs(inc), inc.sources
    assert inc.found_in == "monitors and own-record", inc.found_in


def _colours(changes: list[tuple[float, str]], at: float) -> list[str]:
    shown = [c for t, c in changes if t <= at]
    return {"red_amber": ["red", "amber"]}.get(shown[-1], [shown[-1]]) if shown else []


def speeding_in_own_telemetry() -> Foreign:
    """7 does 40 mph for 10 s on a 30 mph road 250 m from J1, in its own 10 Hz telemetry only;
    J1's camera sees 9 drive through lawfully (so the run has monitor observations)."""
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=LIMIT_MPH, length=600.0))
    run.spawn("7")
    run.spawn("9")
    run.lights("J1", "west", [(0.0, "green")])
    run.drive("7", Motion(-560.0, mps(40)), "west", rate(10, START, START + 10.0), t_start=START)
    slow = Motion(-60.0, mps(25))
    run.drive("9", slow, "west", rate(10, START, START + 8.0), t_start=START)
    run.watch("9", slow, "west", rate(5, START, START + 8.0), t_start=START)
    return run


def test_speeding_only_in_the_vehicles_own_telemetry_is_found_and_says_so(tmp_path):
    """RTRA 1984 s.89: 40 mph against a 30 mph limit is an offence whichever record shows it;
    no camera saw it, so the incident says it was found only in the vehicle's own record.
    Punishable, HC 124, £100 + 3 points, about 10 mph over (40 mph steady, ± 0.1)."""
    inc = one(judge(tmp_path, speeding_in_own_telemetry()), "7", SPEEDING)
    verdict(inc, "punishable", "HC 124")
    assert inc.found_in == "own-record" and srcs(inc) == {"vehicle/7"}, inc.sources
    assert (inc.penalty.fine_gbp, inc.penalty.points) == (100, 3), inc.penalty
    assert inc.margin is not None and abs(inc.margin.value - 10.0) <= 0.1, inc.margin
    assert inc.to_json()["found_in"] == "own-record"


def test_gaps_incidents_lists_the_own_record_acts_apart(tmp_path):
    """`gaps incidents --source own-record` lists the acts only the vehicle's own record shows;
    `--source monitors` the others; the JSON says where each was found."""
    from store import Store
    run = speeding_in_own_telemetry()
    run.end(20.0)
    db = tmp_path / "own.db"
    with Store(db) as store:
        store.append(run.events)
    own = gaps("incidents", "--run", run.run, "--source", "own-record", "--json", db=db)
    assert own.exit_code == 0, own.output
    listed = json.loads(own.stdout)
    assert [(i["vehicle"], i["action"], i["found_in"]) for i in listed] == [("7", SPEEDING, "own-record")], listed
    assert listed[0]["sources"][0]["src"] == "vehicle/7"
    cams = gaps("incidents", "--run", run.run, "--source", "monitors", "--json", db=db)
    assert cams.exit_code == 0 and json.loads(cams.stdout) == [], cams.output
    bad = gaps("incidents", "--run", run.run, "--source", "camera", db=db)
    assert bad.exit_code != 0 and "unknown source 'camera'" in bad.output, bad.output


# ==================================================================================================
# 3. Penalties by road user and offence
# ==================================================================================================

def test_a_cyclist_on_red_gets_the_non_endorsable_penalty(tmp_path):
    """A pedal cyclist crosses the stop line 2 s into red. RTA 1988 s.36 applies to any vehicle
    (HC 176: punishable), but RTOA 1988 Sch 2 Pt I makes the s.36 offence endorsable only when it
    is committed in respect of a motor vehicle: the non-endorsable fixed penalty, £50, no points
    (the shared notes, "Pedal cycles")."""
    run, _, _, _ = runner("c1", mps(15), 2.0, type="cyclist", cameras=("m1",))
    inc = one(judge(tmp_path, run), "c1")
    verdict(inc, "punishable", "HC 176")
    assert (inc.penalty.fine_gbp, inc.penalty.points) == (50, 0), inc.penalty


def test_a_cyclist_rolling_over_a_stop_line_gets_the_non_endorsable_penalty(tmp_path):
    """A pedal cyclist rides over a Stop sign's line at 15 mph without stopping: HC 171 (RTA 1988
    s.36, TSRGD 2016 Sch 9 Pt 7), punishable; RTOA 1988 Sch 2 Pt I endorses the s.36 offence only
    in respect of a motor vehicle: £50, no points."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop")])
    motion = Motion(-95.0, mps(15))
    run.spawn("c2", "cyclist")
    run.drive("c2", motion, "west", rate(5, START, START + 16.0), t_start=START)
    run.watch("c2", motion, "west", rate(5, START, START + 16.0), t_start=START)
    inc = one(judge(tmp_path, run), "c2")
    verdict(inc, "punishable", "HC 171")
    assert (inc.penalty.fine_gbp, inc.penalty.points) == (50, 0), inc.penalty


def test_a_box_junction_contravention_is_non_endorsable(tmp_path):
    """HC 174 (TSRGD 2016 Sch 9 Pts 7 and 8): 7 enters the yellow box on green and stands in it for
    6 s with its exit queued, and the light turns red while it stands there (it crossed its line
    on green: no red-light act). The box contravention is not endorsable (no entry in RTOA 1988
    Sch 2; the working table: £50, no points)."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "lights", box=True)])
    mine = Motion(-60.0, 8.0, [(6.0, 0.0), (2.5, -3.2), (6.0, 0.0), (10.0, 2.0)])   # stands at s = -2
    queued = Motion(16.0, 0.0, [(14.5, 0.0), (10.0, 2.0)])
    crossing = START + mine.when(-12.0)
    west = cycle(crossing + 4.0)
    run.spawn("7")
    run.spawn("q1")
    run.lights("J1", "west", west)
    run.drive("7", mine, "west", rate(5, START, START + 24.0), t_start=START)
    run.drive("q1", queued, "west", rate(2, START, START + 24.0), t_start=START)
    run.watch("7", mine, "west", rate(5, START, START + 24.0), t_start=START, facts=camera("7", west))
    run.watch("q1", queued, "west", rate(5, START, START + 24.0), t_start=START)
    found = judge(tmp_path, run)
    boxed = [i for i in of(found, "7") if i.action == BOX]
    assert len(boxed) == 1, [(i.id, i.action, i.verdict, i.rule) for i in of(found, "7")]
    verdict(boxed[0], "punishable", "HC 174")
    assert (boxed[0].penalty.fine_gbp, boxed[0].penalty.points) == (50, 0), boxed[0].penalty
    assert not [i for i in of(found, "7") if i.verdict == "punishable" and i.action != BOX], \
        [(i.id, i.action, i.verdict, i.rule, i.penalty) for i in of(found, "7")]


# ==================================================================================================
# 4. The map contract: a stop line's kind
# ==================================================================================================

def test_a_stop_line_written_stop_at_traffic_signals_is_judged_under_the_signal_rule(tmp_path):
    """The producer writes `kind: "stop"` for every stop line of a signal junction (`control:
    "lights"`). DESIGN's map: a bare "stop" is read by the junction's control, lights → the
    line at signals (TSRGD diagram 1001), and the reading is reported. 7 crosses 2 s into red at
    30 mph without stopping: HC 176 (not HC 171, the Stop sign's rule), punishable; the reading
    is a finding."""
    run, _, _, _ = runner("7", mps(30), 2.0, junction=crossroads("J1", 0.0, 0.0, "lights",
                                                                 kinds={a: "stop" for a in DIRECTION}))
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 176")
    readings = [f for f in inc.findings if f.kind == "map reading"]
    assert readings and "read as 'signal'" in readings[0].detail and "'lights'" in readings[0].detail, inc.findings
    assert not any("has a stop sign" in f.sentence for f in inc.derived), inc.derived


def test_a_stop_line_written_stop_at_a_stop_junction_is_the_stop_signs_line(tmp_path):
    """The same word at a junction whose control is "stop" is the Stop sign's line (diagram
    1002.1): a car that rolls over it at 20 mph without stopping breaks HC 171 (RTA 1988 s.36),
    punishable, and the reading is reported."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={a: "stop" for a in DIRECTION})])
    motion = Motion(-95.0, mps(20))
    run.spawn("7")
    run.drive("7", motion, "west", rate(5, START, START + 12.0), t_start=START)
    run.watch("7", motion, "west", rate(5, START, START + 12.0), t_start=START)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    assert any(f.kind == "map reading" and "read as 'stop_sign'" in f.detail for f in inc.findings), inc.findings


def test_the_one_incident_is_found_by_any_of_its_records_ids(tmp_path):
    """The merged incident is named by its earliest record; `gaps explain`/`case.incident` find
    it by the id of any record of the act, and its explanation says it is one act of several
    records."""
    import reasoner
    from explain import explanation
    run, _, crossing, _ = runner("7", mps(30), 2.0, monitors=THREE[:2], cameras=("m1", "m2"))
    run.violation("7", crossing + 1.0, ENTER, ["7 has red light", "7 has crossed the stop line"], monitor="m1")
    second = run.violation("7", crossing + 1.5, ENTER, ["7 has red light", "7 has crossed the stop line"],
                           monitor="m2")
    inc = one(judge(tmp_path, run), "7")
    with reasoner.open(tmp_path / "foreign.db") as case:
        found = case.incident(run.run, f"monitor/m2:{second['seq']}")
        assert found.id == inc.id and found.id != f"monitor/m2:{second['seq']}"
        text = " ".join(explanation(case, found, level="full").split())
    assert "one act, 2 records of it, judged as one" in text, text[:2000]


def test_records_of_one_act_judged_differently_give_the_proved_verdict_and_say_so(tmp_path, monkeypatch):
    """reasoner/oneact.py's rule, on the two cameras' records of one red-light passage: where one
    record is dismissed and another proves the act, the incident takes the proof (a camera whose
    own record does not support its flag does not undo another's), names the disagreement as a
    finding, and keeps the earliest monitor record's id."""
    from dataclasses import replace

    from reasoner import oneact
    run, _, crossing, _ = runner("7", mps(30), 2.0, monitors=THREE[:2], cameras=("m1", "m2"))
    for m in ("m1", "m2"):
        run.violation("7", crossing + 1.0, ENTER, ["7 has red light", "7 has crossed the stop line"], monitor=m)
    monkeypatch.setattr(oneact, "groups", lambda found: [[i] for i in found])
    apart = of(judge(tmp_path, run), "7")
    assert len(apart) >= 2 and all(i.verdict == "punishable" for i in apart), [(i.id, i.verdict) for i in apart]
    first, second = apart[0], apart[1]
    merged = oneact.merge([replace(first, verdict="dismissed", penalty=None, why="unsupported"), second])
    assert (merged.verdict, merged.penalty) == ("punishable", second.penalty)
    assert merged.id == first.id and [s.id for s in merged.sources][:2] == [first.id, second.id]
    said = [f.detail for f in merged.findings if f.kind == "sources disagree"]
    assert said and f"{first.id}" in said[0] and "dismissed" in said[0] and "punishable" in said[0], merged.findings
