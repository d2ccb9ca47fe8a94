"""The town map (the benchmarks' long runs): the paper's kinds of junction repeated on a grid, each
signal programme in the UK order, and every camera aimed at a stop line it can see."""
from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import Counter

import pytest

from sim_replay.maps import map_files
from sim_replay.monitors import read_monitors
from sim_replay.sim_config import SimConfig
from sim_replay.simulation import Simulation
from sim_replay.sumo_net import read_network
from sim_replay.world_state import COLOURS

TOWN = map_files("town")


@pytest.fixture(scope="module")
def net():
    return read_network(TOWN.net)


def test_twenty_junctions_of_the_papers_kinds_left_hand(net):
    assert net.lefthand and len(net.junctions) == 20
    assert Counter(j.control for j in net.junctions.values()) == {"lights": 10, "stop": 5, "give_way": 5}
    lines = Counter(a.kind for j in net.junctions.values() for a in j.approaches if a.kind)
    assert lines == {"signal": 40, "stop": 8, "give_way": 12}
    assert [j.id for j in net.junctions.values() if j.box] == ["j1"]
    for paper_j2 in ("j2", "j13"):
        assert {a.name: a.kind for a in net.junctions[paper_j2].approaches} == {
            "east": None, "west": None, "north": "stop", "south": "give_way"}


def test_every_signal_junction_numbers_its_links_as_the_papers_j1(net):
    for tls, links in net.links.items():
        assert [(link.approach, link.direction) for link in links[:12]] == [
            (arm, turn) for arm in ("south", "east", "north", "west") for turn in ("l", "s", "r")], tls
        crossings = {c.id: c.arm for c in net.junctions[tls].crossings}
        assert [crossings[link.crossing] for link in links[12:]] == ["south", "east", "north", "west"], tls


def test_every_programme_runs_in_the_uk_order_for_every_approach(net):
    follows = {"red": "red_amber", "red_amber": "green", "green": "amber", "amber": "red"}
    logics = ET.parse(TOWN.net).getroot().iter("tlLogic")
    for logic in logics:
        states = [p.get("state") for p in logic.iter("phase")]
        for key, index in net.approach_links(logic.get("id")).items():
            colours = [COLOURS[s[index]] for s in states]
            changes = [(a, b) for a, b in zip(colours, colours[1:] + colours[:1]) if a != b]
            assert changes and all(follows[a] == b for a, b in changes), (key, colours)


def test_every_camera_sees_the_whole_stop_line_it_watches_and_the_junction(net):
    monitors = read_monitors(TOWN.monitors, set(net.junctions))
    assert len(monitors) == 23
    for m in monitors:
        junction = net.junctions[m.junction]
        (approach,) = m.watches
        line = junction.approach(approach).line
        assert line is not None and all(m.sees(x, y) for x, y in line), m.id
        assert m.sees(junction.x, junction.y), m.id
    watched = {(m.junction, a) for m in monitors for a in m.watches}
    kinds = {junction.approach(a).kind for j, a in watched for junction in [net.junctions[j]]}
    assert kinds == {"signal", "stop", "give_way"}


def test_a_short_run_on_the_town_sets_off_vehicles_all_through_it():
    sim = Simulation(SimConfig(run="town-test", map="town", seed=3, vehicles=30, duration_s=60.0,
                               depart_within=1.0, pedestrians=2))
    events = list(sim.events())
    spawns = sorted(e["t"] for e in events if e["kind"] == "entity.spawn" and e["src"].startswith("vehicle/"))
    assert len(spawns) >= 25 and spawns[-1] - spawns[0] > 40 * 1_000_000_000
    assert any(e["kind"] == "monitor.observation" for e in events)
