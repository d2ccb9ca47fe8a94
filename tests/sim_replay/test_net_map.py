"""The run.start map of a SUMO network: valid, what the reasoner reads (stop lines, the box, the major
road), and what it measures a passage against: a car the SUMO world drove through j1's red light is
found crossing the west stop line on red, at the moment the world says its front passed the line."""
from __future__ import annotations

import json

import pytest

from reasoner import history
from reasoner.history import read_map
from sim_replay.maps import map_files
from sim_replay.monitors import MonitorsError, read_monitors
from sim_replay.net_map import world_map
from sim_replay.sumo_net import read_network
from sim_replay.sumo_world import World
from store import validate_event

PAPER = map_files("paper")
T0 = 1_732_176_000_000_000_000
SECOND = 1_000_000_000


@pytest.fixture(scope="module")
def network():
    return read_network(PAPER.net)


@pytest.fixture(scope="module")
def the_map(network):
    return world_map(network, read_monitors(PAPER.monitors, set(network.junctions)))


def start_event(the_map: dict) -> dict:
    return {"v": 1, "run": "sumo-map", "src": "sim/world", "seq": 0, "t": T0, "kind": "run.start",
            "body": {"map": the_map, "seed": 0, "config": {}}}


def test_the_map_is_a_valid_run_start_and_the_same_every_time(network, the_map):
    validate_event(start_event(the_map))
    again = world_map(read_network(PAPER.net), read_monitors(PAPER.monitors))
    assert json.dumps(again, sort_keys=True) == json.dumps(the_map, sort_keys=True)
    assert the_map["network"] == {"file": "paper.net.xml", "sha256": the_map["network"]["sha256"], "lefthand": True}
    assert len(json.dumps(the_map)) < 64 * 1024          # a small part of the 1 MiB an event may be


def test_roads_as_the_paper_draws_them(the_map):
    assert the_map["roads"] == [
        {"id": "r1", "from": [-200.0, 0.0], "to": [400.0, 0.0], "speed_limit_mph": 30},
        {"id": "r2", "from": [0.0, -200.0], "to": [0.0, 200.0], "speed_limit_mph": 30},
        {"id": "r3", "from": [200.0, -200.0], "to": [200.0, 200.0], "speed_limit_mph": 30}]


def test_the_reasoner_reads_the_stop_lines_the_box_and_the_major_road(the_map):
    m = read_map(start_event(the_map))
    assert m.problems == ()
    j1, j2 = m.junction("j1"), m.junction("j2")
    west = j1.line_for("west")
    assert (west.a, west.b, west.kind, west.source) == ((-12.0, 0.0), (-12.0, 3.5), "signal", "map stop_lines")
    assert west.to_line(-20.0, 1.75) == pytest.approx(8.0) and west.to_line(-2.0, 1.75) == pytest.approx(-10.0)
    assert west.alongside(-20.0, 1.75)
    assert j1.extent_m == pytest.approx(12.0)
    assert j1.boxed and j1.in_box(0.0, 0.0) and j1.in_box(6.0, 1.75) and not j1.in_box(-10.0, 1.75)
    assert not j1.in_box(7.5, 7.5)                       # the kerb's corner, not the carriageway
    assert j1.major is None                              # at signals the lights decide
    assert j2.control == "stop" and not j2.boxed
    assert j2.line_for("north").kind == "stop_sign" and j2.line_for("south").kind == "give_way"
    assert j2.line_for("east") is None and j2.major == frozenset({"east", "west"})
    assert j2.is_major("west") and not j2.is_major("north")
    assert sorted(j1.monitors) == ["monitor/m1"] and sorted(j2.monitors) == ["monitor/m2", "monitor/m3"]
    assert m.road("r1", None, None).limit_mph == 30 and m.road(None, 150.0, 1.75).id == "r1"


def test_lanes_are_polylines_with_widths_and_junctions_carry_their_crossings(the_map):
    lanes = {lane["id"]: lane for lane in the_map["lanes"]}
    assert lanes["w_j1_1"] == {"id": "w_j1_1", "edge": "w_j1", "road": "r1", "index": 1, "kind": "road",
                               "width_m": 3.5, "shape": [[-200.0, 1.75], [-12.0, 1.75]]}
    assert lanes["w_j1_0"]["kind"] == "sidewalk" and lanes["w_j1_0"]["width_m"] == 2.0
    assert not any(i.startswith(":") for i in lanes)
    j1 = next(j for j in the_map["junctions"] if j["id"] == "j1")
    assert {c["arm"] for c in j1["crossings"]} == {"north", "south", "east", "west"}
    assert len(j1["shape"]) > 8


def test_each_monitor_sees_the_line_it_watches_its_junction_and_what_comes_up_to_the_line(network):
    monitors = read_monitors(PAPER.monitors, set(network.junctions))
    assert [m.id for m in monitors] == ["m1", "m2", "m3"]
    for m in monitors:
        j = network.junctions[m.junction]
        assert m.sees(j.x, j.y), m.id
        for name in m.watches:
            (ax, ay), (bx, by) = j.approach(name).line
            assert m.sees(ax, ay) and m.sees(bx, by), (m.id, name)
            lane = network.lanes[j.approach(name).lanes[0]]
            (x0, y0), (x1, y1) = lane.shape[-2], lane.shape[-1]
            length = ((x1 - x0) ** 2 + (y1 - y0) ** 2) ** 0.5
            assert m.sees(x1 - (x1 - x0) / length * 50, y1 - (y1 - y0) / length * 50), (m.id, name, "50 m out")


def test_a_monitors_file_naming_no_junction_of_the_network_is_refused(tmp_path):
    path = tmp_path / "m.json"
    path.write_text(json.dumps({"monitors": [{"id": "m9", "junction": "j7", "x": 0, "y": 0, "heading_deg": 0,
                                              "range_m": 50, "fov_deg": 90}]}))
    with pytest.raises(MonitorsError, match="j7"):
        read_monitors(path, {"j1", "j2"})
    path.write_text(json.dumps({"monitors": [{"id": "m 9", "junction": "j1", "x": 0, "y": 0, "heading_deg": 0,
                                              "range_m": 50, "fov_deg": 90}]}))
    with pytest.raises(MonitorsError, match="id"):
        read_monitors(path)


def drive(world: World, ident: str, ticks: int) -> tuple[list[dict], float | None]:
    """Each tick's entity.state of a vehicle and the signals (every approach's colour on the first
    tick, then each change), as events; and when (s) the world first reported the vehicle's front
    past its line."""
    events, seqs, crossed = [], {}, None

    def emit(src: str, t_s: float, kind: str, body: dict) -> None:
        seqs[src] = seqs.get(src, -1) + 1
        events.append({"v": 1, "run": "sumo-map", "src": src, "seq": seqs[src], "t": T0 + round(t_s * SECOND),
                       "kind": kind, "body": body})

    emit(f"vehicle/{ident}", 0.0, "entity.spawn", {"type": "car", "driver": "human"})
    for n in range(ticks):
        snap = world.step()
        for s in snap.signals if n == 0 else snap.changed:
            if s.crossing is None:
                emit(f"signal/{s.junction}-{s.approach}", snap.t_s, "signal.state",
                     {"junction": s.junction, "approach": s.approach, "colour": s.colour})
        v = snap.vehicle(ident)
        if v is None:
            continue
        if crossed is None and v.junction is not None:
            crossed = snap.t_s
        emit(f"vehicle/{ident}", snap.t_s, "entity.state",
             {"x": v.x, "y": v.y, "heading_deg": v.heading_deg, "speed_mps": v.speed_mps, "road": v.road,
              "junction": v.junction})
    return events, crossed


def test_the_reasoner_measures_a_sumo_red_light_run_against_the_exported_map(the_map):
    with World(PAPER.net) as world:
        for _ in range(330):                         # 33 s: j1's west approach is red from 32.1 s to 75.1 s
            world.step()
        world.add_vehicle("173", "car", world.route("w_j1", "j1_j2"), depart_pos=110.0)
        world.take_control("173")
        events, crossed = drive(world, "173", 120)
    for e in events:
        validate_event(e)
    passages = history.from_events([start_event(the_map), *events], "173")
    (p,) = [p for p in passages if p.junction.id == "j1"]
    assert p.approach == "west" and p.line is not None and p.line.kind == "signal"
    assert p.crossing is not None and p.crossing.light.colour == "red"
    # the crossing the reasoner interpolates lies in the tick where the world first had it past the line
    assert crossed - 0.1 <= (p.crossing.t - T0) / SECOND <= crossed
    assert p.limit_mph == 30 and p.limit_road == "r1"


def test_the_reasoner_finds_a_stop_line_at_j2_on_the_exported_map(the_map):
    with World(PAPER.net) as world:
        world.add_vehicle("41", "car", world.route("n2_j2", "j2_s2"), depart_pos=150.0)
        world.take_control("41")
        events, crossed = drive(world, "41", 80)
    (p,) = [p for p in history.from_events([start_event(the_map), *events], "41") if p.junction.id == "j2"]
    assert p.approach == "north" and p.line.kind == "stop_sign" and p.crossing is not None
    assert crossed - 0.1 <= (p.crossing.t - T0) / SECOND <= crossed
    assert p.exit == "south"


def test_the_papers_run_judged_on_the_exported_map_gives_the_papers_verdicts(the_map, tmp_path):
    """sim_replay/paper.py's events with its hand-written map swapped for the SUMO network's: the
    verdicts are the paper's, with the margins measured against the exported west stop line (12 m out,
    as the hand-written one)."""
    import reasoner
    from sim_replay.paper import RUN, paper_run
    from store import Store

    events = paper_run()
    (start,) = [e for e in events if e["kind"] == "run.start"]
    start["body"]["map"] = the_map
    with Store(tmp_path / "gaps.db") as store:
        store.append(events)
    with reasoner.open(tmp_path / "gaps.db") as case:
        found = case.incidents(RUN)
    assert [(i.vehicle, i.rule, i.verdict) for i in found] == [
        ("173", "HC 176", "punishable"), ("253", "HC 176", "mitigated")]
    assert [i.margin.value for i in found] == [2.444, 2.444]      # as on the hand-written map (README)
