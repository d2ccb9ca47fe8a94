"""SUMO's own account in the ground truth (sim_replay/sumo_account.py): who braked for whom, and why,
as SUMO says it, checked on scenes built by hand in SUMO where the cause is known by construction.

The paper's map: r1 runs west to east through j1 (lights; r1 red from 32 s to 75 s of the 75 s cycle)
and j2 (r1 has no line; r3's north arm a Stop line). "main" drives east on r1 towards j2 with the
right of way; "side" comes down r3's north arm and goes straight across, its decisions ours
(World.take_control: SUMO no longer stops it at its line nor makes it give way), timed so that it
is in the junction ahead of "main": main must brake for it. "red" arrives at j1's west line while
r1's light is red, and "queue" follows it: one brakes for its own light, the other for the car
in front of it.
"""
from __future__ import annotations

import libsumo
import pytest

from sim_replay.maps import map_files
from sim_replay.sim_config import Behaviour, SimConfig
from sim_replay.simulation import Simulation
from sim_replay.crossing_paths import WINDOW_S, Geometry, PathWatch, Recent, pet
from sim_replay.sumo_account import COMING_S, Account, Yield, read_ssm, shares, ssm_options
from sim_replay.sumo_world import World
from sim_replay.truth import yielded_to

NET = map_files("paper").net


def scene(tmp_path) -> tuple[list, list]:
    """The yields and SSM conflicts of the scene above, 60 s of it."""
    ssm = tmp_path / "ssm.xml"
    routes: dict = {}
    with World(NET, seed=3, extra=ssm_options(ssm)) as world:
        account = Account(routes, world.modes)
        add_cars(world, routes, (("main", "j1_j2", "j2_e", 124.0, "max"), ("side", "n2_j2", "j2_s2", 158.0, 5.0)))
        for step in range(600):
            if step == 330:                                       # 33 s: r1's light at j1 is red from 32 s
                for ident, pos in (("red", 90.0), ("queue", 40.0)):
                    routes[ident] = world.route("w_j1", "j1_j2")
                    world.add_vehicle(ident, "car", routes[ident], depart_pos=pos)
            snap = world.step()
            if step == 0:
                world.take_control("side")
            account.tick(snap)
        account.close()
    return [y.to_json() for y in account.yields], read_ssm(ssm)



def add_cars(world, routes: dict, cars) -> None:
    """Cars into a scene: (id, from edge, to edge, depart position m, depart speed), each route kept
    in `routes` as the account reads it."""
    for ident, start, end, pos, speed in cars:
        routes[ident] = world.route(start, end)
        world.add_vehicle(ident, "car", routes[ident], depart_pos=pos, depart_speed=speed)

def test_the_account_names_a_junction_foe_a_red_light_and_a_leader_as_sumo_gives_them(tmp_path):
    yields, conflicts = scene(tmp_path)
    by = {}
    for y in yields:
        by.setdefault(y["vehicle"], []).append(y)
    # main, with the right of way, braked hard because side was in the junction across its path
    main = max(by["main"], key=lambda y: y["peak_decel_mps2"])
    assert (main["cause"], main["by"]) == ("foe", "side") and main["junction"] == "j2"
    assert main["causes"]["foe side"]["decel_mps2"] >= 2.0 and main["causes"]["foe side"]["foe_in_junction"]
    # red stopped for its own light, not for anybody
    red = max(by["red"], key=lambda y: y["peak_decel_mps2"])
    assert (red["cause"], red["by"]) == ("signal", None) and red["causes"]["signal"]["state"] == "r"
    assert red["min_speed_mps"] < 0.1 and red["junction"] == "j1"
    # queue braked for red ahead of it in its own lane: a leader, not one that joined from another arm
    queue = max(by["queue"], key=lambda y: y["peak_decel_mps2"])
    assert (queue["cause"], queue["by"]) == ("leader", "red") and queue["causes"]["leader red"]["merged"] is False
    assert not any(y["by"] in ("main", "red", "queue") for y in by.get("side", ()))
    # SUMO's SSM device logged the pair's crossing conflict, with its measures
    pair = next(c for c in conflicts if (c["ego"], c["foe"]) == ("main", "side"))
    assert pair["minTTC"]["value"] < 3.0 and "crossing" in pair["minTTC"]["type"]
    assert pair["maxDRAC"]["value"] > 0 and {"begin_s", "end_s"} <= set(pair)
    assert not any({c["ego"], c["foe"]} & {"red", "queue"} and {c["ego"], c["foe"]} & {"main", "side"}
                   for c in conflicts)


def test_a_crossing_is_given_the_road_users_sumo_says_braked_for_it():
    act = {"vehicle": "side", "t_s": 3.5}
    yields = [
        {"vehicle": "main", "t_s": 3.6, "until_s": 9.1, "speed_mps": 13.4, "min_speed_mps": 0.0,    # then its own red
         "causes": {"foe side": {"t_s": 3.6, "decel_mps2": 4.9, "min_speed_mps": 10.5},
                    "signal": {"t_s": 5.0, "decel_mps2": 3.0, "min_speed_mps": 0.0}}},
        {"vehicle": "behind", "t_s": 4.0, "until_s": 5.0, "speed_mps": 9.0, "min_speed_mps": 4.0,       # queued behind it
         "causes": {"leader side": {"t_s": 4.0, "decel_mps2": 3.0, "merged": False}}},
        {"vehicle": "joined", "t_s": 6.0, "until_s": 7.0, "speed_mps": 13.0, "min_speed_mps": 9.0,      # it pulled out ahead
         "causes": {"leader side": {"t_s": 6.0, "decel_mps2": 2.5, "merged": True}}},
        {"vehicle": "later", "t_s": 30.0, "until_s": 31.0, "speed_mps": 13.0, "min_speed_mps": 0.0,     # long after
         "causes": {"foe side": {"t_s": 30.0, "decel_mps2": 4.5}}},
        {"vehicle": "own", "t_s": 4.0, "until_s": 6.0, "speed_mps": 13.0, "min_speed_mps": 0.0,         # its own light
         "causes": {"signal": {"t_s": 4.0, "decel_mps2": 4.5}}},
    ]
    conflicts = [{"ego": "main", "foe": "side", "begin_s": 0.0, "end_s": 9.0,
                  "minTTC": {"t_s": 4.0, "value": 0.9, "x_y": [0, 0], "type": "crossing (ego first)"}}]
    got = yielded_to(act, yields, conflicts)
    assert [(y["vehicle"], y["cause"], y["decel_mps2"], y["min_speed_mps"]) for y in got] == \
        [("main", "foe", 4.9, 10.5), ("joined", "leader", 2.5, 9.0)]
    assert got[0]["ssm"]["minTTC"]["value"] == 0.9 and got[1]["ssm"] == {}


def test_keeping_the_account_changes_no_event_and_only_adds_to_the_truth():
    config = SimConfig(run="account", vehicles=30, duration_s=60.0, seed=5, rate_hz=5.0, pedestrians=6,
                       behaviour=Behaviour(no_give_way=0.5, stop_roller=0.4, red_runner=0.3))
    plain, kept = Simulation(config), Simulation(config, account=True)
    assert list(plain.events()) == list(kept.events())
    without, with_ = plain.truth.to_json(), kept.truth.to_json()
    assert "yields" not in without and "conflicts" not in without
    assert with_["yields"] and with_["conflicts"] is not None
    crossings = [a for a in with_["acts"] if a["kind"] == "crossed the stop line"]
    assert crossings and all("yielded" in a["sumo"] and "in_path" in a["sumo"] for a in crossings)
    for a in with_["acts"] + without["acts"]:        # pedestrians in a path are asked of SUMO only with it
        a.pop("sumo", None), a.pop("in_path")
    assert with_["acts"] == without["acts"]
    assert {y["cause"] for y in with_["yields"]} <= {"foe", "leader", "signal", "line", "turn", "speed",
                                                      "pedestrian", "link", "none"}


def crossing_scene(walker: tuple[str, str, float], through_mps: float | None = None) -> tuple[list, dict]:
    """"side" comes down r3's north arm at j2 and goes straight across, its decisions ours; one
    pedestrian walks (from, to, depart position) by the crossing of j2's north arm (":j2_c2",
    196.5-203.5 m east at y 10, 4 m wide). The crossing is a foe of side's junction lane. Side's
    path over it is 201.8 m east, ± 1.4 m: the car's width and SUMO's 1 m pedestrian safety gap.
    `through_mps`: side drives through at that speed whatever is in its way (speed mode 0), as a
    driver who does not give way would; else SUMO drives it. Returns the pedestrians
    crossing_paths finds in side's path, and the nearest each pedestrian on that crossing came to
    side."""
    with World(NET, seed=3) as world:
        geometry, recent, watch = Geometry(), Recent(), None
        world.add_person("p", *walker[:2], depart_pos=walker[2])
        for step in range(300):
            if step == 104:
                world.add_vehicle("side", "car", world.route("n2_j2", "j2_s2"), depart_pos=158.0, depart_speed=5.0)
            snap = world.step()
            if step == 105:
                world.take_control("side")
                if through_mps is not None:
                    libsumo.vehicle.setSpeedMode("side", 0)
                    libsumo.vehicle.setSpeed("side", through_mps)
            side = snap.vehicle("side")
            if watch is None and side is not None and side.junction == "j2":      # its front is over its line
                watch = PathWatch(geometry, side, snap.t_s, recent)
            if watch is not None:
                watch.tick(snap.t_s, side, snap.pedestrians)
            recent.tick(snap.t_s, snap.pedestrians)
        assert watch is not None and not watch.open(snap.t_s)
        return watch.found(), watch.nearest


def test_a_pedestrian_on_a_crossing_of_the_vehicles_way_but_not_in_its_path_is_not_in_its_path():
    """SUMO drives side. p steps onto the north arm's crossing from the west kerb (196.7 m east)
    as side comes through, 5 m to side's side. It walks at about 1 m/s and reaches side's path
    (from 200.4 m east) 2.5 s after side's back has left the crossing: more than WINDOW_S (2 s).
    Coming the other way (from the east kerb, westwards), p is on the crossing first; side waits for
    it and drives over the place it left a second before, while p walks on over the rest of the
    crossing: it is past side's path (SUMO's blockedAtDist: a pedestrian completely past the
    vehicle's crossing point no longer blocks it). SUMO makes the crossing a foe of side's lane
    both times, and p is on it while side passes, but neither time is p in side's path. The
    account used to list both (issue 35's unraised paper acts: pedestrians 3.5-19.5 m off, one
    0.29 s past the path)."""
    for walker in (("j1_j2", "j2_e", 170.0), ("j2_e", "j1_j2", 5.0)):
        found, nearest = crossing_scene(walker)
        assert "p" in nearest and nearest["p"] < 8.0          # on a crossing of side's way as it passed
        assert found == [], walker


def test_a_pedestrian_stepping_into_the_vehicles_path_just_after_it_is_in_its_path():
    """side drives through at 8 m/s, giving way to nobody; p steps onto the north arm's crossing
    from the west kerb as side comes, and reaches side's path about a second after side has left
    the crossing: side passed just in front of it, within WINDOW_S (2 s). It is in side's path,
    with the post-encroachment time measured."""
    found, nearest = crossing_scene(("j1_j2", "j2_e", 171.0), through_mps=8.0)
    assert [(who, crossing) for who, crossing, _, _ in found] == [("p", ":j2_c2")]
    assert 0.0 < found[0][3] <= WINDOW_S and found[0][2] == nearest["p"]


def test_the_post_encroachment_time_is_the_least_gap_between_the_two_occupancies_and_says_who_was_first():
    assert pet([10.0, 10.1, 10.2], [12.0, 12.1]) == (1.8, "mine")       # the pedestrian came 1.8 s after
    assert pet([10.0, 10.1], [8.0, 8.1, 9.5]) == (0.5, "theirs")        # it left 0.5 s before
    assert pet([10.0, 10.1], [10.1, 10.2]) == (0.0, None)               # both in it at once
    assert pet([], [1.0]) is None and pet([1.0], []) is None            # one was never in it


def test_a_car_following_the_vehicle_on_its_own_approach_follows_it_and_is_no_foe_of_it(tmp_path):
    """"side" comes up r3's south arm to j2 and turns right (east); "behind" follows it up the same
    lane and goes straight on (north). Their junction lanes leave j2's south arm from one lane,
    so SUMO lists side among behind's junction foes (getJunctionFoes); but its junction model
    follows a vehicle ahead from the same lane as a leader until it has turned off, and its SSM
    device calls such pairs "following". behind brakes behind side (a leader that did not join its
    road from another arm), never for side as a junction foe, so no crossing of side's is said to
    have made behind give way (issue 35's "a cyclist following on its own approach")."""
    routes: dict = {}
    with World(NET, seed=3) as world:
        account = Account(routes, world.modes)
        add_cars(world, routes, (("side", "s2_j2", "j2_e", 150.0, 8.0), ("behind", "s2_j2", "j2_j1", 120.0, "max")))
        for step in range(120):
            snap = world.step()
            if step == 0:
                world.take_control("side")
            account.tick(snap)
        account.close()
    behind = [y.to_json() for y in account.yields if y.vehicle == "behind"]
    named = {key for y in behind for key in y["causes"]}
    assert "leader side" in named and "foe side" not in named
    assert all(not c.get("merged") for y in behind for k, c in y["causes"].items() if k == "leader side")
    assert yielded_to({"vehicle": "side", "t_s": 3.4}, behind, []) == []


def test_braking_is_measured_held_over_a_second_under_each_cause():
    """A braking's strength is the speed shed under one cause within a second (HELD_S), as the
    2 m/s² threshold of a considerable change of speed is stated: a one-tick peak of 4.5 m/s² sheds
    0.45 m/s (0.45 m/s² held); ten ticks at 2.5 m/s² shed 2.5 m/s; what was shed under another
    cause in the same second is not counted for this one."""
    y = Yield("u", 0.0, 0.0, "j2", "e_j2_1", 13.4, 13.4, 0.0, "none", None)
    assert y.held(10.0, 0.45, "foe v") == 0.45                     # one tick of 4.5 m/s²
    assert y.held(12.0, 0.05, "foe v") == 0.05                     # ... forgotten a second later
    steady = Yield("u", 0.0, 0.0, "j2", "e_j2_1", 13.4, 13.4, 0.0, "none", None)
    ticks = [steady.held(10.0 + 0.1 * k, 0.25, "foe v") for k in range(12)]
    assert ticks[9] == 2.5 and max(ticks) == 2.5                 # ten ticks at 2.5 m/s² within the second
    z = Yield("u", 0.0, 0.0, "j2", "e_j2_1", 13.4, 13.4, 0.0, "none", None)
    for k in range(5):
        z.held(20.0 + 0.1 * k, 0.45, "turn")                     # its own turn first
    assert z.held(20.5, 0.45, "foe v") == 0.45                   # then a tick for v


def test_a_leader_counts_only_where_it_joined_the_road_at_the_acts_junction():
    """"side" crossed j1's line; "behind" braked behind it on the road to j1, which side had joined
    at j2 earlier on: a queue on its own approach to j1, not a braking side's crossing of j1 caused.
    "cut" braked behind side on j1's exit, which side joined at j1 as it crossed: side's crossing."""
    act = {"vehicle": "side", "t_s": 10.0, "junction": "j1"}
    yields = [
        {"vehicle": "behind", "t_s": 10.5, "until_s": 12.0, "speed_mps": 13.4, "min_speed_mps": 9.0,
         "causes": {"leader side": {"t_s": 10.5, "decel_mps2": 4.5, "held_mps2": 3.0, "merged": True,
                                    "merged_at": "j2"}}},
        {"vehicle": "cut", "t_s": 11.0, "until_s": 12.0, "speed_mps": 13.4, "min_speed_mps": 8.0,
         "causes": {"leader side": {"t_s": 11.0, "decel_mps2": 4.5, "held_mps2": 3.0, "merged": True,
                                    "merged_at": "j1"}}},
    ]
    assert [y["vehicle"] for y in yielded_to(act, yields, [])] == ["cut"]


def test_a_foe_still_far_off_is_not_one_the_vehicle_waited_for():
    """SUMO lists among a vehicle's junction foes every vehicle whose route crosses its link, one
    480 m and 38 s away with one about to arrive; the vehicle waits for one arriving within
    COMING_S, not for one that will come in half a minute."""
    act = {"vehicle": "far", "t_s": 10.0, "junction": "j6"}
    yields = [{"vehicle": "u", "t_s": 11.0, "until_s": 11.6, "speed_mps": 9.6, "min_speed_mps": 6.5,
               "causes": {"foe far": {"t_s": 11.0, "decel_mps2": 4.5, "held_mps2": 3.1, "foe_arrives_s": 37.7}}},
              {"vehicle": "w", "t_s": 11.0, "until_s": 11.6, "speed_mps": 9.6, "min_speed_mps": 6.5,
               "causes": {"foe far": {"t_s": 11.0, "decel_mps2": 4.5, "held_mps2": 3.1, "foe_arrives_s": 1.5}}}]
    assert [y["vehicle"] for y in yielded_to(act, yields, [])] == ["w"]


def test_a_vehicle_braking_to_stand_at_its_own_stop_line_is_not_coming_into_the_junction():
    """"waiting" (SUMO's driving) comes down r3's north arm to j2's Stop line, braking to stand
    there as SUMO's Stop sign (link state `s`) makes it. Meanwhile "inside", on r1 with the right
    of way, brakes in j2 (a slowDown, a cause SUMO's calls cannot see). waiting has not yet stood at
    its line, so it is not coming into the junction: SUMO brings it to a stop first. inside did
    not brake for it then; once waiting has stood and moves off its line, it is coming (inside's
    braking is the slowDown's: SUMO's stop speed short of waiting's way allows all inside can
    reach, so it names waiting at no time). The account used to read its distance over its speed (a few metres at
    6-10 m/s) as coming within COMING_S, as it read a vehicle standing at its line: the paper's 107
    "braked for foe 282" 11.8 m and 1.3 m from 282's line while 282 braked to stand there."""
    routes: dict = {}
    with World(NET, seed=3) as world:
        account = Account(routes, world.modes)
        add_cars(world, routes, (("waiting", "n2_j2", "j2_s2", 150.0, 5.0), ("inside", "j1_j2", "j2_e", 129.0, "max")))
        slowed, standing_from, coming = None, None, []
        for step in range(120):
            snap = world.step()
            inside, waiting = snap.vehicle("inside"), snap.vehicle("waiting")
            if slowed is None and inside is not None and inside.lane.startswith(":j2"):
                libsumo.vehicle.slowDown("inside", 3.0, 2.0)
                slowed = (snap.t_s, waiting.speed_mps, waiting.to_junction_m)
            if standing_from is None and waiting is not None and waiting.speed_mps < 0.1:
                standing_from = snap.t_s
            account.tick(snap)
            if slowed is not None and waiting is not None and not waiting.lane.startswith(":"):
                coming.append((snap.t_s, account._coming(waiting) is not None))
        account.close()
    assert slowed is not None and slowed[1] > 2.0 and slowed[2] < slowed[1] * COMING_S   # braking to its line
    assert standing_from is not None and standing_from > slowed[0]
    braked = [y for y in account.yields if y.vehicle == "inside" and y.t_s >= slowed[0]]
    assert braked and max(y.peak_decel_mps2 for y in braked) >= 2.0
    named = [y.causes["foe waiting"]["t_s"] for y in braked if "foe waiting" in y.causes]
    assert not [t for t in named if t < standing_from]     # not while it braked to stand at its line
    assert not [t for t, yes in coming if yes and t < standing_from]
    assert [t for t, yes in coming if yes and t > standing_from]   # once it had stood and moved off, it was


def test_one_road_user_as_foe_then_as_leader_is_one_cause_held_as_one():
    """SUMO's model keeps one speed for a vehicle, the lowest its constraints allow: a road user
    that crossed its way at the junction (a foe in its path) and then, having joined its road
    there, drove ahead of it (its merged leader) made it brake once, not twice. The speeds are the
    paper-11 run's 228 braking for 116 at j2: 13.41 to 10.78 m/s in six ticks at 4.5 m/s² with
    116 its foe, then on to 8.53 m/s in five more with 116 its leader; each constraint here asks
    for the whole tick (the stop short of the crossing point, then the follow speed behind 116,
    below the speed it reached). Counted apart, neither is 2 m/s² held over a second (2.7 and
    2.25 m/s shed in 0.6 and 0.5 s: 2.7 within the second under the foe); the whole braking
    sheds 4.5 m/s within one second under 116."""
    y = Yield("228", 448.0, 448.0, "j2", "j1_j2_1", 13.41, 13.41, 0.0, "none", None)
    speed = 13.41
    for k in range(11):
        t = round(448.0 + 0.1 * k, 1)
        cause = "foe" if k < 6 else "leader"
        detail = {"foe_in_junction": True} if cause == "foe" else {"merged": True, "merged_at": "j2"}
        y.record(t, speed, round(speed - 0.45, 2), 0.1, [(speed - 1.0, cause, "116", detail)])
        speed = round(speed - 0.45, 2)
    foe, leader = y.causes["foe 116"], y.causes["leader 116"]
    assert foe["held_mps2"] == 2.7 and leader["held_mps2"] == 2.25        # each apart, over its own ticks
    assert leader["road_user_held_mps2"] == 4.5                           # 116's, held as one
    # a leader that drove ahead of it all along (not merged) is not folded in with a foe of that name
    z = Yield("u", 0.0, 0.0, "j2", "j1_j2_1", 13.41, 13.41, 0.0, "none", None)
    speed = 13.41
    for k in range(6):
        cause, detail = ("foe", {}) if k < 3 else ("leader", {"merged": False})
        z.record(round(0.1 * k, 1), speed, round(speed - 0.45, 2), 0.1, [(speed - 1.0, cause, "w", detail)])
        speed = round(speed - 0.45, 2)
    assert z.causes["foe w"]["road_user_held_mps2"] == 1.35
    assert "road_user_held_mps2" not in z.causes["leader w"]


def test_the_comparison_reads_a_road_users_braking_held_as_one():
    """A braking SUMO puts down to V as a foe (0.94 m/s² held) and then as the leader that joined
    the road at the act's junction (1.9 held), held as one at 2.8 m/s², is giving way to V; the
    same braking with V's causes held as one under 2 m/s² is not."""
    from tests.helpers.conflict_agreement import gave_way
    act = {"vehicle": "v", "t_s": 10.0, "junction": "j2"}
    causes = {"foe v": {"t_s": 10.5, "decel_mps2": 4.5, "held_mps2": 0.94, "road_user_held_mps2": 2.8,
                        "from_mps": 13.41, "min_speed_mps": 10.9},
              "leader v": {"t_s": 11.1, "decel_mps2": 4.5, "held_mps2": 1.9, "road_user_held_mps2": 2.8,
                           "merged": True, "merged_at": "j2", "from_mps": 10.9, "min_speed_mps": 6.3}}
    y = {"vehicle": "u", "t_s": 10.5, "until_s": 12.0, "speed_mps": 13.41, "min_speed_mps": 6.3, "causes": causes}
    assert all(gave_way(r) for r in yielded_to(act, [y], []))
    weak = {k: {**c, "road_user_held_mps2": 1.9} for k, c in causes.items()}
    assert not any(gave_way(r) for r in yielded_to(act, [{**y, "causes": weak}], []))


def test_a_leader_far_ahead_is_no_cause_of_a_braking_for_something_else(tmp_path):
    """"main" drives east on r1 towards j2 (j2 has no line on r1) at full speed with "ahead" 60 m in front of it at the
    same speed; main is made to brake hard (a slowDown, a cause SUMO's calls cannot see). SUMO's
    follow speed behind ahead is only what main can reach in a tick (its maxNextSpeed, speed +
    2.6 m/s² x 0.1 s: getFollowSpeed gives that for a leader 1000 m off too), so ahead asked for
    no braking. Braking at 4.5 m/s², harder than it can accelerate, main's follow speed lies
    0.19 m/s under the speed it braked from in each tick: the account used to name "leader ahead"
    at 1.9 m/s² (as it named the town-11 run's 269 braking "for leader 146", 370 m ahead), and the
    share of a real cause beside it was cut by as much."""
    routes: dict = {}
    with World(NET, seed=3) as world:
        account = Account(routes, world.modes)
        for ident, pos in (("ahead", 165.0), ("main", 105.0)):
            routes[ident] = world.route("j1_j2", "j2_e")
            world.add_vehicle(ident, "car", routes[ident], depart_pos=pos, depart_speed="max")
        for step in range(40):
            snap = world.step()
            if step == 5:
                libsumo.vehicle.slowDown("main", 5.0, 2.0)
            account.tick(snap)
        account.close()
    main = [y.to_json() for y in account.yields if y.vehicle == "main"]
    assert main and max(y["peak_decel_mps2"] for y in main) >= 4.0
    assert not [k for y in main for k in y["causes"] if k == "leader ahead"]
    assert {y["cause"] for y in main} == {"none"}


def test_the_constraint_sumo_takes_explains_the_whole_tick_and_one_beside_it_what_it_alone_asked():
    """SUMO's next speed is the lowest its constraints allow, braking no harder than the vehicle
    can. Recorded in the red-light scene above: "red" at 12.93 m/s, 18.9 m from j1's red light,
    whose stop speed SUMO gives as 12.83 m/s; the next tick it braked to 12.48 m/s at 4.5 m/s²
    and stood 1.0 m short of that distance. The light is what SUMO's model took: the whole tick's
    braking is its (the account used to count it the 0.10 m/s the stop speed asked). A road user
    beside the vehicle's own control is counted only what it asked beyond it (issue 35: not for
    its own control), and a second road user what it alone asked."""
    signal = (12.83, "signal", None, {})
    assert shares([signal], 12.93, 0.45) == [0.45]
    turn, foe = (12.6, "turn", None, {}), (12.55, "foe", "v", {})
    assert [round(x, 2) for x in shares([foe, turn], 12.93, 0.45)] == [0.05, 0.33]
    near, far = (12.1, "foe", "v", {}), (12.7, "foe", "w", {})
    assert [round(x, 2) for x in shares([near, far], 12.93, 0.45)] == [0.45, 0.23]


def junction_scene(main: tuple[str, str, float], side: tuple[str, str, float] | None, steps: int = 120) -> list:
    """The brakings of "main", driving at full speed from `main`'s edge and position on the paper
    map, with "side" (if any) departing at 5 m/s from its own, its decisions ours (it goes across
    j2 without stopping at its line or giving way)."""
    routes: dict = {}
    with World(NET, seed=3) as world:
        account = Account(routes, world.modes)
        add_cars(world, routes, [("main", *main, "max")] + ([("side", *side, 5.0)] if side else []))
        for step in range(steps):
            snap = world.step()
            if step == 0 and side:
                world.take_control("side")
            account.tick(snap)
        account.close()
    return [y.to_json() for y in account.yields if y.vehicle == "main"]


def test_a_right_turner_slows_for_its_minor_link_whoever_comes():
    """"main" drives west on r1 into j2 and turns right, across the oncoming lane, to r3's north
    arm: j2 has an internal junction there, where a right-turner waits for oncoming traffic, and
    its link on from it is minor (state `m`). With nobody else on the map SUMO brakes it at its
    full 4.5 m/s² from 13.4 to about 6.3 m/s towards that point, then lets it speed up: a
    vehicle further from a minor link than the link's foe visibility distance (4.5 m) cannot yet
    see whether foes come, and SUMO gives it the speed at which it could stop there
    (MSVehicle::processLinkApproaches; paper-11's 228 did this at j2 with every other road user
    taken away). The same again on its way out, towards the link over the north arm's crossing.
    Its own control, like its own line: the account named it "none" (the stop speeds it asked
    allowed all main could reach), and the run's 228 and paper-12's 180 stood as road users
    forced by the car crossing ahead of them."""
    main = junction_scene(("e_j2", "j2_n2", 110.0), None)
    hard = [y for y in main if y["peak_decel_mps2"] >= 4.0]
    assert len(hard) == 2 and all(y["cause"] == "link" for y in hard)
    first = hard[0]["causes"]["link"]
    assert first["held_mps2"] >= 4.0 and 5.5 < first["min_speed_mps"] < 7.0      # down to about 6.3, not to a stop
    assert not [k for y in main for k in y["causes"] if k == "none"]


def test_a_right_turner_held_at_its_internal_junction_for_a_car_crossing_its_way():
    """The same right-turner, with "side" coming down r3's north arm and turning right (west)
    across j2 so that it is in the junction, across main's way beyond the internal junction,
    as main comes within sight of it: SUMO holds main at the internal junction (its stop before
    the next lane, MSLink's CONFLICT_STOP_AT_INTERNAL_JUNCTION), further short than the crossing
    point less its minGap, which the account asked and which allowed all main could reach. Its
    braking down to 6.3 m/s is its own approach to the minor link; from there on to a stop it
    braked for side: paper-11's 192, braking to a stop in front of 191 (4.5 m/s² held), the
    account put down to nothing."""
    main = junction_scene(("e_j2", "j2_n2", 110.0), ("n2_j2", "j2_j1", 120.0))
    braking = max(main, key=lambda y: y["peak_decel_mps2"])
    causes = braking["causes"]
    assert set(causes) <= {"link", "foe side"} and (braking["cause"], braking["by"]) == ("foe", "side")
    assert causes["link"]["min_speed_mps"] > 5.5                                 # its own, down to ~6.3
    side = causes["foe side"]
    assert side["held_mps2"] >= 4.0 and side["min_speed_mps"] < 0.5 and "to_internal_junction_m" in side
    assert yielded_to({"vehicle": "side", "t_s": braking["t_s"]}, [braking], [])   # SUMO: it gave way to side


def test_a_car_pulling_out_onto_the_road_ahead_is_followed_as_sumos_junction_leader():
    """"main" drives east on r1 through j2 with the right of way; "side" comes out of r3's north
    arm (its decisions ours: across its Stop line without stopping) and turns left onto r1 ahead
    of main. While side is in the junction SUMO's junction model follows it as main's link
    leader (MSVehicle::adaptToJunctionLeader: the follow speed at MSLink::getLeaderInfo's gap,
    `getLeader`'s), braking main at 4.5 m/s². A stop speed at that gap allows all main can
    reach: the account named the braking "none", as it did the town-11 run's 578 behind 170
    pulling out of j13's Stop arm."""
    main = junction_scene(("j1_j2", "j2_e", 100.0), ("n2_j2", "j2_e", 150.0))
    braking = max(main, key=lambda y: y["peak_decel_mps2"])
    assert (braking["cause"], braking["by"]) == ("foe", "side") and braking["causes"]["foe side"]["decel_mps2"] >= 4.0
    assert "none" not in braking["causes"]


def main_with_and_without(side: tuple[str, str, float, float], steps: int = 120) -> tuple[list, list, list]:
    """"main" turning right from r1's west arm into j2's south arm at full speed from 100 m, alone
    and with "side" (edge, to, depart position, depart speed; its decisions ours): main's speeds
    each tick alone and with side, side's distance to j2 and speed each tick, and main's brakings
    as the account with side tells them."""
    runs = []
    for cars in ([("main", "j1_j2", "j2_s2", 100.0, "max")], [("main", "j1_j2", "j2_s2", 100.0, "max"), ("side", *side)]):
        routes: dict = {}
        speeds, coming = [], []
        with World(NET, seed=3) as world:
            account = Account(routes, world.modes)
            add_cars(world, routes, cars)
            for step in range(steps):
                snap = world.step()
                if step == 0 and len(cars) > 1:
                    world.take_control("side")
                account.tick(snap)
                main, other = snap.vehicle("main"), snap.vehicle("side")
                if main is not None:
                    speeds.append((round(snap.t_s, 1), main.speed_mps, main.lane))
                    if other is not None:
                        coming.append((round(snap.t_s, 1), other.to_junction_m, other.speed_mps))
            account.close()
        runs.append((speeds, coming, [y.to_json() for y in account.yields if y.vehicle == "main"]))
    (alone, _, _), (beside, coming, yields) = runs
    return [(a, b) for a, b in zip(alone, beside)], coming, yields


@pytest.mark.parametrize("side", [("s2_j2", "j2_n2", 45.0, "max"), ("e_j2", "j2_j1", 50.0, "max")],
                         ids=["across-from-the-stop-arm", "oncoming"])
def test_a_vehicle_past_its_internal_junction_does_not_wait_for_one_still_coming(side):
    """"main" turns right off r1 into j2's south arm: past the internal junction where it waits for
    oncoming traffic (on :j2_15_0), SUMO brakes it at 4.5 m/s² once more, towards its exit link
    (minor: the crossing beyond), and lets it speed up within sight of it: its own control (`link`).
    "side" comes at 13.4 m/s, 3-4 s from j2 as main brakes there, and comes in after main has gone:
    up the south arm straight on across main's way (SUMO: side yields to main), or oncoming on r1
    (SUMO: main yields to side, at its internal junction). SUMO's own speeds for main are the same,
    tick for tick, with side and without it: side had no part in that braking. SUMO's junction model
    asks whether foes come only at a link the vehicle has still to pass (the entry link, the
    internal junction's, MSLink::opened); past them it has been let through, and the ones coming
    wait for it. The account stopped main for any vehicle coming within COMING_S onto a lane
    crossing its own, and for a foe it must let pass still coming, and named "foe side", held
    3.15 m/s²: the town-11 run's 293, past j10's internal junction, "gave way" to 458 coming 51 m
    off, by SUMO's own speeds a braking for its exit link alone (issue 35, branch miss35c)."""
    pairs, coming, yields = main_with_and_without(side)
    assert all(abs(a[1] - b[1]) < 1e-9 for a, b in pairs)                   # side changed nothing of main's
    past = [y for y in yields if y["lane"] == ":j2_15_0" and y["peak_decel_mps2"] >= 4.0]
    assert len(past) == 1 and past[0]["cause"] == "link"                    # its own exit link, as alone
    side_then = [d for t, d, v in coming if past[0]["t_s"] <= t <= past[0]["until_s"]]
    assert side_then and all(d is not None and 0 < d < 13.4 * COMING_S for d in side_then)   # within COMING_S
    assert not [k for y in yields for k in y["causes"] if k == "foe side"]
    assert not yielded_to({"vehicle": "side", "t_s": past[0]["t_s"]}, yields, [])


def test_a_right_turner_still_before_its_internal_junction_waits_for_oncoming_traffic():
    """Control: the same, with the oncoming car a second sooner. SUMO holds main at its internal
    junction for it (main's speeds differ with side and without), and the account names the foe."""
    pairs, _, yields = main_with_and_without(("e_j2", "j2_j1", 60.0, "max"))
    assert any(abs(a[1] - b[1]) > 0.5 for a, b in pairs)
    assert any(y["cause"] == "foe" and y["by"] == "side" and y["causes"]["foe side"]["held_mps2"] >= 2.0 for y in yields)

def test_a_turner_behind_one_standing_in_the_junction_on_the_straight_lane_follows_it():
    """"main" drives east on r1 into j2 to go straight on; "follower", 30 m behind it in the same
    lane, turns right (south) there; "side", a bus at 6 m/s, comes out of r3's north arm (its
    decisions ours) straight across j2 onto the road follower turns into. main, with the right of
    way, stands in the junction on its straight junction lane (:j2_10_0) for side; follower brakes
    behind it. SUMO's junction model follows main as a leader it cannot ignore (a foe lane of the
    same incoming lane, MSLink::getLeaderInfo), but `getLeader` names side, the first link leader
    it finds, joining follower's road well ahead and asking nothing of it: the account put the
    braking down to side and then to nothing, as it did the town-12 run's 439 behind 534 (SUMO's
    next speed the same without 111, higher without 534, tick by tick). Follower gave way to
    nobody: it followed main."""
    from tests.helpers.conflict_agreement import gave_way
    routes: dict = {}
    with World(NET, seed=3) as world:
        account = Account(routes, world.modes)
        add_cars(world, routes, (("main", "j1_j2", "j2_e", 124.0, "max"), ("follower", "j1_j2", "j2_s2", 94.0, "max")))
        routes["side"] = world.route("n2_j2", "j2_s2")
        world.add_vehicle("side", "bus", routes["side"], depart_pos=172.0, depart_speed=5.0)
        for step in range(90):
            snap = world.step()
            if step == 0:
                world.take_control("side")
                libsumo.vehicle.setMaxSpeed("side", 6.0)
            account.tick(snap)
        account.close()
    main = max((y for y in account.yields if y.vehicle == "main"), key=lambda y: y.peak_decel_mps2)
    assert (main.cause, main.by) == ("foe", "side") and main.min_speed_mps < 0.1     # it stood for side
    braking = max((y for y in account.yields if y.vehicle == "follower" and y.t_s > 5.0),
                  key=lambda y: y.speed_mps - y.min_speed_mps)          # the braking that shed the most speed
    assert (braking.cause, braking.by) == ("leader", "main")
    behind = braking.causes["leader main"]
    assert behind["held_mps2"] >= 4.0 and behind["diverging"] and behind["min_speed_mps"] < 3.5
    assert "none" not in braking.causes and braking.causes.get("foe side", {}).get("held_mps2", 0.0) < 0.5
    assert not any(gave_way(r) for r in yielded_to({"vehicle": "side", "t_s": braking.t_s}, [braking.to_json()], []))
