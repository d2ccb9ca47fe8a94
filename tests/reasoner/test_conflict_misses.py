"""Issue 35, the misses: road users SUMO's own account says gave way to the vehicle, which the
reasoner had put down to something else. Scenarios written as a foreign producer writes them
(tests/helpers/foreign.py: positions at 5 Hz, core sentences only), the law's answer beside each:

- HC 172 (RTA 1988 s.36, TSRGD 2016 Sch 9 Pts 7 and 8): at a Give Way line, give way to traffic
  on the major road; TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): no vehicle may proceed past a Stop
  line "so as to be likely to ... cause the driver of another vehicle to change its speed or course
  in order to avoid an accident";
- a change of speed counts from 2 m/s² beyond its uncertainty (reaction.FORCE_DECEL_MPS2, Hupfer
  1997), made "to avoid an accident" with the vehicle where, unslowed, the other would have come
  within 2 s of it where their paths meet (conflicts.PET_MAX_S, SUMO's SSM device PET threshold).
"""
from __future__ import annotations

import math

from tests.helpers.foreign import Foreign, Motion, crossroads, ns, rate
from tests.reasoner.test_foreign_scenarios import START, camera, judge, one, stop_then_go_run, verdict

GIVE_WAY = {"west": "give_way", "east": "give_way"}


def test_a_car_still_to_stand_at_its_line_when_the_main_road_car_braked_is_not_what_it_braked_for(tmp_path):
    """HC 172: 7 comes out of its Give Way line (west arm) at 6 m/s without slowing, straight
    across the junction. c2, on the major road from the north at 13.4 m/s, brakes at over 4 m/s²
    for a second from 20 m short of their conflict zone, 1.3 s after 7 left it: unslowed it would
    have come into the zone 1.51 s after 7 left it (a near miss). 8, behind 7 on the same arm, is
    then still braking to its line; it stands there from 0.2 s after c2 began to slow for 0.3 s,
    and then pulls out behind c2 (its zone 1.33 s after where unslowed c2 would have left it).
    c2's braking began while 8 was yet to stand where the law asks it to wait: 8's proceeding came
    after it and is not what c2 braked for; 7's crossing in front of it is. Punishable, HC 172,
    "7 would force c2" (the town run's 279, braking at 4.5 m/s² as the cyclist 114 rode out of its
    Give Way line while 108 braked to stand at it; SUMO's account: foe 114, held 2.55 m/s². On
    main, 108's later crossing, its projected gap the smaller, took the braking off 114.)"""
    onset = 7.67                      # c2's onset, s from START; 8 stands from 7.8 to 8.1
    seven = Motion(-40.0, 6.0)
    c2 = Motion(-24.7 - 13.4 * onset, 13.4, [(onset, 0.0), (1.0, -4.5), (30.0, 0.0)])
    eight = Motion(-12.5 - 8.0 - 8.0 * (7.8 - 2.0), 8.0, [(7.8 - 2.0, 0.0), (2.0, -4.0), (0.3, 0.0), (10.0, 2.5)])
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds=GIVE_WAY)])
    times = rate(5, START, START + 25.0)
    for who, motion in (("7", seven), ("c2", c2), ("8", eight)):
        arm = "north" if who == "c2" else "west"
        run.spawn(who)
        run.drive(who, motion, arm, times, t_start=START)
        run.watch(who, motion, arm, times, t_start=START, facts=["7 has a give way sign"] if who == "7" else None)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 172")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived), \
        [(f.sentence, f.method) for f in inc.derived]


TURN_R = 10.0                       # 7's right turn: a quarter circle from heading east (y = +1.75) to south (x = +1.75)


def _turning_right(d: float) -> tuple[float, float, float]:
    """x, y and heading of 7 d metres along its way from (-40, +1.75): east along its arm, a right
    turn of radius TURN_R inside the junction, then south down the major road's lane (x = +1.75)."""
    straight = 1.75 - TURN_R + 40.0
    if d <= straight:
        return -40.0 + d, 1.75, 0.0
    if d <= straight + TURN_R * math.pi / 2:
        th = (d - straight) / TURN_R
        return 1.75 - TURN_R + TURN_R * math.sin(th), 1.75 - TURN_R + TURN_R * math.cos(th), -math.degrees(th) % 360.0
    return 1.75, 1.75 - TURN_R - (d - straight - TURN_R * math.pi / 2), 270.0

def _stop_and_turn_right(seven: Motion) -> tuple[Foreign, list[float]]:
    """A run at a crossroads with Stop lines on its west and east arms: 7 comes in from the west
    along `seven` and turns right into the major road (`_turning_right`), its positions at 5 Hz
    and a Stop camera's observations of it; the other road users are added by the caller."""
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop", "east": "stop"})])
    run.spawn("7")
    times = rate(5, START, START + 30.0)
    stop_camera = camera("7", sign="stop")
    for at in times:
        d, v = seven.at(at - START)
        x, y, heading = _turning_right(d)
        where = {"x": round(x, 3), "y": round(y, 3)}
        run.emit("vehicle/7", ns(at), "entity.state", {**where, "heading_deg": round(heading, 3), "speed_mps": round(v, 3)})
        run.emit("monitor/m1", ns(at), "monitor.observation",
                 {"vehicle": "7", "facts": stop_camera(at, d - 40.0, v), "speed_mps": round(v, 3), **where})
    return run, times



def test_a_main_road_car_braking_in_the_junction_behind_a_vehicle_that_pulled_into_its_lane_and_slowed_was_forced(
        tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171). 7 stops at its Stop line (west arm), pulls away at
    2.5 m/s² turning right into the major road's southbound lane, reaches 9 m/s and then slows at
    2 m/s² to 2.5 m/s ahead of c2. c2 comes down that lane from the north at 9 m/s, 1.3 s behind
    7 where their paths merge, and brakes at 2.5 m/s² for 3 s from 4 m short of the centre, inside
    the junction (then goes on at 1.5 m/s): unslowed, it would have closed on 7 to well inside the
    two-second rule's gap (HC 126) as 7 slowed. A change of speed to avoid an accident with the
    vehicle that pulled out in front of it: punishable, HC 171, "7 would force c2" (the paper run's
    193, which turned into 186's lane and slowed from 9.9 to 3.4 m/s, 186 braking at 2.35 m/s² in
    j2; SUMO's account: leader 193, merged at j2, held 2.34). On main c2's way, as the passage
    read it, ended in the junction with its braking (counted only on its arm), so only 7's
    positions in the turn, still well ahead, were measured against it: "well ahead"."""
    seven = Motion.stopping_at(0.0, 8.0, 40.0 - 12.5, wait=2.0, then=9.0 / 2.5, accel=2.5)
    seven.phases += [((9.0 - 2.5) / 2.0, -2.0), (40.0, 0.0)]
    onset = seven.phases[0][0] + 2.0 + 5.9          # c2 brakes 5.9 s after 7 set off, 4 m short of the centre
    c2 = Motion(-4.0 - 9.0 * onset, 9.0, [(onset, 0.0), (3.0, -2.5), (30.0, 0.0)])
    run, times = _stop_and_turn_right(seven)
    run.spawn("c2")
    run.drive("c2", c2, "north", times, t_start=START)
    run.watch("c2", c2, "north", times, t_start=START)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived), \
        [(f.sentence, f.method) for f in inc.derived]


def test_a_stop_after_creeping_on_behind_a_leader_that_had_gone_is_a_change_of_speed_of_its_own(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171) asks of a change of speed whether the vehicle caused
    it "in order to avoid an accident"; a road user can change speed twice, for two causes. l
    stands in the junction 8 m north of the centre and pulls away at 3 m/s², turning off east;
    c2, behind it on the major road from the north at 13.4 m/s, brakes at 4.5 m/s² to 2.5 m/s for
    it (a leader in its lane, HC 126), creeps on at 2.5 m/s for 2 s once l has turned off, and
    then stops 7.5 m north of the centre as 7, running its Stop line at 3 m/s (west arm), comes
    across its way: had c2 crept on, it would have been in 7's zone with 7. The braking was for l;
    the stop, a second change of speed from a steady 2.5 m/s, was to avoid 7: "7 would force c2"
    (punishable HC 171 in any case: 7 did not stop). The town run's 225, which braked behind 424
    waiting to turn in j11, crept on at 2.5 m/s and stopped as 125 (over its Stop line without
    standing) came across; SUMO's account: foe 125, held 2.5 m/s². On main, the stop was read
    with the braking as one slowing, explained by the leader at its onset.)"""
    seven = Motion(-40.0, 3.0)
    c2 = Motion(-32.5 - 13.4 * 7.52, 13.4, [(7.52, 0.0), (2.42, -4.5), (2.0, 0.0), (0.56, -4.5), (3.0, 0.0), (10.0, 2.0)])
    lead = Motion(-8.0, 0.0, [(7.5, 0.0), (3.0, 3.0)])
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"west": "stop", "east": "stop"})])
    times = rate(5, START, START + 25.0)
    for who, motion, arm in (("7", seven, "west"), ("c2", c2, "north"), ("l", lead, "north>east")):
        run.spawn(who)
        run.drive(who, motion, arm, times, t_start=START)
        run.watch(who, motion, arm, times, t_start=START, facts=camera("7", sign="stop") if who == "7" else None)
    inc = one(judge(tmp_path, run), "7")
    verdict(inc, "punishable", "HC 171")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived), \
        [(f.sentence, f.method) for f in inc.derived]
    assert not any(f.sentence == "7 would force l to change speed or course" for f in inc.derived)


MINOR_NS = {"south": "give_way", "north": "give_way"}      # the major road runs west-east


def _turner_behind(lead: Motion) -> Foreign:
    """c2 on the major road from the west at 13.35 m/s, turning right into the south arm's
    outbound lane, brakes at 4.5 m/s² from 25.3 m short of the centre to 2.55 m/s and pulls away
    at 2.6 m/s²; 7 comes up the south arm (Give Way) at 13.4 m/s without slowing, straight across
    c2's way 2.0 s after c2 began to slow (unslowed, c2 would have reached their conflict zone
    0.24 s before 7 and been in it with 7: a collision course); l, from the north arm straight
    through into the lane c2 turns into, is 30 m ahead of c2 on c2's way when c2 begins to slow,
    at 9.5 m/s, moving as `lead` says."""
    onset = 4.0                                       # c2's onset, s from START
    c2 = Motion(-25.3 - 13.35 * onset, 13.35, [(onset, 0.0), (2.4, -4.5), (30.0, 2.6)])
    seven = Motion(1.75 - 13.4 * (onset + 2.0), 13.4)
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds=MINOR_NS)])
    times = rate(5, START, START + 20.0)
    for who, motion, arm in (("7", seven, "south"), ("c2", c2, "west>south"), ("l", lead, "north")):
        run.spawn(who)
        run.drive(who, motion, arm, times, t_start=START)
        run.watch(who, motion, arm, times, t_start=START, facts=["7 has a give way sign"] if who == "7" else None)
    return run


def test_a_turner_braking_far_below_the_speed_of_one_pulling_away_ahead_of_it_was_forced_by_the_crosser(tmp_path):
    """HC 172 (TSRGD 2016 Sch 9 Pt 8): 7 does not give way to c2, traffic on the major road. l,
    30 m ahead of c2 on c2's own way (it came through from the north arm into the lane c2 turns
    into), is at 9.5 m/s when c2 begins to slow and speeds up at 2.3 m/s² to 13.4 m/s; c2 brakes
    at 4.5 m/s² from 13.35 to 2.55 m/s. Keeping the two-second gap behind l (HC 126: "the vehicle
    in front") asked c2 at most to come down to l's speed; it went on to 7 m/s below the slowest l
    went, as 7 came across its way: the change of speed was to avoid 7. Punishable, HC 172, "7
    would force c2" (the town run's 534, braking from 13.35 to 2.55 m/s turning right in j4 behind
    389, which came from the north into 534's exit lane 30 m ahead at 9.5 m/s and sped up, as 496
    ran its Give Way line; SUMO's account: foe 496, held 4.5 m/s². On main, 389 was taken as
    534's leader: 2.3 m/s² by the two-second rule at the onset.)"""
    lead = Motion(1.25 - 13.04 - 5.5 * (START - 5.0 + 4.0 - 1.74), 5.5, [(4.0 - 1.74, 0.0), (3.9 / 2.3, 2.3), (30.0, 0.0)])
    inc = one(judge(tmp_path, _turner_behind(lead)), "7")
    verdict(inc, "punishable", "HC 172")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived), \
        [(f.sentence, f.method) for f in inc.derived]
    assert not any(f.sentence == "7 would force l to change speed or course" for f in inc.derived)


def _braked_behind_leader_l(tmp_path, lead: Motion) -> None:
    """The run with l ahead of c2 moving as `lead`: 7's Give Way not giving way is mitigated HC 172,
    with no "7 would force c2": the second limb puts c2's braking down to its own leader l."""
    inc = one(judge(tmp_path, _turner_behind(lead)), "7")
    verdict(inc, "mitigated", "HC 172")
    assert not any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived), \
        [(f.sentence, f.method) for f in inc.derived]
    c2 = next(u for u in inc.second_limb if u.user == "c2")
    assert c2.reason == "leader" and "its own leader l" in c2.words, (c2.reason, c2.words)


def test_a_turner_braking_behind_one_slowing_ahead_on_its_way_braked_for_it(tmp_path):
    """HC 126: a following driver keeps a gap behind the vehicle in front in which it can pull up
    if that vehicle slows. As above, but l, 30 m ahead of c2 on c2's way at 9.5 m/s when c2 begins
    to slow, slows at 3 m/s² to 2.5 m/s: c2, braking to 2.55 m/s, came down to l's speed behind
    it, its leader in its lane, and not below it. c2 braked for l, not for 7: no "7 would force
    c2"; 7 still did not give way: HC 172 without anyone forced, mitigated as the tool grades it."""
    lead = Motion(1.25 - 9.5 * 4.0, 9.5, [(4.0, 0.0), (7.0 / 3.0, -3.0), (30.0, 0.0)])
    _braked_behind_leader_l(tmp_path, lead)


def test_a_harder_braking_after_the_vehicle_set_off_is_a_change_of_speed_of_its_own(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): no vehicle may proceed past a Stop line "so as to be
    likely to ... cause the driver of another vehicle to change its speed or course in order to avoid
    an accident". 7 stands at its Stop line (west arm) and sets off at 2 m/s² (8.87 s), straight
    across. On the major road c2, from the north at 13.4 m/s, begins to slow at 4 m/s² 0.9 s
    before 7 sets off, for 8, which crawls at 2 m/s across c2's lane out of the east arm, eases to
    1 m/s² after half a second, and from 0.2 s after 7 set off brakes at 6 m/s² to a stand, going
    on once 7 is across. Had c2 kept the speed it had when it began to slow, it would have been in
    8's zone with 8 (a collision course, -0.42 s; 7's a near miss, 0.71 s): that first slowing was
    for 8. The braking after 7 set off is a second change of speed, harder than the easing it broke
    off by more than 2 m/s² (Hupfer's considerable reaction); from where c2 was when 7 set off, at
    the speed it then had, 7's zone came first on its way (26.2 m on, 0.01 s after 7 left it: a
    near miss) and 8's 3.5 m beyond it (0.21 s). The law asks of that change of speed whether 7
    caused it: punishable, HC 171, "7 would force c2" (the paper run's 205, slowing
    for 279 while 253 stood at its Give Way line, then braking at 5.5 m/s² as 253 came out; SUMO's
    account: foe 253, 8.7 m/s² from 325.4 s. On main, the slowing's onset before 253 set off put
    the braking down to 279's collision course.)"""
    c2 = Motion(-43.5 - 13.4 * 8.0, 13.4, [(8.0, 0.0), (0.5, -4.0), (0.6, -1.0), (3.0, -6.0), (2.0, 0.0),
                                           (10.0, 2.0)])
    eight = Motion(-21.0, 2.0)              # in c2's lane's zone from about 7.75 s to 11.5 s
    inc = one(judge(tmp_path, stop_then_go_run(("c2", c2, "north"), ("8", eight, "east"))), "7")
    verdict(inc, "punishable", "HC 171")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived), \
        [(f.sentence, f.method) for f in inc.derived]


def test_a_harder_braking_tail_of_a_slowing_for_another_is_not_a_change_of_speed_of_its_own(tmp_path):
    """Control for the last: the same, but c2 brakes on at 4 m/s² through 7's set-off and only then
    at 5 m/s², no harder than the slowing it was making by 2 m/s²: one braking, begun for 8 (a
    collision course, unslowed, with 8 crawling across its lane) while 7 still stood where the law
    asks it to wait. 7 made nobody change speed (the shape of the paper-12 run's 187, braking at
    4.5 m/s² from 224.0 s to a stop at 226.6 s through 204's set-off at 226.0 s)."""
    c2 = Motion(-43.5 - 13.4 * 8.0, 13.4, [(8.0, 0.0), (1.1, -4.0), (3.0, -5.0), (2.0, 0.0), (10.0, 2.0)])
    eight = Motion(-21.0, 2.0)
    found = judge(tmp_path, stop_then_go_run(("c2", c2, "north"), ("8", eight, "east")))
    assert not [i for i in found if i.vehicle == "7" and any(
        f.sentence == "7 would force c2 to change speed or course" for f in i.derived)], \
        [(i.vehicle, i.verdict, [f.sentence for f in i.derived]) for i in found]


def test_a_harder_braking_inside_another_road_users_zone_is_that_road_users_to_explain(tmp_path):
    """Control for the harder braking read afresh: 7 stands at its Stop line on the east arm and
    sets off at 2 m/s² (8.87 s), straight across. c2, from the north at 13.4 m/s, slows at
    4.5 m/s² to 6 m/s from 6.86 s for 8, which crawls at 2 m/s out of the west arm across c2's lane
    (in their zone from 8.5 s; unslowed, c2 would have been in it with 8), keeps on at 6 m/s, and
    from 9.1 s, already in 8's zone with 8 in it, brakes at 12 m/s² to a stand until 8 has gone.
    The braking after 7 set off is harder than the slowing before it, but it was made inside 8's
    conflict zone with 8 there (had c2 kept its speed, it would have left the zone 1.5 s after 8
    came in): resolving 8's conflict, the first on its way (where no projected gap is defined,
    the occupancy at the onset stands for it). Had c2 kept 13.4 m/s from where it began to slow,
    it would have been through 7's zone 2.5 s before 7 came. 7 made nobody change speed "in order to avoid an
    accident" (TSRGD 2016 Sch 9 Pt 7 para 1): no "7 would force c2" (the town run's 279, turning
    right across j2, braking again inside 108's zone as 170 set off from its Stop line; SUMO's
    account: foe 108; 333 for 440 and 191 for 174, in the same place, likewise)."""
    c2 = Motion(-22.95 - 13.4 * 6.856, 13.4, [(6.856, 0.0), ((13.4 - 6.0) / 4.5, -4.5), (0.6, 0.0), (0.5, -12.0),
                                              (3.5, 0.0), (10.0, 2.0)])
    eight = Motion(-19.05, 2.0)             # in c2's zone (its lane's strip, half a car on either side) from 8.5 s
    found = judge(tmp_path, stop_then_go_run(("c2", c2, "north"), ("8", eight, "west"), arm="east"))
    assert not [i for i in found if i.vehicle == "7" and any(
        f.sentence == "7 would force c2 to change speed or course" for f in i.derived)], \
        [(i.vehicle, i.verdict, [f.sentence for f in i.derived]) for i in found]

def test_a_car_braking_to_stand_at_its_own_stop_line_across_the_vehicles_way_is_not_forced_by_it(tmp_path):
    """TSRGD 2016 Sch 9 Pt 7 para 1 (HC 171): "every vehicle must stop before crossing the
    transverse line"; the second limb protects the driver of another vehicle made "to change its
    speed or course in order to avoid an accident", and a vehicle that had to stand at its own Stop
    line whoever passed did not change speed for the one that did (issue 35's "Attribution": not
    for its own control, its own Stop line). 7 stops at its Stop line (west arm), pulls away and
    turns right across the westbound lane. 8 comes west on the opposite arm (also a Stop line) at
    10 m/s and, from 4.1 s, brakes at 4 m/s² to stand 1.15 m short of its own line, stands 3 s and
    goes on: unslowed it would have been in 7's way as 7 turned (a collision course), but it had to
    stop where it stopped anyway. Not forced: no "7 would force 8" (the paper run's 267, 1.2 m from
    its own Stop line on j2's north arm, and 142, 3.4 m from it, braking to it as 195 and 155 came
    out of the opposite Give Way line; SUMO's account: foe 195 and foe 155, each holding the car at
    its line). Fails if a Stop line of the road user's own is read as no excuse, as a Give Way line
    on a collision course is (derived._line_no_excuse)."""
    from reasoner import derived, history

    seven = Motion.stopping_at(0.0, 8.0, 40.0 - 12.5, wait=2.0, then=9.0 / 2.5, accel=2.5)
    seven.phases += [(40.0, 0.0)]
    meets = seven.when(40.38)                   # 7's front on the westbound lane (y = -1.75) at x = -0.65
    brakes = meets - 2.6                        # unslowed, 8's front there (s = +0.65) at `meets`
    eight = Motion(0.65 - 10.0 * meets, 10.0, [(brakes, 0.0), (2.5, -4.0), (3.0, 0.0), (20.0, 2.0)])
    stood_at = eight.at(brakes + 2.6)[0]
    assert -13.5 < stood_at < -12.0, stood_at   # short of its own line (12 m out), by 1.15 m
    run, times = _stop_and_turn_right(seven)
    run.spawn("8")
    run.drive("8", eight, "east", times, t_start=START)
    run.watch("8", eight, "east", times, t_start=START)
    p = next(p for p in history.from_events(run.events, "7") if p.crossing is not None)
    eights = [o for o in derived.reacting(p) if o.user == "8"]
    assert eights and eights[0].braking is not None and eights[0].braking.decel_mps2 > 3.5, eights
    shown = {f.sentence for f in derived.facts(p, p.crossing.t)}
    assert "7 would force 8 to change speed or course" not in shown, shown


def test_a_turner_too_close_behind_one_going_on_that_braked_on_below_it_was_forced_by_the_crosser(tmp_path):
    """HC 172 (TSRGD 2016 Sch 9 Pt 8): 7 does not give way to c2, traffic on the major road. l, from
    the north arm straight through into the lane c2 turns into, is 30 m ahead of c2 on c2's way when
    c2 begins to slow, at 13 m/s and going on at it: c2 (13.35 m/s) is within the two-second gap
    behind it (HC 126: 8 m and two seconds at 13 m/s, 34 m). Keeping that gap asked c2 to drop back,
    going slower than l until the gap was kept (by 0.5 s on, at 11.1 m/s, it was two seconds behind
    l at its own speed), and no further; c2 braked on at 4.5 m/s² to 2.55 m/s as 7 came across its
    way: that change of speed was to avoid 7. Punishable, HC 172, "7 would force c2" (the paper
    run's 154, a police car on j2's south Give Way arm 16.8 m behind 241, which turned the same way
    at 8.2 m/s and sped up, braking from 8.35 m/s to a stand as 142 turned out of the north Stop arm
    into the lane 154 was turning into; SUMO's account: foe 142, held 4.5 m/s². On main, 241 was
    taken as 154's leader: within the gap at the onset, whatever came after.)"""
    lead = Motion(1.25 - 13.0 * 4.0, 13.0)
    inc = one(judge(tmp_path, _turner_behind(lead)), "7")
    verdict(inc, "punishable", "HC 172")
    assert any(f.sentence == "7 would force c2 to change speed or course" for f in inc.derived), \
        [(f.sentence, f.method) for f in inc.derived]


def test_a_turner_too_close_behind_one_slowing_ahead_that_came_down_to_its_speed_braked_for_it(tmp_path):
    """Control for the last: l, 30 m ahead at 13 m/s (c2 within the two-second gap behind it), slows
    at 4.5 m/s² to 2.5 m/s from c2's onset; c2, braking to 2.55 m/s, came down to l's speed behind it
    and not below (HC 126). c2 braked for its leader, not for 7: no "7 would force c2"; 7 still did
    not give way: HC 172 without anyone forced, mitigated as the tool grades it."""
    lead = Motion(1.25 - 13.0 * 4.0, 13.0, [(4.0, 0.0), (10.5 / 4.5, -4.5), (30.0, 0.0)])
    _braked_behind_leader_l(tmp_path, lead)
