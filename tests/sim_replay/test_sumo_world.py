"""The SUMO world: it starts, repeats itself for a seed, keeps left, runs the UK signal sequence,
holds a vehicle whose decisions are ours at its line and lets it go, and walks pedestrians across.

j1's programme (paper.tll.xml), seconds into the 75 s cycle: r1 (east-west) red and amber 0-2,
green 2-29, amber 29-32; red from 32 until red and amber again at 75."""
from __future__ import annotations

import pytest

from sim_replay.maps import map_files
from sim_replay.sumo_world import World, WorldError

NET = map_files("paper").net


def run(world: World, seconds: float, on_tick=None) -> list:
    snaps = []
    for _ in range(round(seconds / world.step_s)):
        snap = world.step()
        snaps.append(snap)
        if on_tick:
            on_tick(snap)
    return snaps


def busy(world: World) -> None:
    """A mix on every road: cars, an ambulance, a bus and a cyclist, starting at random places, and
    two pedestrians; the seed decides where they start."""
    for n, (a, b, kind) in enumerate([("w_j1", "j2_e", "car"), ("e_j2", "j1_w", "car"), ("s1_j1", "j1_n1", "bus"),
                                      ("n2_j2", "j2_j1", "car"), ("s2_j2", "j2_n2", "cyclist"),
                                      ("w_j1", "j1_s1", "ambulance"), ("n1_j1", "j1_j2", "car")]):
        world.add_vehicle(f"v{n}", kind, world.route(a, b, kind), depart_pos="random")
    world.add_person("p0", "w_j1", "j1_s1", depart_pos=150.0)
    world.add_person("p1", "n2_j2", "j2_s2", depart_pos=170.0)


def test_same_seed_same_snapshots_over_300_steps():
    def record(seed: int) -> list:
        with World(NET, seed=seed) as world:
            busy(world)
            return run(world, 30.0)

    first, again, other = record(7), record(7), record(8)
    assert len(first) == 300 and first == again
    assert sum(len(s.vehicles) for s in first) > 1000 and any(s.pedestrians for s in first)
    assert first != other, "the seed is not used (random departure positions should differ)"


def test_one_world_at_a_time_and_closing_twice_is_harmless():
    world = World(NET)
    try:
        with pytest.raises(WorldError, match="already open"):
            World(NET)
    finally:
        world.close()
        world.close()
    with pytest.raises(WorldError, match="closed"):
        world.step()


def test_a_vehicle_keeps_left():
    """Heading east it is north of r1's centre line, heading west south of it; north on r2, west of it."""
    with World(NET) as world:
        world.add_vehicle("east", "car", world.route("w_j1", "j2_e"))
        world.add_vehicle("west", "car", world.route("e_j2", "j1_w"))
        world.add_vehicle("north", "car", world.route("s1_j1", "j1_n1"))
        seen = {}
        for snap in run(world, 10.0):
            for v in snap.vehicles:
                if v.road is not None:
                    seen.setdefault(v.id, []).append((v.x, v.y, v.heading_deg))
    assert all(y > 0 and abs(h - 0.0) < 1 for _, y, h in seen["east"])
    assert all(y < 0 and abs(h - 180.0) < 1 for _, y, h in seen["west"])
    assert all(x < 0 and abs(h - 90.0) < 1 for x, _, h in seen["north"])


def test_the_lights_follow_red_red_and_amber_green_amber():
    with World(NET) as world:
        changes = [(s.t_s, c) for s in run(world, 160.0) for c in s.changed]
    follows = {"red": "red_amber", "red_amber": "green", "green": "amber", "amber": "red"}
    for approach in ("west", "east", "north", "south"):
        colours = [c.colour for _, c in changes if c.approach == approach and c.crossing is None]
        assert len(colours) >= 8, approach
        assert all(follows[a] == b for a, b in zip(colours, colours[1:])), (approach, colours)
    west = [(t, c.colour, c.since_s) for t, c in changes if c.approach == "west" and c.crossing is None]
    # a phase that begins at t is first reported by the tick that ends at t + 0.1 s: SUMO switched the
    # light at the start of that step and moved every vehicle under it
    assert west[:5] == [(0.1, "red_amber", 0.1), (2.1, "green", 2.1), (29.1, "amber", 29.1), (32.1, "red", 32.1),
                        (75.1, "red_amber", 75.1)]
    walk = [c.colour for _, c in changes if c.crossing is not None and c.approach == "west"]
    assert walk[:3] == ["red", "green", "red"]


def test_a_vehicle_under_our_control_runs_a_red_light_unless_held_and_goes_when_released():
    """At 33 s (j1's west approach red until 75 s) two vehicles whose decisions are ours come up to
    the line: one is left alone and drives through the red; the other is held, stands behind the
    line through the red and the first seconds of green, and crosses once released at 80 s."""
    with World(NET) as world:
        run(world, 33.0)
        route = world.route("w_j1", "j1_j2")
        world.add_vehicle("runner", "car", route, depart_pos=110.0)
        world.add_vehicle("held", "car", route, depart_pos=40.0)
        world.take_control("runner")
        world.take_control("held")
        world.step()
        assert world.hold("held")
        runner_entered_on = None
        held_states = []
        for snap in run(world, 47.0):                       # to 80 s
            runner, held = snap.vehicle("runner"), snap.vehicle("held")
            if runner and runner.junction == "j1" and runner_entered_on is None:
                runner_entered_on = snap.signal("j1", "west").colour
            held_states.append((snap.t_s, held))
        assert runner_entered_on == "red"
        assert all(h.to_line_m is not None and h.to_line_m >= 0.0 and h.held and h.controlled for _, h in held_states)
        standing = [h for t, h in held_states if t >= 70.0]
        assert all(h.speed_mps < 0.01 and h.to_line_m < 1.0 for h in standing)   # at the line, not short of it
        assert held_states[-1][1].light == "green"
        world.release("held")
        after = run(world, 6.0)
    assert not after[-1].vehicle("held").held
    assert any(s.vehicle("held") and s.vehicle("held").junction == "j1" for s in after)


def test_a_vehicle_released_before_it_reaches_the_line_drives_on_without_stopping():
    with World(NET) as world:
        world.add_vehicle("v", "car", world.route("w_j1", "j1_j2"), depart_pos=0.0)
        world.take_control("v")
        assert world.hold("v") is False                     # not on the network until a tick reports it
        world.step()
        assert world.hold("v") and world.hold("v")          # (holding twice is holding)
        run(world, 3.0)
        world.release("v")
        world.release("v")                                  # (releasing twice is harmless)
        snaps = run(world, 20.0)
    speeds = [s.vehicle("v").speed_mps for s in snaps if s.vehicle("v")]
    assert min(speeds) > 12.0 and any(s.vehicle("v") and s.vehicle("v").junction == "j1" for s in snaps)


def test_a_vehicle_too_close_to_stop_cannot_be_held():
    """At 13.4 m/s a car needs 20 m to stop at its planned 4.5 m/s²: 8 m before the line SUMO refuses."""
    with World(NET) as world:
        world.add_vehicle("late", "car", world.route("w_j1", "j1_j2"), depart_pos=100.0)
        world.take_control("late")
        v = None
        while v is None or v.to_line_m > 8.0:
            v = world.step().vehicle("late")
        assert v.speed_mps > 13.0
        assert world.hold("late") is False
        assert not world.step().vehicle("late").held


def test_sumo_still_obeys_the_lights_for_a_vehicle_it_decides_for():
    with World(NET) as world:
        run(world, 33.0)
        world.add_vehicle("sumo", "car", world.route("w_j1", "j1_j2"), depart_pos=110.0)
        snaps = run(world, 30.0)
    positions = [s.vehicle("sumo") for s in snaps if s.vehicle("sumo")]
    assert all(v.junction is None and v.to_line_m >= 0 for v in positions)
    assert positions[-1].speed_mps < 0.01 and not positions[-1].controlled


def test_pedestrians_cross_at_the_signals_and_at_the_stop_junction():
    with World(NET) as world:
        walk = world.add_person("p", "w_j1", "j1_w", depart_pos=170.0, arrival_pos=5.0)
        world.add_person("q", "n2_j2", "j2_s2", depart_pos=180.0, arrival_pos=20.0)
        crossed: dict[str, set[str]] = {"p": set(), "q": set()}
        arrived: set[str] = set()
        lights_when_on_crossing = set()
        for snap in run(world, 120.0):
            for p in snap.pedestrians:
                if p.crossing:
                    crossed[p.id].add(p.crossing)
                    if p.junction == "j1":
                        lights_when_on_crossing.add(next(s.colour for s in snap.signals if s.crossing == p.crossing))
            arrived |= set(snap.arrived)
    assert walk == ("w_j1", "j1_w")          # the pavements; SUMO picks the crossing on the way
    assert crossed["p"] == {":j1_c3"}                                       # r1, west arm of j1
    assert crossed["q"] and all(c.startswith(":j2_c") for c in crossed["q"])
    assert {"p", "q"} <= arrived
    assert "green" in lights_when_on_crossing


def test_vehicles_and_bicycles_of_every_type_drive():
    kinds = ("car", "ambulance", "fire_engine", "police_car", "bus", "cyclist")
    with World(NET) as world:
        for n, kind in enumerate(kinds):
            world.add_vehicle(kind, kind, world.route("e_j2", "j1_w", kind), depart_pos=n * 25.0, depart_speed=0)
        snap = run(world, 3.0)[-1]
    assert {v.type for v in snap.vehicles} == set(kinds)
    assert all(v.speed_mps > 0 for v in snap.vehicles)
    with World(NET) as world:
        with pytest.raises(WorldError, match="unknown vehicle type"):
            world.add_vehicle("x", "tank", ("w_j1",))
        with pytest.raises(WorldError, match="no route"):
            world.route("w_j1", "nowhere")
        with pytest.raises(WorldError, match="vehicle y"):
            world.add_vehicle("y", "car", ("w_j1", "n2_j2"))         # edges that do not meet
        assert world.step().vehicles == ()                           # and the world goes on without it


def _right_turn_on_green(mindful: bool) -> tuple[str | None, float]:
    """j1 at 3 s: the west approach green. A car from the west turns right (across the oncoming
    lane, in left-hand traffic) while a car from the east comes straight on; both are ours. The
    light the turner entered on, and its lowest speed inside the junction."""
    with World(NET) as world:
        run(world, 3.0)
        world.add_vehicle("oncoming", "car", world.route("j2_j1", "j1_w"), depart_pos=70.0)
        world.add_vehicle("turner", "car", world.route("w_j1", "j1_s1"), depart_pos=110.0)
        world.take_control("oncoming")
        world.take_control("turner")
        world.step()
        world.mind_foes("turner", mindful)
        entered_on, slowest = None, float("inf")
        for snap in run(world, 25.0):
            v = snap.vehicle("turner")
            if v and v.junction == "j1":
                entered_on = entered_on or snap.signal("j1", "west").colour
                slowest = min(slowest, v.speed_mps)
        return entered_on, slowest


def test_a_vehicle_going_lawfully_on_green_waits_in_the_junction_for_oncoming_traffic():
    """HC 180: turning right, wait until there is a safe gap in the oncoming traffic. A lawful go
    (World.mind_foes) lets SUMO keep the turner out of the oncoming car's way: it stops inside the
    junction until the car has passed. Without it, the turner drives through at speed."""
    assert _right_turn_on_green(True) == ("green", 0.0)
    entered_on, slowest = _right_turn_on_green(False)
    assert entered_on == "green" and slowest > 5.0
