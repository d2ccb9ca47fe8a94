"""End to end on networks a SUMO user makes (issue 39): simulated, stored, judged, and each act of the
ground truth lined up with the incidents by tests/helpers/sim_truth_table (its rows cite the law:
entering on red HC 176 / RTA 1988 s.36, over a Stop line without stopping HC 171 / TSRGD Sch 14 Pt 1
para 5(5)... as the table says). The stop lines' kinds come from SUMO's junction types, so a red
light, a Stop line and a Give Way line are judged under their own rules only if the map read them
right. A camera at every junction (a 360-degree cone over its arms) sees every act, so that an act
without an incident is a disagreement, not one nobody saw."""
from __future__ import annotations

import json

from reasoner.investigation import Investigation
from sim_replay.sim_config import Behaviour, SimConfig
from sim_replay.sim_events import T0
from sim_replay.simulation import Simulation
from sim_replay.sumo_net import read_network
from store import Store
from tests.helpers.sim_truth_table import compare
from tests.helpers.sumo_tools import netconvert, netgenerate

HABITS = Behaviour(red_runner=0.5, amber_runner=0.3, stop_roller=0.5, no_give_way=0.5, speeder=0.0)

NODES = """<nodes>
  <node id="w" x="-200" y="0" type="dead_end"/> <node id="e" x="400" y="0" type="dead_end"/>
  <node id="c1" x="0" y="0" type="priority_stop"/> <node id="c2" x="200" y="0" type="priority"/>
  <node id="s1" x="0" y="-200" type="dead_end"/> <node id="n2" x="200" y="200" type="dead_end"/>
</nodes>"""
ARMS = (("w", "c1", 2), ("c1", "c2", 2), ("c2", "e", 2), ("s1", "c1", 1), ("n2", "c2", 1))


def _edges() -> str:
    both = [(a, b, p) for a, b, p in ARMS] + [(b, a, p) for a, b, p in ARMS]
    return "<edges>" + "".join(f'<edge id="{a}_{b}" from="{a}" to="{b}" priority="{p}" numLanes="1" speed="13.41"/>'
                               for a, b, p in both) + "</edges>"


def _cameras(net, path):
    """A camera at each junction's centre that sees its whole neighbourhood."""
    network = read_network(net)
    path.write_text(json.dumps({"monitors": [
        {"id": f"m{j.id}", "junction": j.id, "x": j.x, "y": j.y, "heading_deg": 0.0, "range_m": 60.0,
         "fov_deg": 360.0} for j in network.junctions.values()]}))
    return path


def _judged(net, monitors, vehicles, duration_s):
    config = SimConfig(run="own", net=str(net), monitors=str(monitors), vehicles=vehicles, duration_s=duration_s,
                       seed=3, pedestrians=0, rate_hz=5.0, behaviour=HABITS)
    sim = Simulation(config)
    events = list(sim.events())
    with Store(monitors.parent / "gaps.db") as store:
        assert not store.append(events).rejected
        incidents = Investigation(store).incidents("own")
    return compare(sim.truth.to_json(), incidents, T0)


def _disagreements(lines):
    return [line.describe() for line in lines if not line.agrees and line.known is None]


def test_red_lights_on_a_netgenerate_signal_grid_are_judged_under_hc_176(tmp_path):
    net = netgenerate(tmp_path / "grid.net.xml", "--grid", "--grid.number", "2", "--grid.length", "150",
                      "--grid.attach-length", "100", "--default-junction-type", "traffic_light", "--lefthand")
    lines = _judged(net, _cameras(net, tmp_path / "m.json"), 16, 50.0)
    rows = {line.row.name for line in lines if line.row is not None}
    assert "crossed on red, no call" in rows, rows
    red = [line for line in lines if line.row is not None and line.row.name == "crossed on red, no call"]
    assert all(line.got == (("punishable", "HC 176"),) for line in red), [line.describe() for line in red]
    assert _disagreements(lines) == []


def test_stop_and_give_way_lines_of_netconvert_junction_types_are_judged_under_hc_171_and_172(tmp_path):
    (tmp_path / "t.nod.xml").write_text(NODES)
    (tmp_path / "t.edg.xml").write_text(_edges())
    net = netconvert(tmp_path / "t.net.xml", "--node-files", "t.nod.xml", "--edge-files", "t.edg.xml", "--lefthand")
    lines = _judged(net, _cameras(net, tmp_path / "m.json"), 24, 70.0)
    stop = [line for line in lines if line.row is not None and line.row.name == "over a Stop line without stopping"]
    assert stop and all(line.got == (("punishable", "HC 171"),) for line in stop), [line.describe() for line in stop]
    assert any(line.act and line.act["line"] == "give_way" for line in lines)
    assert _disagreements(lines) == []
