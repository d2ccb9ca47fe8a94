"""`gaps sim` on a SUMO user's own files (issue 39): networks made by netgenerate and netconvert,
a `.sumocfg` with its net and routes, routes from a `.rou.xml`. Each network either runs end to end
with the map its junction types say (traffic_light: signal lines; priority: Give Way lines on the
minor arms; priority_stop: Stop lines) or is refused with a one-line reason, exit 2, no traceback.

The expected stop-line kinds are SUMO's junction types read as the TSRGD marks them: at signals the
stop line (diagram 1001), a priority_stop junction's minor arms a Stop sign's line (diagram 1002.1),
a priority junction's minor arms a Give Way line (diagram 1003).
"""
from __future__ import annotations

import json
import xml.etree.ElementTree as ET

import pytest

from store import Store
from tests.helpers.cli import gaps
from tests.helpers.sumo_tools import netconvert, netgenerate

GRID = ("--grid", "--grid.number", "2", "--grid.length", "120", "--grid.attach-length", "80")


def _one_line(result) -> str:
    return " ".join(result.output.split())


def _run_start(db, run):
    with Store(db, read_only=True) as store:
        return next(e for e in store.events(run) if e["kind"] == "run.start")


def _sim(tmp_path, *args, run="own-1", vehicles="8", duration="30s"):
    return gaps("sim", "--vehicles", vehicles, "--duration", duration, "--run", run, *args, "--json",
                db=tmp_path / "s.db")


@pytest.fixture(scope="module")
def nets(tmp_path_factory):
    where = tmp_path_factory.mktemp("nets")
    return {
        "signals": netgenerate(where / "signals.net.xml", *GRID, "--default-junction-type", "traffic_light",
                               "--lefthand"),
        "closed": netgenerate(where / "closed.net.xml", "--grid", "--grid.number", "3", "--grid.length", "120",
                              "--default-junction-type", "traffic_light", "--lefthand"),
        "priority": netgenerate(where / "priority.net.xml", *GRID, "--default-junction-type", "priority",
                                "--lefthand"),
        "right": netgenerate(where / "right.net.xml", *GRID, "--default-junction-type", "traffic_light"),
        "ring": netgenerate(where / "ring.net.xml", "--spider", "--spider.arm-number", "4", "--spider.circle-number",
                            "1", "--spider.omit-center", "--default-junction-type", "traffic_light", "--lefthand"),
        "right_before_left": netgenerate(where / "rbl.net.xml", *GRID, "--default-junction-type", "right_before_left",
                                         "--lefthand"),
        "unregulated": netgenerate(where / "unregulated.net.xml", *GRID, "--default-junction-type", "unregulated",
                                   "--lefthand"),
    }


def test_a_generated_left_hand_signal_grid_runs_with_signal_lines_at_its_four_junctions(nets, tmp_path):
    # issue 39: `netgenerate --grid --default-junction-type traffic_light --lefthand` crashed with IndexError;
    # no --monitors: a network of the user's has no cameras unless a monitors file says where they are
    result = _sim(tmp_path, "--map", nets["signals"])
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["simulation"]["vehicles"] == 8
    start = _run_start(tmp_path / "s.db", "own-1")["body"]["map"]
    assert start["network"]["lefthand"] is True and start["monitors"] == []
    junctions = {j["id"]: j for j in start["junctions"]}
    assert sorted(junctions) == ["A0", "A1", "B0", "B1"]       # the fringe's road ends are not junctions
    for j in junctions.values():
        assert j["control"] == "lights" and len(j["stop_lines"]) == 4
        assert {line["kind"] for line in j["stop_lines"]} == {"signal"}


def test_a_monitors_file_beside_the_network_is_its_cameras(nets, tmp_path):
    (tmp_path / "grid.net.xml").write_bytes(nets["signals"].read_bytes())
    camera = {"id": "cam1", "junction": "A0", "x": 90.0, "y": 90.0, "heading_deg": 225.0, "range_m": 60.0,
              "fov_deg": 90.0}
    (tmp_path / "grid.monitors.json").write_text(json.dumps({"monitors": [camera]}))
    result = _sim(tmp_path, "--map", tmp_path / "grid.net.xml")
    assert result.exit_code == 0, result.output
    assert _run_start(tmp_path / "s.db", "own-1")["body"]["map"]["monitors"] == [camera]


def test_signals_joined_under_one_programme_are_published_per_junction_and_approach(tmp_path):
    # netgenerate --tls.join: one traffic light (joinedS_A0_A1) runs two junctions 25 m apart
    net = netgenerate(tmp_path / "joined.net.xml", "--grid", "--grid.x-number", "2", "--grid.y-number", "2",
                      "--grid.x-length", "120", "--grid.y-length", "25", "--grid.attach-length", "80",
                      "--default-junction-type", "traffic_light", "--tls.join", "--tls.join-dist", "30", "--lefthand")
    assert "joinedS_A0_A1" in net.read_text()
    result = _sim(tmp_path, "--map", net, duration="20s")
    assert result.exit_code == 0, result.output
    with Store(tmp_path / "s.db", read_only=True) as store:
        signals = {(e["body"]["junction"], e["body"]["approach"]) for e in store.events("own-1")
                   if e["kind"] == "signal.state"}
    lines = {(j["id"], line["approach"]) for j in _run_start(tmp_path / "s.db", "own-1")["body"]["map"]["junctions"]
             for line in j["stop_lines"]}
    assert len(lines) == 16 and signals == lines


@pytest.mark.parametrize("name", ["closed", "ring"])
def test_a_closed_network_without_road_ends_still_gets_its_vehicles(nets, tmp_path, name):
    # a grid with no road ends crashed (IndexError); on a ring without U-turns, a vehicle drawn to leave by the
    # other carriageway had no route and was left out without a word
    result = _sim(tmp_path, "--map", nets[name])
    assert result.exit_code == 0, result.output
    with Store(tmp_path / "s.db", read_only=True) as store:
        spawned = [e for e in store.events("own-1") if e["kind"] == "entity.spawn" and e["src"].startswith("vehicle/")]
    assert len(spawned) == 8


def test_a_random_network_with_bends_runs(tmp_path):
    # netgenerate --rand puts two-road nodes (bends) with lanes inside them: a vehicle there was taken to be
    # in a junction the map does not have (KeyError in the witness)
    net = netgenerate(tmp_path / "rand.net.xml", "--rand", "--rand.iterations", "15", "--rand.min-angle", "80",
                      "--rand.grid", "--tls.guess", "--tls.guess.threshold", "40", "--lefthand")
    result = _sim(tmp_path, "--map", net, vehicles="10")
    assert result.exit_code == 0, result.output
    with Store(tmp_path / "s.db", read_only=True) as store:
        states = [e["body"] for e in store.events("own-1") if e["kind"] == "entity.state"
                  and e["src"].startswith("vehicle/")]
    assert states and all(s["road"] is not None or s["junction"] is not None for s in states)
    bends = [s for s in states if s["lane"].startswith(":") and s["junction"] is None]
    assert bends and all(s["road"] for s in bends)       # through a bend: on its road, not in a junction
    junctions = _run_start(tmp_path / "s.db", "own-1")["body"]["map"]["junctions"]
    assert "traffic_light" in {j["sumo_type"] for j in junctions}


def test_a_priority_grid_has_give_way_lines_on_its_minor_arms_only(nets, tmp_path):
    result = _sim(tmp_path, "--map", nets["priority"])
    assert result.exit_code == 0, result.output
    for j in _run_start(tmp_path / "s.db", "own-1")["body"]["map"]["junctions"]:
        assert j["control"] == "give_way" and {line["kind"] for line in j["stop_lines"]} == {"give_way"}
        assert len(j["major"]) == 2 and len(j["stop_lines"]) == 2


def test_netconvert_plain_files_with_a_stop_junction_give_stop_sign_lines(tmp_path):
    (tmp_path / "t.nod.xml").write_text(
        '<nodes><node id="c" x="0" y="0" type="priority_stop"/><node id="w" x="-150" y="0" type="dead_end"/>'
        '<node id="e" x="150" y="0" type="dead_end"/><node id="s" x="0" y="-150" type="dead_end"/></nodes>')
    (tmp_path / "t.edg.xml").write_text(
        '<edges>' + "".join(f'<edge id="{a}{b}" from="{a}" to="{b}" numLanes="1" speed="13.89" priority="{p}"/>'
                            for a, b, p in (("w", "c", 2), ("c", "w", 2), ("e", "c", 2), ("c", "e", 2),
                                            ("s", "c", 1), ("c", "s", 1))) + '</edges>')
    net = netconvert(tmp_path / "t.net.xml", "--node-files", "t.nod.xml", "--edge-files", "t.edg.xml", "--lefthand")
    result = _sim(tmp_path, "--map", net, vehicles="4", duration="20s")
    assert result.exit_code == 0, result.output
    (j,) = _run_start(tmp_path / "s.db", "own-1")["body"]["map"]["junctions"]
    assert j["control"] == "stop" and j["major"] == ["east", "west"]
    assert [(line["approach"], line["kind"]) for line in j["stop_lines"]] == [("south", "stop_sign")]


def test_a_right_hand_network_is_refused_with_the_reason(nets, tmp_path):
    # issue 39: a right-hand network ran silently although the rules are the UK's (left-hand traffic)
    result = _sim(tmp_path, "--map", nets["right"])
    assert result.exit_code == 2
    said = _one_line(result)
    assert "right-hand traffic" in said and "--lefthand" in said and "right.net.xml" in said
    assert not (tmp_path / "s.db").exists()


def test_a_right_hand_network_rebuilt_with_netconvert_lefthand_runs(nets, tmp_path):
    rebuilt = netconvert(tmp_path / "left.net.xml", "--sumo-net-file", str(nets["right"]), "--lefthand")
    result = _sim(tmp_path, "--map", rebuilt)
    assert result.exit_code == 0, result.output


def _fork(folder):
    """A netconvert network whose junction c has two arms from the north, 35 degrees apart (a fork)."""
    (folder / "f.nod.xml").write_text(
        '<nodes><node id="c" x="0" y="0" type="priority"/><node id="w" x="-150" y="0"/><node id="e" x="150" y="0"/>'
        '<node id="n1" x="-20" y="150"/><node id="n2" x="-110" y="110"/></nodes>')
    (folder / "f.edg.xml").write_text("<edges>" + "".join(
        f'<edge id="{a}{b}" from="{a}" to="{b}" numLanes="1" priority="{p}"/><edge id="{b}{a}" from="{b}" to="{a}" '
        f'numLanes="1" priority="{p}"/>' for a, b, p in (("w", "c", 2), ("c", "e", 2), ("n1", "c", 1), ("n2", "c", 1)))
        + "</edges>")
    return netconvert(folder / "fork.net.xml", "--node-files", "f.nod.xml", "--edge-files", "f.edg.xml", "--lefthand")


@pytest.mark.parametrize("name,words", [
    ("fork", ("fork.net.xml: junction c", "both come from the north", "compass")),
    ("right_before_left", ("junction", "right_before_left", "no UK")),
    ("unregulated", ("junction", "unregulated", "no UK junction")),   # (libsumo 1.28 crashed on it: segfault)
])
def test_a_network_the_audit_cannot_name_or_judge_is_refused_naming_the_junction(nets, tmp_path, name, words):
    result = _sim(tmp_path, "--map", _fork(tmp_path) if name == "fork" else nets[name])
    assert result.exit_code == 2, result.output
    said = _one_line(result)
    assert all(w in said for w in words), said
    assert len(result.output.strip().splitlines()) == 1


ROUTES = """<routes>
    <vType id="van" vClass="delivery"/>
    <vType id="coach" vClass="bus"/>
    <route id="across" edges="left0A0 A0B0 B0right0"/>
    <vehicle id="first" type="van" depart="0" route="across"/>
    <vehicle id="bus.7" type="coach" depart="2.5"><route edges="bottom0A0 A0A1 A1top0"/></vehicle>
    <trip id="t" depart="4" from="right1B1" to="B1A1"/>
    <flow id="f" begin="1" end="10" number="2" from="top1B1" to="B1B0"/>
</routes>
"""


def _routes_spawned(db, run):
    with Store(db, read_only=True) as store:
        return sorted(e["body"]["type"] for e in store.events(run)
                      if e["kind"] == "entity.spawn" and e["src"].startswith("vehicle/"))


def test_routes_from_a_rou_xml_replace_the_drawn_demand(nets, tmp_path):
    # issue 39: there was no way to pass a .rou.xml
    (tmp_path / "my.rou.xml").write_text(ROUTES)
    result = _sim(tmp_path, "--map", nets["signals"], "--routes", tmp_path / "my.rou.xml")
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["simulation"]["vehicles"] == 5
    truth = json.loads((tmp_path / "own-1.truth.json").read_text())
    by_file = {u["routes_file_id"]: u for u in truth["road_users"].values() if "routes_file_id" in u}
    assert sorted(by_file) == ["bus.7", "f.0", "f.1", "first", "t"]
    assert by_file["first"]["route"] == ["left0A0", "A0B0", "B0right0"] and by_file["bus.7"]["type"] == "bus"
    assert by_file["t"]["route"][0] == "right1B1" and by_file["t"]["route"][-1] == "B1A1"
    assert _routes_spawned(tmp_path / "s.db", "own-1") == ["bus", "car", "car", "car", "car"]


def test_a_sumocfg_brings_its_net_and_routes_relative_to_itself(nets, tmp_path):
    # issue 39: `--map grid.sumocfg` answered "no bundled map"
    folder = tmp_path / "scenario"
    (folder / "net").mkdir(parents=True)
    (folder / "net" / "grid.net.xml").write_bytes(nets["signals"].read_bytes())
    (folder / "demand.rou.xml").write_text(ROUTES)
    (folder / "grid.sumocfg").write_text(
        '<configuration><input><net-file value="net/grid.net.xml"/><route-files value="demand.rou.xml"/></input>'
        '<time><begin value="0"/><end value="60"/></time></configuration>')
    result = _sim(tmp_path, "--map", folder / "grid.sumocfg")
    assert result.exit_code == 0, result.output
    assert json.loads(result.stdout)["simulation"]["vehicles"] == 5
    assert _run_start(tmp_path / "s.db", "own-1")["body"]["map"]["network"]["file"] == "grid.net.xml"


@pytest.mark.parametrize("make,words", [
    (lambda p, net: ("--map", p / "nowhere.sumocfg"), ("no such configuration file", "nowhere.sumocfg")),
    (lambda p, net: ("--map", "suburb"), ("no bundled map 'suburb'", ".net.xml", ".sumocfg")),
    (lambda p, net: ("--map", net, "--routes", _write(p / "bad.rou.xml", '<routes><vehicle id="v" depart="0">'
                                                      '<route edges="left0A0 nowhere"/></vehicle></routes>')),
     ("bad.rou.xml", "vehicle 'v'", "'nowhere'")),
    (lambda p, net: ("--map", net, "--routes", _write(p / "broken.rou.xml", "<routes><vehicle")),
     ("broken.rou.xml", "not")),
    (lambda p, net: ("--map", _write(p / "x.sumocfg", "<configuration><input/></configuration>")),
     ("x.sumocfg", "net-file")),
    (lambda p, net: ("--map", net, "--routes", _write(p / "stops.rou.xml", '<routes><vehicle id="v" depart="0">'
                                                      '<route edges="left0A0 A0B0"/><stop lane="A0B0_0" duration="5"/>'
                                                      '</vehicle></routes>')),
     ("stops.rou.xml", "<stop>")),
    (lambda p, net: ("--map", net, "--routes", _write(p / "truck.rou.xml", '<routes><vType id="t" vClass="truck"/>'
                                                      '</routes>')),
     ("truck.rou.xml", "'truck'")),
    (lambda p, net: ("--map", _write(p / "demand.rou.xml", ROUTES)), ("demand.rou.xml", "not a SUMO network")),
    (lambda p, net: ("--map", _write(p / "junk.net.xml", "hello")), ("junk.net.xml", "not a SUMO network")),
    (lambda p, net: ("--map", net, "--routes", _write(p / "flood.rou.xml", '<routes><flow id="f" period="1e-9" '
                                                      'from="left0A0" to="A0B0"/></routes>')),
     ("flood.rou.xml", "flow 'f'", "more than 100,000 vehicles")),
])
def test_mistakes_in_the_users_files_are_one_line_errors(nets, tmp_path, make, words):
    result = _sim(tmp_path, *make(tmp_path, nets["signals"]))
    assert result.exit_code == 2, result.output
    said = _one_line(result)
    assert all(w in said for w in words), said


def _write(path, text):
    path.write_text(text)
    return path


def test_the_routes_file_helper_parses_what_it_is_given():
    # guards the test's own routes text: it is the SUMO routes format
    root = ET.fromstring(ROUTES)
    assert [e.tag for e in root] == ["vType", "vType", "route", "vehicle", "vehicle", "trip", "flow"]
