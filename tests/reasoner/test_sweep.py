"""reasoner/sweep.py: the candidate moments of acts nobody recorded, from measurements alone.

The verdicts on these acts are tested end to end in test_foreign_scenarios.py; here, that the
sweep names a candidate where the measurements suggest an act and none where they show the
vehicle doing what the law asks (so the histories run only where needed)."""
from __future__ import annotations

from reasoner.history import read_map
from reasoner.sweep import BOX, ENTER, SPEEDING, sweep

from tests.helpers.foreign import Foreign, Motion, crossroads, rate, roads_through


def candidates(run: Foreign, kind: str = "monitor.observation"):
    start = next(e for e in run.events if e["kind"] == "run.start")
    return sweep([e for e in run.events if e["kind"] == kind], read_map(start))


def stop_junction() -> Foreign:
    return Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop")])


def test_a_car_rolling_over_a_stop_line_is_a_candidate_and_one_that_stops_is_not():
    rolling = stop_junction()
    rolling.watch("7", Motion(-80, 13.4), "west", rate(2, 0, 8))
    (c,) = candidates(rolling)
    assert (c.user, c.action, c.junction) == ("7", ENTER, "J1") and "Stop junction" in c.why

    stopping = stop_junction()
    stopping.watch("8", Motion.stopping_at(-80, 13.4, -12.5, wait=3, then=5), "west", rate(2, 0, 25))
    assert candidates(stopping) == []


def test_a_give_way_entry_is_a_candidate_only_when_another_road_user_braked_hard():
    def run(brake: float) -> Foreign:
        r = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "give_way", kinds={"south": "give_way",
                                                                           "north": "give_way"})])
        r.watch("7", Motion(-40, 6.0), "south", rate(5, 0, 10))
        r.watch("u1", Motion(-60, 13.0, [(4.0, 0.0), (2.0, -brake)]), "west", rate(5, 0, 10))
        return r
    (c,) = candidates(run(5.0))
    assert (c.user, c.action) == ("7", ENTER) and "u1 braked" in c.why
    assert candidates(run(1.0)) == []


def test_a_signal_entry_is_a_candidate_only_when_the_camera_states_no_light():
    silent = Foreign()
    silent.watch("9", Motion(-60, 13.4), "west", rate(5, 0, 8))
    assert [c.user for c in candidates(silent)] == ["9"]
    stating = Foreign()
    stating.watch("9", Motion(-60, 13.4), "west", rate(5, 0, 8), facts=["9 has green light"])
    assert candidates(stating) == []


def test_standing_in_a_yellow_box_is_a_candidate_once():
    run = Foreign(junctions=[crossroads("J1", 0.0, 0.0, "lights", box=True)])
    run.watch("5", Motion.stopping_at(-40, 8.0, 2.0, wait=6, then=5), "west", rate(5, 0, 20),
              facts=["5 has green light"])
    (c,) = candidates(run)
    assert (c.user, c.action) == ("5", BOX)


def test_speeding_near_a_junction_is_a_candidate_once_per_stretch():
    run = Foreign(roads=roads_through(0.0, 0.0, limit_mph=30))
    run.watch("3", Motion(-90, 20.0), "west", rate(5, 0, 8), facts=["3 has green light"])
    found = [c for c in candidates(run) if c.action == SPEEDING]
    assert len(found) == 1 and "45 mph" in found[0].why
    lawful = Foreign(roads=roads_through(0.0, 0.0, limit_mph=30))
    lawful.watch("3", Motion(-90, 13.0), "west", rate(5, 0, 8), facts=["3 has green light"])
    assert [c for c in candidates(lawful) if c.action == SPEEDING] == []


def test_a_run_with_no_monitor_is_swept_on_the_vehicles_own_positions():
    run = stop_junction()
    run.drive("7", Motion(-80, 13.4), "west", rate(2, 0, 8))
    assert [c.user for c in candidates(run, "entity.state")] == ["7"]


def test_hostile_bodies_are_passed_over():
    run = stop_junction()
    run.emit("monitor/m1", 1, "monitor.observation", {"vehicle": "7", "x": "a", "y": None, "speed_mps": float("nan")})
    run.emit("monitor/m1", 2, "monitor.observation", {"vehicle": ["7"], "x": 1.0, "y": 1.0})
    run.emit("monitor/m1", 3, "monitor.observation", {"vehicle": "7", "x": float("inf"), "y": 0.0})
    assert candidates(run) == []


def mixed_junction() -> Foreign:
    """The simulation's j2: a Stop line on the north arm, a Give Way line on the south arm, the
    east-west road major (no line); the junction's `control` names only "stop"."""
    return Foreign(junctions=[crossroads("J1", 0.0, 0.0, "stop", kinds={"north": "stop", "south": "give_way"})])


def test_at_a_mixed_junction_only_the_stop_arm_is_held_to_stopping():
    # HC 171: stop at the Stop line; the major road (no line) and the Give Way arm (HC 172: give
    # way, no duty to stop) owe no stop, so driving through from them is no Stop candidate
    run = mixed_junction()
    run.watch("north", Motion(-80, 13.4), "north", rate(5, 0, 8))
    run.watch("major", Motion(-80, 13.4), "west", rate(5, 0, 8))
    run.watch("giveway", Motion(-80, 13.4), "south", rate(5, 0, 8))
    assert [(c.user, c.action) for c in candidates(run)] == [("north", ENTER)]


def test_at_a_mixed_junction_a_give_way_entry_before_major_road_braking_is_a_candidate_a_major_entry_not():
    run = mixed_junction()
    run.watch("7", Motion(-40, 6.0), "south", rate(5, 0, 10))
    run.watch("u1", Motion(-60, 13.0, [(4.0, 0.0), (2.0, -5.0)]), "west", rate(5, 0, 10))
    run.watch("u2", Motion(-45, 10.0), "east", rate(5, 0, 10))     # on the major road: entering is its right
    assert [c.user for c in candidates(run) if "braked" in c.why] == ["7"]
